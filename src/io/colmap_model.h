// COLMAP sparse models (cameras, images, points3D) in TEXT and BINARY form.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"

namespace hdribr {

struct ColmapPoint2D {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();  // pixels, COLMAP convention
  std::int64_t point3d_id = -1;                  // -1 when unmatched
};

struct ColmapImage {
  int id = -1;
  int camera_id = -1;
  std::string name;
  Rigid3d cam_from_world;
  std::vector<ColmapPoint2D> points2d;
};

struct ColmapTrackElement {
  int image_id = -1;
  int point2d_idx = -1;
};

struct ColmapPoint3D {
  std::int64_t id = -1;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  std::array<std::uint8_t, 3> color = {0, 0, 0};
  double error = -1;
  std::vector<ColmapTrackElement> track;
};

struct ColmapModel {
  std::map<int, Camera> cameras;
  std::map<int, ColmapImage> images;  // ids need not be contiguous
  std::map<std::int64_t, ColmapPoint3D> points3d;
};

enum class ColmapFormat { kText, kBinary };

// Reads a model folder; prefers BINARY when both .bin and .txt files are present. Throws
// InputError naming the file and the problem (missing, truncated, corrupt, NaN pose,
// non-unit quaternion, unknown camera model, dangling ids).
ColmapModel ReadColmapModel(const std::filesystem::path& dir);
ColmapModel ReadColmapModelText(const std::filesystem::path& dir);
// A model folder whose points3D file may be absent (a set of ground-truth cameras: cameras and
// images only, TEXT then); with points3D, ReadColmapModel.
ColmapModel ReadColmapCameras(const std::filesystem::path& dir);
ColmapModel ReadColmapModelBinary(const std::filesystem::path& dir);
// Parses binary buffers (the three files' bytes); `dir` only names files in errors.
ColmapModel ParseColmapModelBinary(const std::string& cameras_bin, const std::string& images_bin,
                                   const std::string& points3d_bin,
                                   const std::filesystem::path& dir);

// The three BINARY files' bytes for a model (cameras.bin, images.bin, points3D.bin).
struct ColmapBinaryFiles {
  std::string cameras;
  std::string images;
  std::string points3d;
};
ColmapBinaryFiles SerializeColmapModelBinary(const ColmapModel& model);

// Writes cameras/images/points3D (.txt or .bin) into dir (created if needed), each atomically.
void WriteColmapModel(const ColmapModel& model, const std::filesystem::path& dir,
                      ColmapFormat format);

// True when dir holds a complete TEXT or BINARY model.
bool IsColmapModelDir(const std::filesystem::path& dir);

}  // namespace hdribr
