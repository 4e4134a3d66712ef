#include <cmath>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "io/colmap_model_internal.h"

namespace hdribr {
namespace fs = std::filesystem;

Camera MakeColmapCamera(int id, int model_id_or_minus1, const std::string& model_name,
                        std::int64_t width, std::int64_t height, std::vector<double> params,
                        const fs::path& file, const std::string& where) {
  Camera cam;
  cam.id = id;
  try {
    cam.model = model_id_or_minus1 >= 0 ? CameraModelFromId(model_id_or_minus1)
                                        : CameraModelFromName(model_name);
  } catch (const std::invalid_argument&) {
    throw InputError(file, where + "unknown camera model " +
                               (model_id_or_minus1 >= 0 ? std::to_string(model_id_or_minus1)
                                                        : "'" + model_name + "'"));
  }
  if (width <= 0 || height <= 0 || width > 1'000'000 || height > 1'000'000) {
    throw InputError(file, where + "camera " + std::to_string(id) + " has an invalid size " +
                               std::to_string(width) + "x" + std::to_string(height));
  }
  cam.width = static_cast<int>(width);
  cam.height = static_cast<int>(height);
  if (static_cast<int>(params.size()) != CameraModelNumParams(cam.model)) {
    throw InputError(file, where + "camera " + std::to_string(id) + " (" +
                               CameraModelName(cam.model) + ") needs " +
                               std::to_string(CameraModelNumParams(cam.model)) +
                               " parameters, got " + std::to_string(params.size()));
  }
  for (double v : params) {
    if (!std::isfinite(v)) {
      throw InputError(file,
                       where + "camera " + std::to_string(id) + " has a non-finite parameter");
    }
  }
  cam.params = std::move(params);
  if (!(cam.fx() > 0) || !(cam.fy() > 0)) {
    throw InputError(file, where + "camera " + std::to_string(id) + " has a focal length <= 0 (" +
                               std::to_string(cam.fx()) + ", " + std::to_string(cam.fy()) + " px)");
  }
  return cam;
}

void CheckColmapPose(const ColmapImage& image, const fs::path& file, const std::string& where) {
  const Eigen::Quaterniond& q = image.cam_from_world.rotation;
  if (!q.coeffs().allFinite() || !image.cam_from_world.translation.allFinite()) {
    throw InputError(file, where + "image " + std::to_string(image.id) + " (" + image.name +
                               ") has a non-finite pose");
  }
  if (!IsValidRotation(q)) {
    throw InputError(file, where + "image " + std::to_string(image.id) + " (" + image.name +
                               ") has a quaternion of norm " + std::to_string(q.norm()) +
                               ", not a rotation");
  }
}

void CheckColmapReferences(const ColmapModel& m, const fs::path& images_file,
                           const fs::path& points_file) {
  for (const auto& [id, image] : m.images) {
    if (!m.cameras.count(image.camera_id)) {
      throw InputError(images_file, "image " + std::to_string(id) + " (" + image.name +
                                        ") refers to camera " + std::to_string(image.camera_id) +
                                        ", which cameras does not define");
    }
    for (const auto& p : image.points2d) {
      if (p.point3d_id != -1 && !m.points3d.count(p.point3d_id)) {
        throw InputError(images_file, "image " + std::to_string(id) + " refers to 3D point " +
                                          std::to_string(p.point3d_id) +
                                          ", which points3D does not define");
      }
    }
  }
  for (const auto& [id, point] : m.points3d) {
    if (!point.xyz.allFinite()) {
      throw InputError(points_file, "point " + std::to_string(id) + " is not finite");
    }
    for (const auto& t : point.track) {
      auto it = m.images.find(t.image_id);
      if (it == m.images.end()) {
        throw InputError(points_file, "point " + std::to_string(id) + " refers to image " +
                                          std::to_string(t.image_id) +
                                          ", which images does not define");
      }
      if (t.point2d_idx < 0 || t.point2d_idx >= static_cast<int>(it->second.points2d.size())) {
        throw InputError(points_file, "point " + std::to_string(id) + " refers to 2D point " +
                                          std::to_string(t.point2d_idx) + " of image " +
                                          std::to_string(t.image_id) + ", which has only " +
                                          std::to_string(it->second.points2d.size()));
      }
    }
  }
}

}  // namespace hdribr
