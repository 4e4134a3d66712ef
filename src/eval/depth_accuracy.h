// Accuracy of a rendered depth map against ground-truth depth: the depth pass's figure at the
// views of a synthetic capture. OpenGL-free.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

namespace hdribr::eval {

// Default tolerances of CompareDepth, relative to the GT depth.
inline constexpr double kDepthTolerance = 0.01;  // accurate within
inline constexpr double kLeakTolerance = 0.05;   // deeper by more: a farther surface shows

// What one pixel of CompareDepth is.
enum class DepthOutcome : std::uint8_t {
  kEmpty,     // no GT surface, no depth
  kSpurious,  // no GT surface, a depth
  kMissing,   // a GT surface, no depth
  kAccurate,  // within the relative tolerance of GT
  kTooNear,   // off by more, nearer than GT
  kTooDeep,   // off by more, deeper than GT
};

// Pixel counts of one or more comparisons (add them up with +=).
struct DepthCounts {
  long covered = 0;   // GT-covered pixels
  long accurate = 0;  // valid and within rel_tol of GT
  long too_near = 0;  // valid, off by more than rel_tol, nearer than GT
  long too_deep = 0;  // valid, off by more than rel_tol, deeper than GT
  long missing = 0;   // not valid
  long leak = 0;      // valid and deeper than GT by more than leak_tol (a farther surface)
  long empty = 0;     // GT-empty pixels
  long spurious = 0;  // GT-empty pixels that are valid

  DepthCounts& operator+=(const DepthCounts& o);
  double Share(long n) const { return covered > 0 ? double(n) / double(covered) : 0.0; }
  double accuracy() const { return Share(accurate); }
  double leakage() const { return Share(leak); }
  double coverage() const { return Share(covered - missing); }
};

// Compares `depth` (CV_32FC1 camera z, 0 = invalid) with `gt` (the same size and type, 0 = no
// surface), tolerances relative to the GT depth. When `outcomes` is given, it receives each
// pixel's DepthOutcome (CV_8UC1). Throws std::invalid_argument on mismatched inputs.
DepthCounts CompareDepth(const cv::Mat& depth, const cv::Mat& gt, double rel_tol = kDepthTolerance,
                         double leak_tol = kLeakTolerance, cv::Mat* outcomes = nullptr);

}  // namespace hdribr::eval
