#include "hdr/debevec.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "hdr/response_error.h"
#include "hdr/synthetic_stack.h"

namespace hdribr {
namespace {

using test::MedianAbsLogRatio;
using test::RmsLinearError;
using test::SyntheticRadiance;
using test::SyntheticResponse;
using test::SyntheticStack;

const std::vector<double> kTimes = {1.0 / 64, 1.0 / 32, 1.0 / 16, 1.0 / 8,
                                    1.0 / 4,  1.0 / 2,  1.0,      2.0};

bool AllFinite(const cv::Mat& m) { return cv::checkRange(m, true, nullptr, -1e38, 1e38); }

TEST(HatWeight, IsDebevecsTriangle) {
  EXPECT_EQ(HatWeight(0), 0);
  EXPECT_EQ(HatWeight(255), 0);
  EXPECT_EQ(HatWeight(127), 127);
  EXPECT_EQ(HatWeight(128), 127);
  EXPECT_EQ(HatWeight(10), 10);
}

TEST(CalibrateDebevec, RecoversKnownResponseWithin3Percent) {
  const SyntheticResponse response;
  const ExposureStack stack = SyntheticStack(SyntheticRadiance(), kTimes, response);
  CalibrationStats stats;
  const ResponseCurve got = CalibrateDebevec(stack, {}, &stats);
  ASSERT_TRUE(got.IsValid());
  EXPECT_EQ(got.source, "debevec");
  const ResponseCurve truth = response.Truth();
  for (int c = 0; c < 3; ++c) {
    EXPECT_DOUBLE_EQ(got.log_inverse[c][128], 0.0);
    EXPECT_GT(stats.samples_used[c], 100);
    const double rms = RmsLinearError(got, truth, c);
    std::printf("channel %d: RMS linear error %.4f over 10-245 DN, %d samples\n", c, rms,
                stats.samples_used[c]);
    EXPECT_LE(rms, 0.03) << "channel " << c;
  }
}

TEST(CalibrateDebevec, WrongCurveIsDetectedByTheErrorMeasure) {
  // The measure must be able to fail: a plain gamma 2.2 curve is not the truth.
  const SyntheticResponse response;
  ResponseCurve gamma;
  for (int c = 0; c < 3; ++c) {
    gamma.log_inverse[c].resize(256);
    for (int z = 0; z < 256; ++z) gamma.log_inverse[c][z] = 2.2 * std::log((z + 0.25) / 255.0);
  }
  EXPECT_GT(RmsLinearError(gamma, response.Truth(), 0), 0.03);
}

TEST(CalibrateDebevec, IgnoresPixelsMaskedInvalid) {
  const SyntheticResponse response;
  ExposureStack stack = SyntheticStack(SyntheticRadiance(), kTimes, response);
  // Random garbage in every other 8-pixel column stripe of images 2-5, masked out (the stripes
  // leave the whole radiance range sampled elsewhere).
  stack.masks.assign(stack.images.size(), cv::Mat());
  for (auto& m : stack.masks) m = cv::Mat(stack.images[0].size(), CV_8UC1, cv::Scalar(255));
  cv::RNG rng(7);
  for (int x = 0; x < stack.images[0].cols; x += 16) {
    const cv::Rect stripe(x, 0, 8, stack.images[0].rows);
    for (int i : {2, 3, 4, 5}) {
      rng.fill(stack.images[i](stripe), cv::RNG::UNIFORM, 0, 256);
      stack.masks[i](stripe).setTo(0);
    }
  }
  // Without the masks the garbage spoils the curve: the test can fail.
  ExposureStack unmasked = stack;
  unmasked.masks.clear();
  const ResponseCurve spoiled = CalibrateDebevec(unmasked);
  EXPECT_GT(RmsLinearError(spoiled, response.Truth(), 1), 0.03);
  const ResponseCurve got = CalibrateDebevec(stack);
  const ResponseCurve truth = response.Truth();
  for (int c = 0; c < 3; ++c) EXPECT_LE(RmsLinearError(got, truth, c), 0.03) << c;
}

TEST(MergeDebevec, RecoversRadiance) {
  const SyntheticResponse response;
  const cv::Mat radiance = SyntheticRadiance();
  const ExposureStack stack = SyntheticStack(radiance, kTimes, response);
  cv::Mat valid;
  MergeStats stats;
  const cv::Mat with_truth = MergeDebevec(stack, response.Truth(), &valid, &stats);
  ASSERT_EQ(with_truth.type(), CV_32FC3);
  EXPECT_TRUE(AllFinite(with_truth));
  EXPECT_EQ(cv::countNonZero(valid), valid.rows * valid.cols);
  EXPECT_EQ(stats.invalid, 0);
  const double err_truth = MedianAbsLogRatio(with_truth, radiance);
  const cv::Mat with_recovered = MergeDebevec(stack, CalibrateDebevec(stack));
  const double err_recovered = MedianAbsLogRatio(with_recovered, radiance, {}, true);
  std::printf("median |log ratio|: %.4f with the true curve, %.4f recovered\n", err_truth,
              err_recovered);
  EXPECT_LE(err_truth, 0.02);
  EXPECT_LE(err_recovered, 0.03);
  // The scale is set by g(128) = 0 for the recovered curve, by the truth for the true one.
  const cv::Vec3f e = with_truth.at<cv::Vec3f>(60, 80), r = radiance.at<cv::Vec3f>(60, 80);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(std::log(e[c] / r[c]), 0.0, 0.05);
}

TEST(MergeDebevec, SaturatedEverywhereTakesShortestExposure) {
  const SyntheticResponse response;
  const ResponseCurve truth = response.Truth();
  ExposureStack stack;
  stack.times = {0.5, 0.25, 1.0};
  for (int i = 0; i < 3; ++i) stack.images.emplace_back(8, 6, CV_8UC3, cv::Scalar(255, 255, 255));
  MergeStats stats;
  const cv::Mat e = MergeDebevec(stack, truth, nullptr, &stats);
  EXPECT_TRUE(AllFinite(e));
  EXPECT_EQ(stats.saturated, 8 * 6 * 3);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(e.at<cv::Vec3f>(2, 3)[c], std::exp(truth.log_inverse[c][255]) / 0.25, 1e-3);
  }
  EXPECT_THROW(CalibrateDebevec(stack), UsageError);
}

TEST(MergeDebevec, BlackEverywhereTakesLongestExposure) {
  const ResponseCurve truth = SyntheticResponse().Truth();
  ExposureStack stack;
  stack.times = {0.5, 4.0, 1.0};
  for (int i = 0; i < 3; ++i) stack.images.emplace_back(8, 6, CV_8UC3, cv::Scalar(0, 0, 0));
  MergeStats stats;
  const cv::Mat e = MergeDebevec(stack, truth, nullptr, &stats);
  EXPECT_TRUE(AllFinite(e));
  EXPECT_EQ(stats.dark, 8 * 6 * 3);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(e.at<cv::Vec3f>(0, 0)[c], std::exp(truth.log_inverse[c][0]) / 4.0, 1e-9);
  }
  EXPECT_THROW(CalibrateDebevec(stack), UsageError);
}

TEST(MergeDebevec, OneImageStackIsTheInverseResponse) {
  const ResponseCurve truth = SyntheticResponse().Truth();
  ExposureStack stack;
  stack.times = {0.5};
  stack.images.emplace_back(4, 4, CV_8UC3, cv::Scalar(10, 128, 200));
  const cv::Mat e = MergeDebevec(stack, truth);
  const int z[3] = {10, 128, 200};
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(e.at<cv::Vec3f>(1, 1)[c] / (std::exp(truth.log_inverse[c][z[c]]) / 0.5), 1.0, 1e-5);
  }
  EXPECT_THROW(CalibrateDebevec(stack), UsageError);
}

TEST(MergeDebevec, MaskedPixelsDoNotContribute) {
  const SyntheticResponse response;
  const ResponseCurve truth = response.Truth();
  const ExposureStack clean = SyntheticStack(SyntheticRadiance(40, 30), kTimes, response);
  ExposureStack dirty = clean;
  for (auto& im : dirty.images) im = im.clone();
  dirty.masks.assign(clean.images.size(), cv::Mat());
  for (auto& m : dirty.masks) m = cv::Mat(30, 40, CV_8UC1, cv::Scalar(255));
  // Image 2 is garbage on the top rows and masked there; pixel (0,0) is invalid everywhere.
  dirty.images[2].rowRange(0, 10).setTo(cv::Scalar(77, 200, 3));
  dirty.masks[2].rowRange(0, 10).setTo(0);
  for (auto& m : dirty.masks) m.at<uint8_t>(0, 0) = 0;
  ExposureStack without = clean;
  without.images.erase(without.images.begin() + 2);
  without.times.erase(without.times.begin() + 2);

  cv::Mat valid;
  MergeStats stats;
  const cv::Mat got = MergeDebevec(dirty, truth, &valid, &stats);
  const cv::Mat expected_top = MergeDebevec(without, truth);
  const cv::Mat expected_rest = MergeDebevec(clean, truth);
  EXPECT_EQ(valid.at<uint8_t>(0, 0), 0);
  EXPECT_EQ(got.at<cv::Vec3f>(0, 0), cv::Vec3f(0, 0, 0));
  EXPECT_EQ(stats.invalid, 1);
  EXPECT_EQ(cv::countNonZero(valid), 40 * 30 - 1);
  for (int y = 0; y < 30; ++y) {
    for (int x = (y == 0); x < 40; ++x) {
      const cv::Vec3f a = got.at<cv::Vec3f>(y, x);
      const cv::Vec3f b = (y < 10 ? expected_top : expected_rest).at<cv::Vec3f>(y, x);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c] / b[c], 1.0, 1e-5) << y << "," << x;
    }
  }
}

TEST(ExposureStack, RejectsInconsistentStacks) {
  ExposureStack stack;
  EXPECT_THROW(stack.Validate(), UsageError);
  stack.images = {cv::Mat(4, 4, CV_8UC3, cv::Scalar(1)), cv::Mat(4, 5, CV_8UC3, cv::Scalar(1))};
  stack.times = {1, 2};
  EXPECT_THROW(stack.Validate(), UsageError);  // sizes differ
  stack.images[1] = cv::Mat(4, 4, CV_8UC3, cv::Scalar(1));
  EXPECT_NO_THROW(stack.Validate());
  stack.times = {1};
  EXPECT_THROW(stack.Validate(), UsageError);  // count mismatch
  stack.times = {1, -2};
  EXPECT_THROW(stack.Validate(), UsageError);
  stack.times = {1, NAN};
  EXPECT_THROW(stack.Validate(), UsageError);
  stack.times = {1, 1};
  EXPECT_NO_THROW(stack.Validate());
  EXPECT_THROW(CalibrateDebevec(stack), UsageError);  // equal times
}

TEST(ExposureTime, ParsesDecimalsAndFractions) {
  EXPECT_DOUBLE_EQ(ParseExposureTime("1/1024", "t"), 1.0 / 1024);
  EXPECT_DOUBLE_EQ(ParseExposureTime("32", "t"), 32.0);
  EXPECT_DOUBLE_EQ(ParseExposureTime("0.25", "t"), 0.25);
  EXPECT_THROW(ParseExposureTime("1/0", "t"), UsageError);
  EXPECT_THROW(ParseExposureTime("-1", "t"), UsageError);
  EXPECT_THROW(ParseExposureTime("abc", "t"), UsageError);
  EXPECT_THROW(ParseExposureTime("1/2x", "t"), UsageError);
  EXPECT_THROW(ParseExposureTime("", "t"), UsageError);
}

}  // namespace
}  // namespace hdribr
