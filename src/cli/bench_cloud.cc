#include "cli/bench_cloud.h"

#include <cmath>
#include <random>

namespace hdribr::cli {

BenchCloudSpec DepthBenchScene() {
  BenchCloudSpec s;
  s.wall = true;
  s.spheres = {{{-1.0, -0.5, 0.0}, 0.5}, {{0.6, -0.4, 0.5}, 0.4}, {{0.0, -0.8, -1.0}, 0.8}};
  return s;
}

BenchCloudSpec DomeBenchScene() {
  BenchCloudSpec s;
  s.spheres = {{{0.0, 0.0, 0.0}, 1.0, true}};
  return s;
}

PointCloud MakeBenchCloud(size_t n, const BenchCloudSpec& spec) {
  const double ground = 36.0, wall = spec.wall ? 18.0 : 0.0;
  double area = ground + wall;
  for (const auto& s : spec.spheres) area += (s.upper_half ? 2 : 4) * M_PI * s.radius * s.radius;
  const float radius = static_cast<float>(1.25 * std::sqrt(area / static_cast<double>(n)));
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  PointCloud pc;
  pc.positions.reserve(n);
  pc.normals.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const double pick = u(rng) * area;
    Eigen::Vector3d p, nrm;
    if (pick < ground || spec.spheres.empty()) {
      p = {6 * u(rng) - 3, 0.0, 6 * u(rng) - 3};
      nrm = {0, -1, 0};
    } else if (pick < ground + wall) {
      p = {6 * u(rng) - 3, -3 * u(rng), 3.0};
      nrm = {0, 0, -1};
    } else {
      const BenchSphere& s = spec.spheres[i % spec.spheres.size()];
      Eigen::Vector3d d;
      for (int k = 0; k < 3; ++k) d[k] = g(rng);
      if (s.upper_half) d.y() = -std::abs(d.y());
      d.normalize();
      p = s.centre + s.radius * d;
      nrm = d;
    }
    pc.positions.push_back(p.cast<float>());
    pc.normals.push_back(nrm.cast<float>());
  }
  pc.radii.assign(n, radius);
  return pc;
}

}  // namespace hdribr::cli
