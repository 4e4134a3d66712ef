// A calibrated photograph and its exposure settings.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>

#include "core/rigid3.h"

namespace hdribr {

// Exposure settings read from EXIF (or given by the user); absent fields count as 1.
struct Exposure {
  std::optional<double> time_s;    // exposure time in seconds
  std::optional<double> iso;       // ISO speed
  std::optional<double> f_number;  // aperture f-number
  std::optional<double> focal_mm;  // focal length in millimetres (informative)

  // time x ISO / 100 / f_number^2, with 1 for each missing field.
  double Relative() const;
  // True when time, ISO and f-number are all known.
  bool Complete() const { return time_s && iso && f_number; }
};

struct Photo {
  int id = -1;                       // COLMAP image id
  std::string name;                  // COLMAP image name (relative path inside images/)
  std::filesystem::path image_path;  // absolute or workspace-relative path of the pixels
  int camera_id = -1;
  Rigid3d cam_from_world;
  Exposure exposure;
  int series_id = -1;  // index into Scene::series, -1 until grouped
  // Exposure refined by the radiometric calibration (calib/exposures.json), in the units of
  // Exposure::Relative(); absent before `hdribr calibrate`.
  std::optional<double> calibrated_exposure;

  // Camera centre in world coordinates.
  Eigen::Vector3d Center() const { return cam_from_world.Inverse().translation; }
  // Viewing direction (camera +z) in world coordinates.
  Eigen::Vector3d ViewDirection() const {
    return cam_from_world.rotation.inverse() * Eigen::Vector3d::UnitZ();
  }
};

}  // namespace hdribr
