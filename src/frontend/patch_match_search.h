// The PatchMatch search at one pyramid level (frontend/patch_match.h): random and seeded
// initialisation, upsampling of the coarser level's planes, and red-black iterations of
// propagation and random refinement.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "frontend/patch_match_cost.h"

namespace hdribr::patch_match {

// Per-pixel hypotheses and their costs.
struct State {
  int w = 0, h = 0;
  std::vector<float> depth, cost, ncc;
  std::vector<Vec3> normal;
  void Resize(int width, int height);
};

// Random hypotheses, uniform in inverse depth, with fronto-parallel depth seeds (`seeds`: points
// in the reference camera frame) over `radius` pixels around their projections.
void Initialise(const Level& lv, State& st, const std::vector<Eigen::Vector3d>& seeds, int radius,
                int photo);

// The parent of pixel (x, y) at the next coarser level (`parent`: its index in `coarse`) and the
// depth at which the parent's plane meets the ray of (x, y) (`k_inv`: this level's intrinsics).
// False, leaving `depth` unset, when that ray does not meet the plane in front of the camera.
bool ParentPlaneDepth(const State& coarse, const LevelImage& coarse_image, const Mat3& k_inv, int x,
                      int y, int& parent, float& depth);

// The coarser level's planes at the pixels of this level (nearest parent; the next iterations
// refine them).
void Upsample(const State& coarse, const LevelImage& coarse_image, const Level& lv, State& st);

// Cost of every pixel's current hypothesis.
void ScoreAll(const Level& lv, State& st, int threads);

// Red-black iterations: all pixels of one colour update in parallel over rows, reading only
// pixels of the other colour. Refinement perturbations start at 2^-first_scale of their full
// range and halve each iteration; (photo, level, pass) seed the random numbers, so that results
// do not depend on the thread count.
void Iterate(const Level& lv, State& st, int iterations, int first_scale, int photo, int level,
             int pass, int threads);

}  // namespace hdribr::patch_match
