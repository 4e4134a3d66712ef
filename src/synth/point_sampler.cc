#include "synth/point_sampler.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace hdribr::synth {

PointSampler::PointSampler(double voxel, int stride) : voxel_(voxel), stride_(stride) {
  HDRIBR_CHECK(voxel > 0 && stride > 0);
}

void PointSampler::AddView(const RenderedView& view, const Camera& camera,
                           const Rigid3d& cam_from_world, double colour_scale) {
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const double f = 0.5 * (camera.fx() + camera.fy());
  for (int y = stride_ / 2; y < view.depth.rows; y += stride_) {
    for (int x = stride_ / 2; x < view.depth.cols; x += stride_) {
      const float z = view.depth.at<float>(y, x);
      if (z <= 0) continue;
      const Eigen::Vector3d p_cam = camera.CamFromPixel({x + 0.5, y + 0.5}) * double(z);
      const Eigen::Vector3d p = world_from_cam * p_cam;
      const auto key = [&](double v) {
        return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / voxel_)) +
                                          (1 << 20)) &
               0x1FFFFF;
      };
      const std::uint64_t k = key(p.x()) | key(p.y()) << 21 | key(p.z()) << 42;
      if (!occupied_.emplace(k, static_cast<std::uint32_t>(cloud_.size())).second) continue;

      const cv::Vec3f n = view.normal.at<cv::Vec3f>(y, x);
      const Eigen::Vector3d normal(n[0], n[1], n[2]);
      const cv::Vec3f l = view.radiance.at<cv::Vec3f>(y, x);
      auto to8 = [&](float v) {
        const double d = std::pow(std::clamp(v * colour_scale, 0.0, 1.0), 1.0 / 2.2);
        return static_cast<std::uint8_t>(std::lround(255.0 * d));
      };
      cloud_.positions.emplace_back(p.cast<float>());
      cloud_.normals.emplace_back(normal.cast<float>());
      cloud_.colors.push_back({to8(l[2]), to8(l[1]), to8(l[0])});
      // Fallback for a point without neighbours: its pixel footprint times the stride.
      cloud_.radii.push_back(static_cast<float>(std::max(voxel_, stride_ * z / f)));
      radii_stale_ = true;
    }
  }
}

const PointCloud& PointSampler::cloud() {
  if (radii_stale_) EstimateRadii();
  radii_stale_ = false;
  return cloud_;
}

void PointSampler::EstimateRadii() {
  // Exact k nearest neighbours on a uniform grid of cells of 2 voxels: rings of cells around
  // the query's cell are searched outwards until the k-th distance is below the ring's
  // distance (points beyond ring r are farther than r cells), at most kMaxRing rings.
  const size_t n = cloud_.size();
  if (n < 2) return;
  const double cell = 2.0 * voxel_;
  constexpr int kMaxRing = 8;
  const auto cell_of = [&](const Eigen::Vector3f& p) {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / cell)),
                           static_cast<int>(std::floor(p.y() / cell)),
                           static_cast<int>(std::floor(p.z() / cell)));
  };
  const auto key = [](const Eigen::Vector3i& c) {
    const auto k = [](int v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1FFFFF; };
    return k(c.x()) | k(c.y()) << 21 | k(c.z()) << 42;
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  for (size_t i = 0; i < n; ++i) {
    grid[key(cell_of(cloud_.positions[i]))].push_back(static_cast<std::uint32_t>(i));
  }
  std::vector<float> radii(n);
  std::vector<double> best;  // sorted distances of the k nearest so far
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f& p = cloud_.positions[i];
    const Eigen::Vector3i c = cell_of(p);
    best.clear();
    for (int r = 0; r <= kMaxRing; ++r) {
      for (int dz = -r; dz <= r; ++dz) {
        for (int dy = -r; dy <= r; ++dy) {
          for (int dx = -r; dx <= r; ++dx) {
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;
            const auto it = grid.find(key(c + Eigen::Vector3i(dx, dy, dz)));
            if (it == grid.end()) continue;
            for (std::uint32_t j : it->second) {
              if (j == i) continue;
              const double d = (cloud_.positions[j] - p).cast<double>().norm();
              if (best.size() == kRadiusNeighbors && d >= best.back()) continue;
              best.insert(std::upper_bound(best.begin(), best.end(), d), d);
              if (best.size() > kRadiusNeighbors) best.pop_back();
            }
          }
        }
      }
      if (best.size() == kRadiusNeighbors && best.back() <= r * cell) break;
    }
    double sum = 0;
    for (double d : best) sum += d;
    radii[i] = best.empty() ? cloud_.radii[i] : static_cast<float>(sum / best.size());
  }
  std::vector<float> sorted = radii;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(n / 2), sorted.end());
  const float median = sorted[n / 2];
  for (size_t i = 0; i < n; ++i) {
    cloud_.radii[i] = std::clamp(radii[i], 0.25f * median, 4.0f * median);
  }
}

}  // namespace hdribr::synth
