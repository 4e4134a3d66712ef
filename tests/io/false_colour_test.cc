// False colour: levels rounded as the GPU false-colour pass does (t * 255 + 0.5), clamped,
// turbo map, mask.
#include "io/false_colour.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace hdribr {
namespace {

cv::Vec3b Turbo(int level) {
  const cv::Mat one(1, 1, CV_8UC1, cv::Scalar(level));
  cv::Mat colour;
  cv::applyColorMap(one, colour, cv::COLORMAP_TURBO);
  return colour.at<cv::Vec3b>(0, 0);
}

// The level of each pixel, by the definition.
int Level(float v, double lo, double hi) {
  const double span = hi > lo ? hi - lo : 1.0;
  return static_cast<int>(std::clamp((v - lo) / span, 0.0, 1.0) * 255.0 + 0.5);
}

TEST(FalseColour, EqualsTheDefinitionOnRandomValues) {
  cv::Mat value(300, 400, CV_32FC1);
  cv::RNG rng(5);
  rng.fill(value, cv::RNG::UNIFORM, -1.0, 8.0);  // below and above the range: clamped
  const double lo = 0.123456789, hi = 6.54321;
  const cv::Mat out = FalseColour(value, lo, hi);
  ASSERT_EQ(out.type(), CV_8UC3);
  cv::Mat level(value.size(), CV_8UC1), expected;
  for (int y = 0; y < value.rows; ++y) {
    for (int x = 0; x < value.cols; ++x) {
      level.at<uint8_t>(y, x) = static_cast<uint8_t>(Level(value.at<float>(y, x), lo, hi));
    }
  }
  cv::applyColorMap(level, expected, cv::COLORMAP_TURBO);
  EXPECT_EQ(cv::norm(out, expected, cv::NORM_INF), 0.0);
}

TEST(FalseColour, HalfwayLevelsRoundUp) {
  // Counts over [0, 6]: 1 -> 42.5 -> 43, 5 -> 212.5 -> 213 (not to the even 42 and 212).
  cv::Mat count(1, 7, CV_32FC1);
  for (int i = 0; i < 7; ++i) count.at<float>(0, i) = static_cast<float>(i);
  const cv::Mat out = FalseColour(count, 0, 6);
  EXPECT_EQ(out.at<cv::Vec3b>(0, 0), Turbo(0));
  EXPECT_EQ(out.at<cv::Vec3b>(0, 1), Turbo(43));
  EXPECT_EQ(out.at<cv::Vec3b>(0, 3), Turbo(128));
  EXPECT_EQ(out.at<cv::Vec3b>(0, 5), Turbo(213));
  EXPECT_EQ(out.at<cv::Vec3b>(0, 6), Turbo(255));
  // 8-bit input (error sums) the same way.
  cv::Mat sum(1, 2, CV_8UC1);
  sum.at<uint8_t>(0, 0) = 16;  // 16 * 255 / 96 = 42.5
  sum.at<uint8_t>(0, 1) = 80;  // 212.5
  const cv::Mat err = FalseColour(sum, 0, 96);
  EXPECT_EQ(err.at<cv::Vec3b>(0, 0), Turbo(43));
  EXPECT_EQ(err.at<cv::Vec3b>(0, 1), Turbo(213));
}

TEST(FalseColour, MaskAndEmptyRange) {
  cv::Mat value(2, 3, CV_32FC1, cv::Scalar(0.5f));
  cv::Mat mask(2, 3, CV_8UC1, cv::Scalar(255));
  mask.at<uint8_t>(1, 2) = 0;
  const cv::Mat out = FalseColour(value, 0, 1, mask);
  EXPECT_EQ(out.at<cv::Vec3b>(0, 0), Turbo(128));
  EXPECT_EQ(out.at<cv::Vec3b>(1, 2), cv::Vec3b(0, 0, 0));
  // hi <= lo: a span of 1 from lo.
  EXPECT_EQ(FalseColour(value, 0.25, 0.25).at<cv::Vec3b>(0, 0), Turbo(64));
}

}  // namespace
}  // namespace hdribr
