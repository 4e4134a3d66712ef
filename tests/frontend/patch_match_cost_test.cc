#include "frontend/patch_match_cost.h"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace hdribr::patch_match {
namespace {

cv::Mat Noise(int w, int h, int seed) {
  cv::Mat m(h, w, CV_32F);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::GaussianBlur(m, m, cv::Size(5, 5), 1.2);
  return m;
}

// The weighted NCC cost sample by sample in double: each window point through the homography,
// clamped into the image, interpolated bilinearly; then the weighted mean (the weights b sum to
// 1), variance and covariance.
double ReferenceCost(const cv::Mat& img, const WindowGrid& win, const Mat3& hm, int x, int y,
                     const RefWindow& ref) {
  std::vector<double> samples;
  double mean = 0;
  for (int k = 0; k < win.samples; ++k) {
    const Eigen::Vector3d p =
        hm.cast<double>() * Eigen::Vector3d(x + win.dx[k], y + win.dy[k], 1.0);
    const double u = std::clamp(p.x() / p.z(), 0.0, img.cols - 1.001);
    const double v = std::clamp(p.y() / p.z(), 0.0, img.rows - 1.001);
    const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
    const double fx = u - x0, fy = v - y0;
    const auto at = [&](int yy, int xx) { return static_cast<double>(img.at<float>(yy, xx)); };
    const double top = at(y0, x0) + fx * (at(y0, x0 + 1) - at(y0, x0));
    const double bottom = at(y0 + 1, x0) + fx * (at(y0 + 1, x0 + 1) - at(y0 + 1, x0));
    samples.push_back(top + fy * (bottom - top));
    mean += ref.b[k] * samples.back();
  }
  double var = 0, cov = 0;
  for (int k = 0; k < win.samples; ++k) {
    var += ref.b[k] * (samples[k] - mean) * (samples[k] - mean);
    cov += ref.a[k] * (samples[k] - mean);
  }
  if (!(var > kMinVariance)) return kMaxCost;
  return 1.0 - std::clamp(cov / std::sqrt(var), -1.0, 1.0);
}

TEST(PatchMatchCost, FastNccEqualsTheReferenceOnRandomPatches) {
  LevelImage ref_image{Noise(64, 48, 1), Mat3::Identity(), Mat3::Identity()};
  const cv::Mat src = Noise(80, 60, 2);
  cv::RNG rng(5);
  for (int radius : {3, 5}) {
    const WindowGrid win = MakeWindow(radius, 2);
    ASSERT_EQ(win.padded % 4, 0);
    ASSERT_EQ(static_cast<int>(win.dx.size()), win.padded);
    Level lv;
    lv.ref = &ref_image;
    lv.window = &win;
    lv.w = ref_image.gray.cols;
    lv.h = ref_image.gray.rows;
    lv.inv_two_sigma_color2 = 1.f / (2 * 0.1f * 0.1f);
    int compared = 0;
    for (int t = 0; t < 2000; ++t) {
      const int x = rng.uniform(0, lv.w), y = rng.uniform(0, lv.h);
      RefWindow w;
      if (!PrepareWindow(lv, x, y, w)) continue;
      // A homography near a similarity, with some perspective, mapping into or across the
      // source's border.
      const float a = static_cast<float>(rng.uniform(0.0, 2 * M_PI));
      const float s = static_cast<float>(rng.uniform(0.6, 1.6));
      Mat3 hm;
      hm << s * std::cos(a), -s * std::sin(a), static_cast<float>(rng.uniform(-20.0, 60.0)),
          s * std::sin(a), s * std::cos(a), static_cast<float>(rng.uniform(-20.0, 50.0)),
          static_cast<float>(rng.uniform(-2e-3, 2e-3)),
          static_cast<float>(rng.uniform(-2e-3, 2e-3)), 1.f;
      hm *= static_cast<float>(rng.uniform(0.5, 2.0));  // homogeneous scale: the same mapping
      const float fast = SourcePhotoCost(src, win, hm, x, y, w);
      const double reference = ReferenceCost(src, win, hm, x, y, w);
      EXPECT_NEAR(fast, reference, 1e-5) << "radius " << radius << " pixel " << x << "," << y;
      ++compared;
    }
    EXPECT_GT(compared, 1000);
  }
}

TEST(PatchMatchCost, FlatPatchesCostTheMaximum) {
  LevelImage ref_image{Noise(32, 32, 3), Mat3::Identity(), Mat3::Identity()};
  const WindowGrid win = MakeWindow(5, 2);
  Level lv;
  lv.ref = &ref_image;
  lv.window = &win;
  lv.w = lv.h = 32;
  RefWindow w;
  ASSERT_TRUE(PrepareWindow(lv, 16, 16, w));
  const cv::Mat flat(32, 32, CV_32F, cv::Scalar(0.5f));
  EXPECT_EQ(SourcePhotoCost(flat, win, Mat3::Identity(), 16, 16, w), kMaxCost);
}

// Two sources with their own offsets: the plane's cost with a bound is the plain cost where
// below the bound, and at least the bound where the plain cost is.
TEST(PatchMatchCost, EarlyTerminationNeverChangesTheOutcome) {
  LevelImage ref_image{Noise(64, 48, 4), Mat3::Identity(), Mat3::Identity()};
  ref_image.k << 60, 0, 32, 0, 60, 24, 0, 0, 1;
  ref_image.k_inv = ref_image.k.inverse();
  std::vector<LevelImage> images;
  for (int i = 0; i < 4; ++i)
    images.push_back({Noise(64, 48, 10 + i), ref_image.k, ref_image.k_inv});
  const WindowGrid win = MakeWindow(5, 2);
  Level lv;
  lv.ref = &ref_image;
  lv.window = &win;
  lv.w = 64;
  lv.h = 48;
  lv.depth_min = 1;
  lv.depth_max = 10;
  lv.inv_two_sigma_color2 = 1.f / (2 * 0.1f * 0.1f);
  for (int i = 0; i < 4; ++i) {
    SourceView v;
    v.image = &images[i];
    v.rotation = Mat3::Identity();
    v.translation = Vec3(0.1f * (i + 1) * (i % 2 ? 1 : -1), 0.05f * i, 0);
    v.a = v.image->k * v.rotation * ref_image.k_inv;
    v.b = v.image->k * v.translation;
    v.depth_k = v.depth_k_inv = Mat3::Identity();  // no geometric term here
    lv.sources.push_back(v);
  }
  lv.best_views = 2;
  cv::RNG rng(9);
  int terminated = 0, below = 0;
  for (int t = 0; t < 3000; ++t) {
    const int x = rng.uniform(0, lv.w), y = rng.uniform(0, lv.h);
    RefWindow w;
    if (!PrepareWindow(lv, x, y, w)) continue;
    const Vec3 ray = ref_image.k_inv * Vec3(float(x), float(y), 1.f);
    const float d = static_cast<float>(rng.uniform(1.0, 10.0));
    const Vec3 n = Vec3(static_cast<float>(rng.uniform(-0.5, 0.5)),
                        static_cast<float>(rng.uniform(-0.5, 0.5)), -1.f)
                       .normalized();
    float ncc = 0, ncc_bounded = 0;
    const float plain = PlaneCost(lv, x, y, ray, d, n, w, kNoCost, &ncc);
    const float bound = static_cast<float>(rng.uniform(0.0, 1.5));
    const float bounded = PlaneCost(lv, x, y, ray, d, n, w, bound, &ncc_bounded);
    if (plain < bound) {
      EXPECT_EQ(bounded, plain);
      EXPECT_EQ(ncc_bounded, ncc);
      ++below;
    } else {
      EXPECT_GE(bounded, bound);
      terminated += bounded != plain;
    }
  }
  EXPECT_GT(below, 100);
  EXPECT_GT(terminated, 100);  // the bound does skip sources
}

}  // namespace
}  // namespace hdribr::patch_match
