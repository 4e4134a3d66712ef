#include "hdr/opencv_reference.h"

#include <cmath>
#include <opencv2/photo.hpp>

#include "core/error.h"

namespace hdribr {

cv::Mat OpenCvCalibrateDebevec(const std::vector<cv::Mat>& images, const std::vector<double>& times,
                               const OpenCvDebevecOptions& options) {
  std::vector<float> t(times.begin(), times.end());
  cv::Mat response;
  cv::createCalibrateDebevec(options.samples, options.lambda, options.random)
      ->process(images, response, t);
  return response;
}

cv::Mat OpenCvMergeDebevec(const std::vector<cv::Mat>& images, const std::vector<double>& times,
                           const cv::Mat& response) {
  std::vector<float> t(times.begin(), times.end());
  cv::Mat radiance;
  cv::createMergeDebevec()->process(images, radiance, t, response);
  return radiance;
}

ResponseCurve ResponseFromOpenCv(const cv::Mat& response) {
  HDRIBR_CHECK(response.type() == CV_32FC3 && response.total() == 256);
  ResponseCurve curve;
  curve.source = "opencv-debevec";
  for (int c = 0; c < 3; ++c) {
    curve.log_inverse[c].resize(256);
    for (int z = 0; z < 256; ++z) {
      curve.log_inverse[c][z] = std::log(response.at<cv::Vec3f>(z)[c]);
    }
  }
  return curve;
}

}  // namespace hdribr
