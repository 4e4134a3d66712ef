// Dense ground-truth points sampled on the surfaces seen by rendered views.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/camera.h"
#include "core/point_cloud.h"
#include "core/rigid3.h"
#include "synth/ray_tracer.h"

namespace hdribr::synth {

// Back-projects every `stride`-th pixel centre of each view's depth map (exact ray hits) and
// keeps the first point per voxel of `voxel` scene units. The radius of a point is made as for
// a reconstructed cloud (frontend EstimateRadii): the mean distance to its `kRadiusNeighbors`
// nearest neighbours, clamped to [1/4, 4] x the median, so splats follow the local spacing
// (a radius from one view's pixel footprint overhangs silhouettes seen from other views).
class PointSampler {
 public:
  PointSampler(double voxel, int stride);

  // Adds the samples of one view; `colour_scale` maps radiance to [0, 1] display values (then
  // sRGB-like gamma 1/2.2 for the 8-bit colours).
  void AddView(const RenderedView& view, const Camera& camera, const Rigid3d& cam_from_world,
               double colour_scale);
  // The samples so far, radii computed on the first call after AddView.
  const PointCloud& cloud();

  static constexpr int kRadiusNeighbors = 6;  // as frontend AttributeOptions::radius_neighbors

 private:
  void EstimateRadii();

  double voxel_;
  int stride_;
  bool radii_stale_ = false;
  PointCloud cloud_;
  std::unordered_map<std::uint64_t, std::uint32_t> occupied_;
};

}  // namespace hdribr::synth
