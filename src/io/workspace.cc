#include "io/workspace.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <system_error>

#include "core/error.h"
#include "io/colmap_model.h"
#include "io/exif.h"
#include "io/image.h"
#include "io/ply.h"
#include "io/radiometric_calibration.h"
#include "io/series_json.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// Pinhole copy of a camera whose distortion is zero; refuses distorted models.
Camera UsableCamera(const Camera& camera, const fs::path& sparse_dir) {
  if (camera.IsPinhole()) return camera;
  if (camera.HasZeroDistortion()) {
    return Camera::Pinhole(camera.id, camera.width, camera.height, camera.fx(), camera.fy(),
                           camera.cx(), camera.cy());
  }
  throw InputError(sparse_dir, "camera " + std::to_string(camera.id) +
                                   " uses the distorted model " + CameraModelName(camera.model) +
                                   "; run `colmap image_undistorter --output_type COLMAP` and "
                                   "load its output folder");
}

PointCloud PointsFromModel(const ColmapModel& model) {
  PointCloud cloud;
  cloud.positions.reserve(model.points3d.size());
  cloud.colors.reserve(model.points3d.size());
  for (const auto& [id, p] : model.points3d) {
    cloud.positions.push_back(p.xyz.cast<float>());
    cloud.colors.push_back(p.color);
  }
  return cloud;
}

}  // namespace

WorkspaceLayout DetectWorkspace(const fs::path& root) {
  std::error_code ec;
  if (!fs::is_directory(root, ec)) {
    throw InputError(root, fs::exists(root, ec) ? "not a folder" : "no such workspace folder");
  }
  WorkspaceLayout layout;
  layout.root = root;
  if (IsColmapModelDir(root / "sparse")) {
    layout.sparse_dir = root / "sparse";
  } else if (IsColmapModelDir(root / "sparse" / "0")) {
    layout.sparse_dir = root / "sparse" / "0";
  } else if (IsColmapModelDir(root)) {
    layout.sparse_dir = root;
  } else {
    throw InputError(
        root,
        "no COLMAP model found (expected sparse/, sparse/0/ or cameras/images/points3D "
        "files in the folder)");
  }
  if (fs::is_directory(root / "images", ec)) {
    layout.images_dir = root / "images";
  } else if (layout.sparse_dir == root && fs::is_directory(root.parent_path() / "images", ec)) {
    layout.images_dir = root.parent_path() / "images";
  } else {
    layout.images_dir = root / "images";  // reported as missing photos by ValidateScene
  }
  if (IsFile(root / "points.ply")) {
    layout.points_ply = root / "points.ply";
    layout.kind = "hdribr";
  } else if (IsFile(root / "fused.ply")) {
    layout.points_ply = root / "fused.ply";
    layout.kind = "colmap-dense";
  } else {
    layout.kind = "colmap-sparse";
  }
  if (IsFile(root / "series.json")) {
    layout.series_json = root / "series.json";
    layout.kind = "hdribr";
  }
  return layout;
}

void CheckOutsideInputs(const fs::path& root, const fs::path& out) {
  if (out.empty()) return;
  const WorkspaceLayout layout = DetectWorkspace(root);
  std::vector<fs::path> inputs = {layout.images_dir};
  if (layout.sparse_dir != layout.root) inputs.push_back(layout.sparse_dir);
  std::error_code ec;
  const fs::path target = fs::weakly_canonical(fs::absolute(out, ec), ec);
  if (ec || target.empty()) return;
  for (const fs::path& input : inputs) {
    const fs::path folder = fs::weakly_canonical(fs::absolute(input, ec), ec);
    if (ec || folder.empty()) continue;
    const auto end =
        std::mismatch(folder.begin(), folder.end(), target.begin(), target.end()).first;
    if (end == folder.end()) {
      throw UsageError(out.string() + ": inside the workspace's input folder " + input.string() +
                       ", where it would be read as input; write it elsewhere");
    }
  }
}

Scene LoadWorkspace(const fs::path& root, const LoadOptions& options) {
  const WorkspaceLayout layout = DetectWorkspace(root);
  const ColmapModel model = ReadColmapModel(layout.sparse_dir);

  Scene scene;
  scene.workspace = root;
  for (const auto& [id, camera] : model.cameras) {
    scene.cameras[id] = UsableCamera(camera, layout.sparse_dir);
  }
  for (const auto& [id, image] : model.images) {  // std::map: ascending image id
    Photo photo;
    photo.id = id;
    photo.name = image.name;
    photo.image_path = layout.images_dir / image.name;
    photo.camera_id = image.camera_id;
    photo.cam_from_world = image.cam_from_world;
    scene.photos.push_back(std::move(photo));
  }

  if (options.read_exif) {
    int incomplete = 0;
    std::string example;
    for (auto& photo : scene.photos) {
      if (!IsFile(photo.image_path)) continue;  // reported by ValidateScene
      try {
        photo.exposure = ReadExif(photo.image_path).exposure;
      } catch (const InputError& e) {
        spdlog::warn("{}", e.what());
      }
      if (!photo.exposure.Complete()) {
        ++incomplete;
        if (example.empty()) example = photo.name;
      }
    }
    if (incomplete > 0 && layout.series_json.empty()) {
      spdlog::warn(
          "{} of {} photos lack EXIF exposure time, ISO or f-number (e.g. {}); missing fields "
          "count as 1 (time 1 s, ISO 100, f/1). Give them in series.json if they matter.",
          incomplete, scene.photos.size(), example);
    }
  }

  if (!layout.series_json.empty()) {
    scene.series = ReadSeriesJson(layout.series_json, scene.photos);
  } else {
    scene.series = GroupByExposure(scene.photos);
  }

  const fs::path calibration = root / kCalibFolder / kCalibExposures;
  if (IsFile(calibration)) {
    const RadiometricCalibration c = ReadRadiometricCalibration(calibration);
    for (Photo& photo : scene.photos) {
      const auto it = c.photos.find(photo.name);
      if (it != c.photos.end()) photo.calibrated_exposure = it->second.relative;
    }
  }

  if (!layout.points_ply.empty()) {
    scene.points = ReadPly(layout.points_ply);
  } else {
    scene.points = PointsFromModel(model);
  }
  scene.UpdateDerived();
  return scene;
}

std::vector<std::string> ValidateScene(const Scene& scene) {
  std::vector<std::string> problems;
  for (const auto& photo : scene.photos) {
    const std::string where = photo.image_path.string();
    if (!scene.cameras.count(photo.camera_id)) {
      problems.push_back(photo.name + ": refers to camera " + std::to_string(photo.camera_id) +
                         ", which the model does not have");
      continue;
    }
    if (!photo.cam_from_world.translation.allFinite() ||
        !IsValidRotation(photo.cam_from_world.rotation)) {
      problems.push_back(photo.name + ": pose is not finite or not a rotation");
    }
    if (!IsFile(photo.image_path)) {
      problems.push_back(where + ": photo file is missing");
      continue;
    }
    try {
      const cv::Size size = ReadImageSize(photo.image_path);
      const Camera& cam = scene.CameraOf(photo);
      if (!cam.FitsImage(size.width, size.height)) {
        problems.push_back(where + ": image is " + std::to_string(size.width) + "x" +
                           std::to_string(size.height) + ", not the shape of camera " +
                           std::to_string(cam.id) + " (" + std::to_string(cam.width) + "x" +
                           std::to_string(cam.height) + ")");
      }
    } catch (const InputError& e) {
      problems.push_back(e.what());
    }
  }
  if (scene.photos.empty()) problems.push_back(scene.workspace.string() + ": no photos in model");
  if (scene.points.empty()) problems.push_back(scene.workspace.string() + ": no points");
  if (!scene.points.IsConsistent()) {
    problems.push_back(scene.workspace.string() +
                       ": point attributes are inconsistent or not finite");
  }
  return problems;
}

}  // namespace hdribr
