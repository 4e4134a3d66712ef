// False-colour pictures of scalar images (depth, counts, weights, errors) for inspection.
#pragma once

#include <opencv2/core.hpp>

namespace hdribr {

// CV_8UC3 (BGR) turbo colour map of a single-channel image: t = (value - lo) / (hi - lo)
// (hi - lo taken as 1 unless hi > lo), clamped to [0, 1], picks entry floor(t * 255 + 0.5) of
// the map (lo = blue end), as the viewer's GPU false-colour pass does. Pixels where `mask`
// (CV_8UC1, when given) is zero are black.
cv::Mat FalseColour(const cv::Mat& value, double lo, double hi, const cv::Mat& mask = {});

}  // namespace hdribr
