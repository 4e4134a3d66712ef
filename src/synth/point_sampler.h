// Dense ground-truth points sampled on the surfaces seen by rendered views.
#pragma once

#include <cstdint>
#include <unordered_map>

#include "core/camera.h"
#include "core/point_cloud.h"
#include "core/rigid3.h"
#include "synth/ray_tracer.h"

namespace hdribr::synth {

// Back-projects every `stride`-th pixel centre of each view's depth map (exact ray hits) and
// keeps the first point per voxel of `voxel` scene units. The radius of a point is its pixel
// footprint times the stride, stretched by 1 / |cos| of the viewing angle (at most 4x), and at
// least `voxel`: neighbouring splats overlap.
class PointSampler {
 public:
  PointSampler(double voxel, int stride);

  // Adds the samples of one view; `colour_scale` maps radiance to [0, 1] display values (then
  // sRGB-like gamma 1/2.2 for the 8-bit colours).
  void AddView(const RenderedView& view, const Camera& camera, const Rigid3d& cam_from_world,
               double colour_scale);
  const PointCloud& cloud() const { return cloud_; }

 private:
  double voxel_;
  int stride_;
  PointCloud cloud_;
  std::unordered_map<std::uint64_t, std::uint32_t> occupied_;
};

}  // namespace hdribr::synth
