#include "frontend/ncc.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace hdribr {
namespace {

cv::Mat Noise(int w, int h, int seed) {
  cv::Mat m(h, w, CV_32F);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::GaussianBlur(m, m, cv::Size(3, 3), 0.8);
  return m;
}

TEST(Ncc, IsOneUnderGainAndOffset) {
  const cv::Mat a = Noise(9, 9, 1);
  const cv::Mat b = a * 0.3 + 0.2;  // a darker exposure of the same patch
  EXPECT_NEAR(Ncc(a, b), 1.0, 1e-5);
  EXPECT_NEAR(Ncc(a, 1.0 - a), -1.0, 1e-5);
}

TEST(Ncc, DropsForShiftedContent) {
  const cv::Mat img = Noise(40, 40, 2);
  const cv::Mat a = img(cv::Rect(10, 10, 9, 9)).clone();
  const cv::Mat shifted = img(cv::Rect(13, 10, 9, 9)).clone() * 2.0;
  EXPECT_LT(Ncc(a, shifted), 0.5);
  EXPECT_EQ(Ncc(a, cv::Mat(9, 9, CV_32F, cv::Scalar(0.5))), -1.0);  // flat patch
}

TEST(Ncc, MapMatchesPatchNcc) {
  const cv::Mat a = Noise(30, 20, 3);
  cv::Mat b = a * 0.5 + 0.1 + Noise(30, 20, 4) * 0.2;
  cv::Mat mean, var;
  WindowStats(a, 2, mean, var);
  const cv::Mat map = NccMap(a, mean, var, b, 2);
  const cv::Rect win(10 - 2, 8 - 2, 5, 5);
  EXPECT_NEAR(map.at<float>(8, 10), Ncc(a(win).clone(), b(win).clone()), 1e-3);
}

}  // namespace
}  // namespace hdribr
