// Comparison of a depth-pass output with ground-truth depth (tests of the depth pass): counts
// of accurate, too near, too deep, missing and leaking pixels, and a debug image.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "gl/objects.h"

namespace hdribr::test {

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
  double spurious_share() const { return empty > 0 ? double(spurious) / double(empty) : 0.0; }
};

// Compares `depth` (CV_32FC1 camera z, 0 = invalid) with `gt` (same, 0 = no surface). When
// the environment variable HDRIBR_TEST_DUMP names a folder and `tag` is not empty, also
// writes <folder>/<tag>.png: green = accurate, red = too deep, blue = too near, white =
// missing, yellow = spurious.
DepthCounts CompareDepth(const cv::Mat& depth, const cv::Mat& gt, const std::string& tag = "",
                         double rel_tol = 0.01, double leak_tol = 0.05);

// Reads level 0 of an R8UI texture (e.g. DepthTarget::classes) as CV_8UC1; row 0 = top row.
cv::Mat ReadTextureR8UI(const gl::Texture& texture);

}  // namespace hdribr::test
