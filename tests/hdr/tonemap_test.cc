#include "hdr/tonemap.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace hdribr {
namespace {

TEST(Reinhard, UniformGreyMapsToKeyOverOnePlusKey) {
  const cv::Mat grey(4, 5, CV_32FC3, cv::Scalar(5, 5, 5));
  EXPECT_NEAR(LogAverageLuminance(grey), 5.0, 1e-5);
  ReinhardOptions opt;  // key 0.18, exposure 1, gamma 2.2
  const cv::Mat d = ToneMapReinhard(grey, opt);
  const double expected = std::pow(0.18 / 1.18, 1 / 2.2);  // 0.4255
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(d.at<cv::Vec3f>(2, 3)[c], expected, 1e-5);
  opt.exposure = 2.0;
  opt.gamma = 1.0;
  EXPECT_NEAR(ToneMapReinhard(grey, opt).at<cv::Vec3f>(0, 0)[1], 2 * 0.18 / 1.18, 1e-5);
}

TEST(Reinhard, FollowsEquations8To12) {
  cv::Mat hdr(1, 3, CV_32FC3);
  hdr.at<cv::Vec3f>(0, 0) = {1, 1, 1};
  hdr.at<cv::Vec3f>(0, 1) = {0.5f, 2, 4};  // B, G, R
  hdr.at<cv::Vec3f>(0, 2) = {0.01f, 0.02f, 0.03f};
  const double eps = 1e-6;
  double l[3];
  double sum_log = 0;
  for (int i = 0; i < 3; ++i) {
    const cv::Vec3f p = hdr.at<cv::Vec3f>(0, i);
    l[i] = 0.2126 * p[2] + 0.7152 * p[1] + 0.0722 * p[0];
    sum_log += std::log(eps + l[i]);
  }
  const double l_a = std::exp(sum_log / 3);  // standard log-average, not the paper's eq. 9
  EXPECT_NEAR(LogAverageLuminance(hdr, {}, eps), l_a, 1e-9);
  ReinhardOptions opt;
  opt.key = 0.3;
  opt.exposure = 1.5;
  opt.gamma = 2.0;
  const cv::Mat d = ToneMapReinhard(hdr, opt);
  for (int i = 0; i < 3; ++i) {
    const double l_s = opt.key / l_a * l[i];
    const double l_d = l_s / (1 + l_s);
    for (int c = 0; c < 3; ++c) {
      const double want =
          std::min(1.0, std::pow(opt.exposure * hdr.at<cv::Vec3f>(0, i)[c] * l_d / l[i], 0.5));
      EXPECT_NEAR(d.at<cv::Vec3f>(0, i)[c], want, 1e-6) << i << " " << c;
    }
  }
}

TEST(Reinhard, FixedLogAverageAndValidity) {
  cv::Mat hdr(1, 2, CV_32FC3, cv::Scalar(1, 1, 1));
  hdr.at<cv::Vec3f>(0, 1) = {1000, 1000, 1000};
  const cv::Mat valid = (cv::Mat_<uint8_t>(1, 2) << 255, 0);
  EXPECT_NEAR(LogAverageLuminance(hdr, valid), 1.0, 1e-5);  // the invalid pixel is ignored
  ReinhardOptions opt;
  opt.gamma = 1;
  const cv::Mat d = ToneMapReinhard(hdr, opt, valid);
  EXPECT_NEAR(d.at<cv::Vec3f>(0, 0)[0], 0.18 / 1.18, 1e-5);
  EXPECT_EQ(d.at<cv::Vec3f>(0, 1), cv::Vec3f(0, 0, 0));
  opt.log_average = 0.5;  // fixed L_a: L_s = 0.18 / 0.5
  EXPECT_NEAR(ToneMapReinhard(hdr, opt).at<cv::Vec3f>(0, 0)[2], 0.36 / 1.36, 1e-5);
  opt.log_average = 0.0;
  EXPECT_THROW(ToneMapReinhard(hdr, opt), UsageError);
}

TEST(Reinhard, BlackAndExtremePixelsStayFiniteAndInRange) {
  cv::Mat hdr(1, 4, CV_32FC3);
  hdr.at<cv::Vec3f>(0, 0) = {0, 0, 0};
  hdr.at<cv::Vec3f>(0, 1) = {1e30f, 1e30f, 1e30f};
  hdr.at<cv::Vec3f>(0, 2) = {1e-30f, 0, 0};
  hdr.at<cv::Vec3f>(0, 3) = {0, 0, 50};  // saturated red: clamps to 1
  ReinhardOptions opt;
  opt.exposure = 4;
  opt.log_average = 1.0;
  const cv::Mat d = ToneMapReinhard(hdr, opt);
  EXPECT_TRUE(cv::checkRange(ToneMapReinhard(hdr, {}), true, nullptr, 0.0, 1.0 + 1e-6));
  EXPECT_TRUE(cv::checkRange(d, true, nullptr, 0.0, 1.0 + 1e-6));
  EXPECT_EQ(d.at<cv::Vec3f>(0, 0), cv::Vec3f(0, 0, 0));
  EXPECT_FLOAT_EQ(d.at<cv::Vec3f>(0, 3)[2], 1.0f);
  const cv::Mat bgr = DisplayToBgr8(d);
  EXPECT_EQ(bgr.type(), CV_8UC3);
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 3)[2], 255);
  // All-black image: L_a falls back to epsilon-level values, output stays black.
  const cv::Mat black(2, 2, CV_32FC3, cv::Scalar(0, 0, 0));
  EXPECT_EQ(cv::countNonZero(ToneMapReinhard(black, {}).reshape(1)), 0);
}

}  // namespace
}  // namespace hdribr
