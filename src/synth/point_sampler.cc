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
  const Eigen::Vector3d centre = world_from_cam.translation;
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
      const Eigen::Vector3d to_cam = (centre - p).normalized();
      const double cos_view = std::max(0.25, std::abs(normal.dot(to_cam)));
      const double footprint = stride_ * z / f / cos_view;
      const cv::Vec3f l = view.radiance.at<cv::Vec3f>(y, x);
      auto to8 = [&](float v) {
        const double d = std::pow(std::clamp(v * colour_scale, 0.0, 1.0), 1.0 / 2.2);
        return static_cast<std::uint8_t>(std::lround(255.0 * d));
      };
      cloud_.positions.emplace_back(p.cast<float>());
      cloud_.normals.emplace_back(normal.cast<float>());
      cloud_.colors.push_back({to8(l[2]), to8(l[1]), to8(l[0])});
      cloud_.radii.push_back(static_cast<float>(std::max(voxel_, 0.75 * footprint)));
    }
  }
}

}  // namespace hdribr::synth
