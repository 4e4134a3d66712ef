// Umeyama similarity alignment: exact recovery, residuals, reflections, degenerate input.
#include "eval/alignment.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
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

TEST(AlignSimilarity, MatchesEigenUmeyamaWithNoiseAndReportsResiduals) {
  const auto src = RandomPoints(50, 2);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.01);
  const Eigen::Matrix3d r = Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3d> dst;
  Eigen::Matrix3Xd s(3, 50), d(3, 50);
  for (int i = 0; i < 50; ++i) {
    dst.push_back(0.5 * (r * src[i]) + Eigen::Vector3d(1, 2, 3) +
                  Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    s.col(i) = src[i];
    d.col(i) = dst[i];
  }
  const SimilarityAlignment a = AlignSimilarity(src, dst);
  const Eigen::Matrix4d ref = Eigen::umeyama(s, d, true);
  const double ref_scale = ref.topLeftCorner<3, 3>().col(0).norm();
  EXPECT_NEAR(a.dst_from_src.scale, ref_scale, 1e-9);
  EXPECT_TRUE(a.dst_from_src.rotation.isApprox(ref.topLeftCorner<3, 3>() / ref_scale, 1e-9));
  EXPECT_TRUE(a.dst_from_src.translation.isApprox(ref.topRightCorner<3, 1>(), 1e-9));
  // Residuals of isotropic noise with sigma 0.01: rms near sqrt(3) * 0.01.
  EXPECT_GT(a.rms, 0.01);
  EXPECT_LT(a.rms, 0.03);
  EXPECT_LE(a.median, a.max);
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
}

}  // namespace
}  // namespace hdribr
