#include "eval/depth_accuracy.h"

#include <cmath>
#include <stdexcept>

namespace hdribr::eval {

DepthCounts& DepthCounts::operator+=(const DepthCounts& o) {
  covered += o.covered;
  accurate += o.accurate;
  too_near += o.too_near;
  too_deep += o.too_deep;
  missing += o.missing;
  leak += o.leak;
  empty += o.empty;
  spurious += o.spurious;
  return *this;
}

DepthCounts CompareDepth(const cv::Mat& depth, const cv::Mat& gt, double rel_tol, double leak_tol,
                         cv::Mat* outcomes) {
  if (depth.type() != CV_32FC1 || gt.type() != CV_32FC1 || depth.size() != gt.size()) {
    throw std::invalid_argument("CompareDepth: depth maps must be CV_32FC1 of equal size");
  }
  if (outcomes) outcomes->create(gt.size(), CV_8UC1);
  DepthCounts c;
  for (int y = 0; y < gt.rows; ++y) {
    for (int x = 0; x < gt.cols; ++x) {
      const double g = gt.at<float>(y, x), d = depth.at<float>(y, x);
      DepthOutcome o;
      if (g <= 0) {
        ++c.empty;
        o = d > 0 ? DepthOutcome::kSpurious : DepthOutcome::kEmpty;
        if (d > 0) ++c.spurious;
      } else {
        ++c.covered;
        if (d <= 0) {
          o = DepthOutcome::kMissing;
          ++c.missing;
        } else if (std::abs(d - g) <= rel_tol * g) {
          o = DepthOutcome::kAccurate;
          ++c.accurate;
        } else if (d > g) {
          o = DepthOutcome::kTooDeep;
          ++c.too_deep;
        } else {
          o = DepthOutcome::kTooNear;
          ++c.too_near;
        }
        if (d > g * (1.0 + leak_tol)) ++c.leak;
      }
      if (outcomes) outcomes->at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(o);
    }
  }
  return c;
}

}  // namespace hdribr::eval
