// PSNR and SSIM of eval/metrics.h on images with known answers.
#include "eval/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace hdribr {
namespace {

// A textured 8-bit BGR image with a black flat region (left third) and flat colour (top rows).
cv::Mat TestImage() {
  cv::Mat img(48, 64, CV_8UC3);
  cv::randu(img, cv::Scalar::all(30), cv::Scalar::all(220));
  cv::GaussianBlur(img, img, cv::Size(5, 5), 1.0);
  img.colRange(0, 20).setTo(cv::Scalar(0, 0, 0));
  img.rowRange(0, 6).setTo(cv::Scalar(40, 90, 160));
  return img;
}

TEST(Metrics, PsnrOfAKnownError) {
  const cv::Mat a = TestImage();
  cv::Mat b;
  a.convertTo(b, CV_8UC3, 1.0, 5.0);  // +5 everywhere: no pixel reaches 255 (at most 225)
  const ImageScores s = CompareImages(a, b);
  EXPECT_NEAR(s.psnr_db, 10.0 * std::log10(255.0 * 255.0 / 25.0), 1e-9);
  EXPECT_EQ(s.pixels, static_cast<long long>(a.total()));
  // Masked: only the masked pixels count.
  cv::Mat mask = cv::Mat::zeros(a.size(), CV_8UC1);
  mask.colRange(30, 40).setTo(255);
  b.colRange(0, 30).setTo(cv::Scalar::all(255));
  const ImageScores m = CompareImages(a, b, mask);
  EXPECT_NEAR(m.psnr_db, 10.0 * std::log10(255.0 * 255.0 / 25.0), 1e-9);
  EXPECT_EQ(m.pixels, 10 * a.rows);
}

TEST(Metrics, SsimOfIdenticalImagesIsOneInEveryChannelAndRegion) {
  // Flat regions (zero variance, zero mean in the black one) rest on the constants C1, C2.
  const cv::Mat a = TestImage();
  const cv::Mat map = SsimMap(a, a);
  double lo = 0, hi = 0;
  cv::minMaxLoc(map, &lo, &hi);
  EXPECT_NEAR(lo, 1.0, 1e-5);
  EXPECT_NEAR(hi, 1.0, 1e-5);
  EXPECT_NEAR(CompareImages(a, a).ssim, 1.0, 1e-5);
}

TEST(Metrics, SsimOfColourIsTheMeanOfItsChannels) {
  const cv::Mat a = TestImage();
  cv::Mat b = a.clone();
  cv::GaussianBlur(b, b, cv::Size(3, 3), 0.8);
  cv::Mat noise(a.size(), CV_8UC3);
  cv::randu(noise, cv::Scalar::all(0), cv::Scalar::all(12));
  b += noise;
  std::vector<cv::Mat> ca, cb;
  cv::split(a, ca);
  cv::split(b, cb);
  cv::Mat mean = cv::Mat::zeros(a.size(), CV_32FC1);
  for (int c = 0; c < 3; ++c) mean += SsimMap(ca[c], cb[c]) / 3.0;
  const cv::Mat colour = SsimMap(a, b);
  EXPECT_LT(cv::norm(colour, mean, cv::NORM_INF), 1e-4);
  const double s = CompareImages(a, b).ssim;
  EXPECT_GT(s, 0.3);
  EXPECT_LT(s, 0.99);
}

}  // namespace
}  // namespace hdribr
