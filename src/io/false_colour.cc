#include "io/false_colour.h"

#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace hdribr {

cv::Mat FalseColour(const cv::Mat& value, double lo, double hi, const cv::Mat& mask) {
  HDRIBR_CHECK(value.channels() == 1);
  const double scale = 255.0 / (hi > lo ? hi - lo : 1.0);
  cv::Mat shifted;  // t * 255 + 0.5
  value.convertTo(shifted, CV_64F, scale, 0.5 - lo * scale);
  // Its floor: convertTo rounds to the nearest integer, so step back where that rounded up.
  cv::Mat nearest, nearest_f;
  shifted.convertTo(nearest, CV_32S);
  nearest.convertTo(nearest_f, CV_64F);
  cv::subtract(nearest, cv::Scalar(1), nearest, nearest_f > shifted);
  cv::Mat level, colour;
  nearest.convertTo(level, CV_8U);  // saturates: the clamp to [0, 1]
  cv::applyColorMap(level, colour, cv::COLORMAP_TURBO);
  cv::Mat out(value.size(), CV_8UC3, cv::Scalar::all(0));
  colour.copyTo(out, mask);
  return out;
}

}  // namespace hdribr
