// The cost of a PatchMatch plane hypothesis at a reference pixel (frontend/patch_match.h): the
// bilaterally weighted NCC with each source photo through the plane-induced homography, per-pixel
// view selection, and the forward-backward reprojection error of the geometric pass.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace hdribr::patch_match {

using Mat3 = Eigen::Matrix3f;
using Vec3 = Eigen::Vector3f;

inline constexpr float kMaxCost = 2.f;        // 1 - NCC of a source that cannot score the pixel
inline constexpr float kNoCost = 1e9f;        // cost of a pixel without a valid hypothesis
inline constexpr int kMaxSources = 32;        // sources used per photo at most
inline constexpr float kMinVariance = 1e-6f;  // flat window (intensities in [0, 1])

// A photo at one pyramid level, in OpenCV's pixel convention (pixel centres at integers).
struct LevelImage {
  cv::Mat gray;  // CV_32F
  Mat3 k, k_inv;
};

// A source photo as seen from the reference at one level.
struct SourceView {
  const LevelImage* image = nullptr;
  Mat3 a;         // K_s R K_r^-1: the homography's plane-independent part
  Vec3 b;         // K_s t
  Mat3 rotation;  // src_from_ref
  Vec3 translation;
  const cv::Mat* depth = nullptr;  // its depth from the previous level or pass (geometric cost)
  Mat3 depth_k, depth_k_inv;       // the intrinsics of that depth map, OpenCV convention
};

// Sample offsets of the window: a grid of n x n at -r, -r + step, ..., with spatial weights.
// The per-sample arrays are padded to a multiple of 4 samples (offset 0, weight 0).
struct WindowGrid {
  std::vector<int> offsets;    // per axis
  std::vector<float> spatial;  // per sample, row-major, padded
  std::vector<float> dx, dy;   // per sample offsets, padded
  int n = 0;                   // samples per axis
  int samples = 0;             // n * n
  int padded = 0;              // samples rounded up to a multiple of 4
};

WindowGrid MakeWindow(int radius, int step);

// Everything the cost of one reference photo at one level needs.
struct Level {
  const LevelImage* ref = nullptr;
  std::vector<SourceView> sources;
  const WindowGrid* window = nullptr;
  int w = 0, h = 0;
  float depth_min = 0, depth_max = 0;
  int best_views = 1;
  float inv_two_sigma_color2 = 1;
  bool geometric = false;
  float geom_weight = 0, geom_max_error = 0;
};

// The reference window at a pixel as NCC weights: the weighted NCC with a source patch s is
// sum(a s) / sqrt(sum(b s^2) - sum(b s)^2) (Schönberger et al. 2016, eq. 8 with COLMAP's
// bilateral weights). Sized window.padded, zero in the padding.
struct RefWindow {
  std::vector<float> a, b;
  std::vector<float> samples;  // scratch: a source patch's intensities
};

// Fills `out` for pixel (x, y) of the level's reference; false when the window is flat.
bool PrepareWindow(const Level& lv, int x, int y, RefWindow& out);

// Where the patch of pixel (x, y) through homography `hm` falls in a source image.
enum class Footprint { kOutside, kCentre, kFramed };  // centre outside / centre in / all in
Footprint PatchFootprint(const cv::Mat& image, const WindowGrid& window, const Mat3& hm, int x,
                         int y);

// 1 - weighted NCC, in [0, 2], of the reference window `ref` with the source patch through `hm`
// (kMaxCost when the patch is flat). Samples four window points at a time (SSE2 where
// available); window points behind the source camera sample its border.
float SourcePhotoCost(const cv::Mat& image, const WindowGrid& window, const Mat3& hm, int x, int y,
                      RefWindow& ref);

// Cost of the plane through depth `d` at pixel (x, y) (ray `ray` = K^-1 (x, y, 1)) with normal
// `n`: mean of the best views' costs (per-pixel view selection, so that sources where the pixel
// is occluded do not vote) among the sources that frame the patch, or all of them when none
// does; `ncc` gets the mean NCC of those views. Once the cost provably reaches `bound`, returns
// a value >= bound without scoring the remaining sources (`ncc` then unset).
float PlaneCost(const Level& lv, int x, int y, const Vec3& ray, float d, const Vec3& n,
                RefWindow& ref, float bound, float* ncc);

}  // namespace hdribr::patch_match
