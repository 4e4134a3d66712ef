// Re-exposure: linear radiance turned into the 8-bit values a camera with a given response
// would record at a given exposure (the inverse of Debevec-Malik's g).
#pragma once

#include <opencv2/core.hpp>

#include "hdr/response_curve.h"

namespace hdribr {

// 8-bit BGR image of CV_32FC3 BGR radiance E exposed for `exposure` (in the units the response
// and the radiance share, e.g. a relative exposure): per channel z with g(z) = ln(E exposure),
// interpolated between codes and rounded; 0 where E <= 0 or not finite, 255 above g(255).
cv::Mat ExposeThroughResponse(const cv::Mat& radiance, const ResponseCurve& response,
                              double exposure);

}  // namespace hdribr
