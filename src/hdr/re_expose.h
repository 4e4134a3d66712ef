// Re-exposure: linear radiance turned into the 8-bit values a camera with a given response
// would record at a given exposure (the inverse of Debevec-Malik's g).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "hdr/response_curve.h"

namespace hdribr {

// The code z (continuous) with g(z) = log_value on a non-decreasing curve g (one channel of
// ResponseCurve::log_inverse), linear between codes and clamped to [0, 255]; 0 for NaN.
double CodeOfLog(const std::vector<double>& g, double log_value);

// 8-bit BGR image of CV_32FC3 BGR radiance E exposed for `exposure` (in the units the response
// and the radiance share, e.g. a relative exposure): per channel z with g(z) = ln(E exposure),
// interpolated between codes and rounded; 0 where E <= 0 or not finite, 255 above g(255).
cv::Mat ExposeThroughResponse(const cv::Mat& radiance, const ResponseCurve& response,
                              double exposure);

}  // namespace hdribr
