// A point cloud with optional per-point attributes (world coordinates).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace hdribr {

struct PointCloud {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;             // unit length; empty if absent
  std::vector<std::array<std::uint8_t, 3>> colors;  // sRGB 8-bit; empty if absent
  std::vector<float> radii;                         // splat radius, scene units; empty if absent

  size_t size() const { return positions.size(); }
  bool empty() const { return positions.empty(); }
  bool HasNormals() const { return !normals.empty(); }
  bool HasColors() const { return !colors.empty(); }
  bool HasRadii() const { return !radii.empty(); }
  // Attribute arrays are empty or have one entry per point, and every value is finite.
  bool IsConsistent() const;
};

// Axis-aligned bounding box.
struct Bounds {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(0);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(0);
  bool valid = false;

  void Extend(const Eigen::Vector3d& p);
  Eigen::Vector3d Center() const { return 0.5 * (min + max); }
  Eigen::Vector3d Extent() const { return max - min; }
  double Diagonal() const { return valid ? (max - min).norm() : 0.0; }
};

}  // namespace hdribr
