// Generated point clouds of the benchmarks (`hdribr bench depth`, `hdribr bench render`).
#pragma once

#include <cstddef>
#include <vector>

#include "core/point_cloud.h"

namespace hdribr::cli {

struct BenchSphere {
  Eigen::Vector3d centre;
  double radius = 1.0;
  bool upper_half = false;  // only the half above the ground (y <= centre, y down)
};

// Surfaces of a generated scene: always a 6 x 6 ground (y = 0, facing -y, y down), optionally
// a 6 x 3 back wall (z = 3, facing -z), and spheres.
struct BenchCloudSpec {
  bool wall = false;
  std::vector<BenchSphere> spheres;
};

// Ground, back wall and three spheres (bench depth).
BenchCloudSpec DepthBenchScene();
// Ground and a half dome of radius 1 at the origin (bench render).
BenchCloudSpec DomeBenchScene();

// n points uniformly at random (fixed seed) over the ground and wall by area, the rest on the
// spheres in turn, with normals and radii 1.25 x the mean point spacing.
PointCloud MakeBenchCloud(size_t n, const BenchCloudSpec& spec);

}  // namespace hdribr::cli
