#include "core/point_cloud.h"

namespace hdribr {

bool PointCloud::IsConsistent() const {
  const size_t n = positions.size();
  if (!normals.empty() && normals.size() != n) return false;
  if (!colors.empty() && colors.size() != n) return false;
  if (!radii.empty() && radii.size() != n) return false;
  for (const auto& p : positions) {
    if (!p.allFinite()) return false;
  }
  for (const auto& v : normals) {
    if (!v.allFinite()) return false;
  }
  for (float r : radii) {
    if (!std::isfinite(r) || r < 0) return false;
  }
  return true;
}

void Bounds::Extend(const Eigen::Vector3d& p) {
  if (!valid) {
    min = max = p;
    valid = true;
  } else {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
}

}  // namespace hdribr
