#include "depth_compare.h"

#include <cmath>
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>

namespace hdribr::test {

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

DepthCounts CompareDepth(const cv::Mat& depth, const cv::Mat& gt, const std::string& tag,
                         double rel_tol, double leak_tol) {
  CV_Assert(depth.type() == CV_32FC1 && gt.type() == CV_32FC1 && depth.size() == gt.size());
  const char* dump = std::getenv("HDRIBR_TEST_DUMP");
  cv::Mat img;
  if (dump && !tag.empty()) img = cv::Mat(gt.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  DepthCounts c;
  for (int y = 0; y < gt.rows; ++y) {
    for (int x = 0; x < gt.cols; ++x) {
      const double g = gt.at<float>(y, x), d = depth.at<float>(y, x);
      cv::Vec3b colour(0, 0, 0);
      if (g <= 0) {
        ++c.empty;
        if (d > 0) {
          ++c.spurious;
          colour = {0, 255, 255};
        }
      } else {
        ++c.covered;
        if (d <= 0) {
          ++c.missing;
          colour = {255, 255, 255};
        } else if (std::abs(d - g) <= rel_tol * g) {
          ++c.accurate;
          colour = {0, 120, 0};
        } else if (d > g) {
          ++c.too_deep;
          colour = {0, 0, 255};
        } else {
          ++c.too_near;
          colour = {255, 0, 0};
        }
        if (d > g * (1.0 + leak_tol)) ++c.leak;
      }
      if (!img.empty()) img.at<cv::Vec3b>(y, x) = colour;
    }
  }
  if (!img.empty()) cv::imwrite(std::string(dump) + "/" + tag + ".png", img);
  return c;
}

cv::Mat ReadTextureR8UI(const gl::Texture& texture) {
  cv::Mat out(texture.height(), texture.width(), CV_8UC1);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(texture.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(out.total()), out.data);
  return out;
}

}  // namespace hdribr::test
