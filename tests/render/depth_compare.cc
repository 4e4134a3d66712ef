#include "depth_compare.h"

#include <cstdlib>
#include <opencv2/imgcodecs.hpp>

namespace hdribr::test {

DepthCounts CompareDepth(const cv::Mat& depth, const cv::Mat& gt, const std::string& tag,
                         double rel_tol, double leak_tol) {
  const char* dump = std::getenv("HDRIBR_TEST_DUMP");
  if (!dump || tag.empty()) return eval::CompareDepth(depth, gt, rel_tol, leak_tol);
  cv::Mat outcomes;
  const DepthCounts c = eval::CompareDepth(depth, gt, rel_tol, leak_tol, &outcomes);
  // BGR per eval::DepthOutcome: empty, spurious, missing, accurate, too near, too deep.
  const cv::Vec3b colours[] = {{0, 0, 0},   {0, 255, 255}, {255, 255, 255},
                               {0, 120, 0}, {255, 0, 0},   {0, 0, 255}};
  cv::Mat img(gt.size(), CV_8UC3);
  for (int y = 0; y < gt.rows; ++y) {
    for (int x = 0; x < gt.cols; ++x) img.at<cv::Vec3b>(y, x) = colours[outcomes.at<uchar>(y, x)];
  }
  cv::imwrite(std::string(dump) + "/" + tag + ".png", img);
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
