// A depth map against ground-truth depth: each pixel's outcome, the counts and their shares.
#include "eval/depth_accuracy.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace hdribr::eval {
namespace {

TEST(DepthAccuracy, CountsEveryOutcome) {
  // GT: 10 everywhere but one pixel of sky (0).
  const cv::Mat gt = (cv::Mat_<float>(2, 4) << 10, 10, 10, 10, 10, 10, 10, 0);
  // accurate (+0.9 %), accurate (-0.8 %), too near (-1.5 %), too deep (+2 %, no leak),
  // leak (+6 %), missing, accurate, spurious.
  const cv::Mat depth = (cv::Mat_<float>(2, 4) << 10.09f, 9.92f, 9.85f, 10.2f, 10.6f, 0, 10, 5);
  cv::Mat outcomes;
  const DepthCounts c = CompareDepth(depth, gt, kDepthTolerance, kLeakTolerance, &outcomes);
  EXPECT_EQ(c.covered, 7);
  EXPECT_EQ(c.accurate, 3);
  EXPECT_EQ(c.too_near, 1);
  EXPECT_EQ(c.too_deep, 2);
  EXPECT_EQ(c.missing, 1);
  EXPECT_EQ(c.leak, 1);
  EXPECT_EQ(c.empty, 1);
  EXPECT_EQ(c.spurious, 1);
  EXPECT_DOUBLE_EQ(c.accuracy(), 3.0 / 7.0);
  EXPECT_DOUBLE_EQ(c.leakage(), 1.0 / 7.0);
  EXPECT_DOUBLE_EQ(c.coverage(), 6.0 / 7.0);
  const auto at = [&](int y, int x) { return static_cast<DepthOutcome>(outcomes.at<uchar>(y, x)); };
  EXPECT_EQ(at(0, 0), DepthOutcome::kAccurate);
  EXPECT_EQ(at(0, 2), DepthOutcome::kTooNear);
  EXPECT_EQ(at(0, 3), DepthOutcome::kTooDeep);
  EXPECT_EQ(at(1, 1), DepthOutcome::kMissing);
  EXPECT_EQ(at(1, 3), DepthOutcome::kSpurious);

  DepthCounts sum = c;
  sum += c;
  EXPECT_EQ(sum.covered, 14);
  EXPECT_DOUBLE_EQ(sum.accuracy(), c.accuracy());
}

TEST(DepthAccuracy, MismatchedMapsAreRefused) {
  const cv::Mat gt(2, 2, CV_32FC1, cv::Scalar(1));
  EXPECT_THROW(CompareDepth(cv::Mat(2, 3, CV_32FC1, cv::Scalar(1)), gt), std::invalid_argument);
  EXPECT_THROW(CompareDepth(cv::Mat(2, 2, CV_64FC1, cv::Scalar(1)), gt), std::invalid_argument);
}

}  // namespace
}  // namespace hdribr::eval
