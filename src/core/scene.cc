#include "core/scene.h"

#include <algorithm>

namespace hdribr {

int Scene::FindPhoto(const std::string& name) const {
  for (size_t i = 0; i < photos.size(); ++i) {
    if (photos[i].name == name) return static_cast<int>(i);
  }
  return -1;
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
