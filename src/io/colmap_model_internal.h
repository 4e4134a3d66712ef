// What the COLMAP model's readers and writers share: the checks of both forms and the TEXT
// form's reader and writer. Internal to io (colmap_model.h is the API).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/colmap_model.h"

namespace hdribr {

// A camera from a model file's fields (model by id, or by name when the id is -1); throws
// InputError naming `file` and `where` (a line or record) on an unknown model, a size or
// parameters it cannot hold.
Camera MakeColmapCamera(int id, int model_id_or_minus1, const std::string& model_name,
                        std::int64_t width, std::int64_t height, std::vector<double> params,
                        const std::filesystem::path& file, const std::string& where);
// Throws InputError unless the image's pose is finite and its quaternion a rotation.
void CheckColmapPose(const ColmapImage& image, const std::filesystem::path& file,
                     const std::string& where);
// Cross-references: image -> camera, point2D -> point3D, track -> image and point2D index.
void CheckColmapReferences(const ColmapModel& m, const std::filesystem::path& images_file,
                           const std::filesystem::path& points_file);

// A TEXT model; without `with_points`, points3D.txt is not read (no point is then defined).
ColmapModel ReadColmapText(const std::filesystem::path& dir, bool with_points);

// The three TEXT files' contents for a model (cameras.txt, images.txt, points3D.txt).
struct ColmapTextFiles {
  std::string cameras;
  std::string images;
  std::string points3d;
};
ColmapTextFiles SerializeColmapModelText(const ColmapModel& model);

}  // namespace hdribr
