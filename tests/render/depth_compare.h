// Comparison of a depth-pass output with ground-truth depth (tests of the depth pass): the
// counts of eval::CompareDepth, and a debug image.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "eval/depth_accuracy.h"
#include "gl/objects.h"

namespace hdribr::test {

using eval::DepthCounts;

// eval::CompareDepth. When the environment variable HDRIBR_TEST_DUMP names a folder and `tag`
// is not empty, also writes <folder>/<tag>.png: green = accurate, red = too deep, blue = too
// near, white = missing, yellow = spurious.
DepthCounts CompareDepth(const cv::Mat& depth, const cv::Mat& gt, const std::string& tag = "",
                         double rel_tol = eval::kDepthTolerance,
                         double leak_tol = eval::kLeakTolerance);

// Reads level 0 of an R8UI texture (e.g. DepthTarget::classes) as CV_8UC1; row 0 = top row.
cv::Mat ReadTextureR8UI(const gl::Texture& texture);

}  // namespace hdribr::test
