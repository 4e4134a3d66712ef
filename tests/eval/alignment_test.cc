// Similarity alignment: exact recovery, noisy fit and residuals, reflections, degenerate input.
#include "eval/alignment.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace hdribr {
namespace {

std::vector<Eigen::Vector3d> RandomPoints(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < n; ++i) p.emplace_back(u(rng), u(rng), u(rng));
  return p;
}

TEST(AlignSimilarity, RecoversKnownTransformExactly) {
  const auto src = RandomPoints(20, 1);
  Sim3d truth;
  truth.scale = 3.7;
  truth.rotation =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  truth.translation = Eigen::Vector3d(4, -5, 6);
  std::vector<Eigen::Vector3d> dst;
  for (const auto& p : src) dst.push_back(truth * p);
  const SimilarityAlignment a = AlignSimilarity(src, dst);
  EXPECT_NEAR(a.dst_from_src.scale, 3.7, 1e-9);
  EXPECT_TRUE(a.dst_from_src.rotation.isApprox(truth.rotation, 1e-9));
  EXPECT_TRUE(a.dst_from_src.translation.isApprox(truth.translation, 1e-9));
  EXPECT_LT(a.max, 1e-9);
  ASSERT_EQ(a.residuals.size(), src.size());
}

TEST(AlignSimilarity, FitsNoisyPairsAndReportsResiduals) {
  const auto src = RandomPoints(50, 2);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.01);
  const Eigen::Matrix3d r = Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d translation(1, 2, 3);
  std::vector<Eigen::Vector3d> dst;
  for (const auto& p : src) {
    dst.push_back(0.5 * (r * p) + translation +
                  Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  }
  const SimilarityAlignment a = AlignSimilarity(src, dst);
  EXPECT_NEAR(a.dst_from_src.scale, 0.5, 0.01);
  EXPECT_LT(Eigen::AngleAxisd(a.dst_from_src.rotation * r.transpose()).angle(), 0.02);
  EXPECT_LT((a.dst_from_src.translation - translation).norm(), 0.01);
  // The fit is least squares: the true transform leaves larger residuals.
  double true_sum_sq = 0;
  for (size_t i = 0; i < src.size(); ++i) {
    true_sum_sq += (dst[i] - (0.5 * (r * src[i]) + translation)).squaredNorm();
  }
  EXPECT_LE(a.rms, std::sqrt(true_sum_sq / src.size()));
  // Residuals of isotropic noise with sigma 0.01: rms near sqrt(3) * 0.01.
  EXPECT_GT(a.rms, 0.01);
  EXPECT_LT(a.rms, 0.03);
  ASSERT_EQ(a.residuals.size(), src.size());
  EXPECT_LE(a.median, a.max);
  EXPECT_DOUBLE_EQ(a.max, *std::max_element(a.residuals.begin(), a.residuals.end()));
}

TEST(AlignSimilarity, NeverReturnsAReflection) {
  const auto src = RandomPoints(10, 4);
  std::vector<Eigen::Vector3d> dst;
  for (const auto& p : src) dst.emplace_back(p.x(), p.y(), -p.z());  // a mirror image
  const SimilarityAlignment a = AlignSimilarity(src, dst);
  EXPECT_NEAR(a.dst_from_src.rotation.determinant(), 1.0, 1e-9);
  EXPECT_GT(a.rms, 0.01);  // a mirror cannot be fitted by a rotation
}

TEST(AlignSimilarity, RejectsBadInput) {
  const auto src = RandomPoints(5, 5);
  EXPECT_THROW(AlignSimilarity(src, RandomPoints(4, 6)), std::invalid_argument);
  EXPECT_THROW(AlignSimilarity({src[0], src[1]}, {src[0], src[1]}), std::invalid_argument);
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 5; ++i) line.emplace_back(i, 2 * i, 0);
  EXPECT_THROW(AlignSimilarity(line, line), std::invalid_argument);
  const std::vector<Eigen::Vector3d> point(5, Eigen::Vector3d(1, 2, 3));
  EXPECT_THROW(AlignSimilarity(src, point), std::invalid_argument);
}

}  // namespace
}  // namespace hdribr
