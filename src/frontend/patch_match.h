// PatchMatch multi-view stereo on the CPU: per-pixel slanted planes (depth + normal) found by
// random initialisation, red-black checkerboard propagation and random refinement (Bleyer et al.
// 2011; Galliani et al. 2015, Gipuma; Xu & Tao 2019, ACMM), scored by bilaterally weighted NCC
// through plane-induced homographies with per-pixel view selection, coarse to fine over an image
// pyramid with the sources' coarser depth maps as geometric guidance (ACMM), then a pass with
// forward-backward reprojection error in the cost (Schönberger et al. 2016, COLMAP).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "frontend/dense_mvs.h"

namespace hdribr {

// The inputs of one photo's PatchMatch.
struct PatchMatchTask {
  std::vector<int> sources;             // indices into the maps of its source photos
  double depth_min = 0, depth_max = 0;  // camera-z range of the hypotheses
  std::vector<Eigen::Vector3d> seeds;   // sparse points in this photo's camera frame
};

// Computes depth, normal and score of every map with a task that has sources and a depth range
// (`maps[i].gray`, `camera` and `cam_from_world` must be set); other maps get empty depth.
// Pixels whose NCC is below options.patch_match.min_ncc, or whose window is flatter than
// min_texture, keep the half-size level's plane where it passed those tests (coarse_fill), else
// get depth 0. Rows run on options.threads threads; `progress(done, total)` is
// called after each photo at each pyramid level and in the geometric pass.
void PatchMatchDepthMaps(std::vector<DepthMap>& maps, const std::vector<PatchMatchTask>& tasks,
                         const DenseOptions& options,
                         const std::function<void(int, int)>& progress = {});

}  // namespace hdribr
