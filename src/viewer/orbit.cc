#include "viewer/orbit.h"

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "viewer/camera_controller.h"

namespace hdribr::viewer {

CameraPath OrbitPath(const Scene& scene, int frames, double fps, int width, int height) {
  if (scene.photos.empty()) throw UsageError("orbit: the scene has no photos");
  if (frames < 1) throw UsageError("orbit: the number of frames must be >= 1");
  const Eigen::Vector3d up = SceneUp(scene);
  const Eigen::Vector3d target = scene.centroid;
  Eigen::Vector3d mean_centre = Eigen::Vector3d::Zero();
  for (const Photo& p : scene.photos) mean_centre += p.Center();
  mean_centre /= static_cast<double>(scene.photos.size());
  // Circle through the mean centre: its height along up and its radius about the target.
  const Eigen::Vector3d offset = mean_centre - target;
  const double height_along_up = offset.dot(up);
  Eigen::Vector3d radial = offset - height_along_up * up;
  double radius = radial.norm();
  if (radius < 1e-9) {
    radial = up.unitOrthogonal();
    radius = scene.scene_scale > 0 ? scene.scene_scale : 1.0;
  }
  radial.normalize();
  const Eigen::Vector3d tangent = up.cross(radial);
  // A +-30 degree arc around the captured side keeps the orbit where the photos see the scene.
  const double arc = std::numbers::pi / 6;
  const Photo& first = scene.photos.front();
  Camera camera = scene.cameras.at(first.camera_id);
  if (width > 0 && height > 0) camera = camera.Scaled(width, height);
  CameraPath path;
  path.fps = fps;
  for (int i = 0; i < frames; ++i) {
    const double u = frames == 1 ? 0.0 : static_cast<double>(i) / frames;
    const double a = arc * std::sin(2 * std::numbers::pi * u);
    const Eigen::Vector3d eye =
        target + height_along_up * up + radius * (std::cos(a) * radial + std::sin(a) * tangent);
    View v;
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%04d", i);
    v.name = name;
    v.camera = camera;
    v.cam_from_world = LookAt(eye, target, up);
    path.times_s.push_back(i / fps);
    path.keyframes.push_back(v);
  }
  return path;
}

}  // namespace hdribr::viewer
