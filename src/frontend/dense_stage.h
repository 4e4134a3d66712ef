// The reconstruction's dense stage: the dense cloud (our PatchMatch or plane sweep, COLMAP's
// PatchMatch, or the sparse points), its clean-up, normals and radii into points.ply.
#pragma once

#include <string>

#include "frontend/colmap_stages.h"
#include "frontend/dense_mvs.h"

namespace hdribr {

// The dense method that runs: `auto` is COLMAP's PatchMatch where it has CUDA, else ours.
std::string DenseMode(const StageContext& ctx);

// Throws OptionError naming the first field of the dense options (dense_options.*) that the
// depth maps or the fusion cannot be computed with.
void CheckDenseOptions(const DenseOptions& options);

// Runs the dense stage on workspace/sparse and writes workspace/points.ply; its times and
// point count into `report`. Throws std::runtime_error when too few points remain.
void RunDense(StageContext& ctx, StageProgress& progress, ReconstructReport& report);

}  // namespace hdribr
