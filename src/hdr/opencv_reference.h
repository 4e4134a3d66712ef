// OpenCV's Debevec implementation (photo module), the peer hdribr is compared against in tests
// and `hdribr bench merge`.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "hdr/response_curve.h"

namespace hdribr {

struct OpenCvDebevecOptions {
  int samples = 70;  // cv::createCalibrateDebevec defaults
  float lambda = 10.0f;
  bool random = false;
};

// cv::CalibrateDebevec: a 256x1 CV_32FC3 linear response (OpenCV's own convention).
cv::Mat OpenCvCalibrateDebevec(const std::vector<cv::Mat>& images, const std::vector<double>& times,
                               const OpenCvDebevecOptions& options = {});
// cv::MergeDebevec with that response: CV_32FC3 radiance.
cv::Mat OpenCvMergeDebevec(const std::vector<cv::Mat>& images, const std::vector<double>& times,
                           const cv::Mat& response);
// OpenCV's linear response as a ResponseCurve (g = ln of it), not forced to be monotonic.
ResponseCurve ResponseFromOpenCv(const cv::Mat& response);

}  // namespace hdribr
