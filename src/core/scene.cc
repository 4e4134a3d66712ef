#include "core/scene.h"

#include <algorithm>
#include <vector>

namespace hdribr {

int Scene::FindPhoto(const std::string& name) const {
  for (size_t i = 0; i < photos.size(); ++i) {
    if (photos[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

double Scene::RelativeExposureOf(const Photo& photo) const {
  if (photo.calibrated_exposure) return *photo.calibrated_exposure;
  if (photo.series_id >= 0 && static_cast<size_t>(photo.series_id) < series.size()) {
    return series[static_cast<size_t>(photo.series_id)].relative_exposure;
  }
  return photo.exposure.Relative();
}

double Scene::ExposureGain() const {
  std::vector<double> gains;
  for (const Photo& p : photos) {
    if (p.exposure.time_s) gains.push_back(p.exposure.Relative() / *p.exposure.time_s);
  }
  if (gains.empty()) return 1.0;
  std::nth_element(gains.begin(), gains.begin() + static_cast<std::ptrdiff_t>(gains.size() / 2),
                   gains.end());
  return gains[gains.size() / 2];
}

double Scene::MedianRelativeExposure() const {
  std::vector<double> exposures;
  for (const Photo& p : photos) exposures.push_back(RelativeExposureOf(p));
  if (exposures.empty()) return 1.0;
  std::nth_element(exposures.begin(),
                   exposures.begin() + static_cast<std::ptrdiff_t>(exposures.size() / 2),
                   exposures.end());
  return exposures[exposures.size() / 2];
}

int Scene::NearestPhoto(const Rigid3d& cam_from_world) const {
  std::vector<int> all(photos.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  return NearestPhoto(cam_from_world, all);
}

int Scene::NearestPhoto(const Rigid3d& cam_from_world, const std::vector<int>& candidates) const {
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const Eigen::Vector3d c = world_from_cam.translation;
  const Eigen::Vector3d d = world_from_cam.rotation * Eigen::Vector3d::UnitZ();
  int best = -1;
  double best_score = 0;
  for (int i : candidates) {
    const Photo& photo = photos[static_cast<size_t>(i)];
    const double score = (photo.Center() - c).norm() / std::max(scene_scale, 1e-12) +
                         (1.0 - d.dot(photo.ViewDirection()));
    if (best < 0 || score < best_score) {
      best = i;
      best_score = score;
    }
  }
  return best;
}

void Scene::UpdateDerived() {
  point_bounds = Bounds();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : points.positions) {
    const Eigen::Vector3d d = p.cast<double>();
    point_bounds.Extend(d);
    sum += d;
  }
  if (!points.empty()) {
    centroid = sum / static_cast<double>(points.size());
  } else if (!photos.empty()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& ph : photos) c += ph.Center();
    centroid = c / static_cast<double>(photos.size());
  } else {
    centroid.setZero();
  }
  std::vector<double> d;
  d.reserve(photos.size());
  for (const auto& ph : photos) d.push_back((ph.Center() - centroid).norm());
  scene_scale = 1.0;
  if (!d.empty()) {
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    const double m = d[d.size() / 2];
    if (m > 0 && std::isfinite(m)) scene_scale = m;
  } else if (point_bounds.valid && point_bounds.Diagonal() > 0) {
    scene_scale = point_bounds.Diagonal();
  }
}

}  // namespace hdribr
