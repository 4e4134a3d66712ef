#include "render/render_output.h"

#include <algorithm>
#include <exception>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "core/error.h"
#include "io/exr.h"

namespace hdribr::render {

void WriteRgbaExr(const std::filesystem::path& path, const cv::Mat& bgr, const cv::Mat& valid) {
  WriteExrWithMask(path, bgr, valid, "A", ExrPixel::kFloat);
}

cv::Mat FalseColour(const cv::Mat& value, double lo, double hi, const cv::Mat& mask) {
  HDRIBR_CHECK(value.type() == CV_32FC1);
  cv::Mat gray(value.size(), CV_8UC1);
  const double span = hi > lo ? hi - lo : 1.0;
  for (int y = 0; y < value.rows; ++y) {
    for (int x = 0; x < value.cols; ++x) {
      const double t = std::clamp((value.at<float>(y, x) - lo) / span, 0.0, 1.0);
      gray.at<uint8_t>(y, x) = static_cast<uint8_t>(t * 255.0 + 0.5);
    }
  }
  cv::Mat colour, out(value.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  cv::applyColorMap(gray, colour, cv::COLORMAP_TURBO);
  colour.copyTo(out, mask);
  return out;
}

}  // namespace hdribr::render
