// Dense-cloud accuracy and completeness against ground truth, with the ICP refinement.
#include "eval/cloud_accuracy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"

namespace hdribr::eval {
namespace {

// A floor, a wall and a ball, sampled every 3 cm: no symmetry that ICP could slide along.
PointCloud Scene() {
  PointCloud c;
  const double step = 0.03;
  for (double x = -2; x <= 2; x += step) {
    for (double y = -2; y <= 2; y += step) c.positions.emplace_back(float(x), float(y), 0.f);
    for (double z = step; z <= 2; z += step) c.positions.emplace_back(-2.f, float(x), float(z));
  }
  for (double t = 0; t < M_PI; t += step / 0.5) {
    for (double p = 0; p < 2 * M_PI; p += step / 0.5) {
      const Eigen::Vector3d q =
          Eigen::Vector3d(0.5, 0.3, 0.5) +
          0.5 * Eigen::Vector3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      c.positions.push_back(q.cast<float>());
    }
  }
  return c;
}

// The GT points, jittered by 1 cm, every other one, with 1 % far outliers; returned in a
// reconstruction's frame (rec = 2 * R * gt + t) with the exact gt_from_rec.
PointCloud Reconstruction(const PointCloud& gt, Sim3d& gt_from_rec) {
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.f, 0.01f);
  std::uniform_real_distribution<float> far(5.f, 8.f);
  Sim3d rec_from_gt;
  rec_from_gt.scale = 2;
  rec_from_gt.rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  rec_from_gt.translation = Eigen::Vector3d(1, -2, 5);
  PointCloud rec;
  for (size_t i = 0; i < gt.size(); i += 2) {
    Eigen::Vector3d p = gt.positions[i].cast<double>();
    p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    if (i % 200 == 0) p = Eigen::Vector3d(far(rng), far(rng), far(rng));
    rec.positions.push_back((rec_from_gt * p).cast<float>());
  }
  gt_from_rec.scale = 1 / rec_from_gt.scale;
  gt_from_rec.rotation = rec_from_gt.rotation.transpose();
  gt_from_rec.translation = -(gt_from_rec.rotation * rec_from_gt.translation) / rec_from_gt.scale;
  return rec;
}

TEST(CloudAccuracy, ExactAlignmentScoresTheCloudAndIcpKeepsIt) {
  const PointCloud gt = Scene();
  Sim3d gt_from_rec;
  const PointCloud rec = Reconstruction(gt, gt_from_rec);
  const CloudAccuracy a = CompareClouds(rec, gt_from_rec, gt, 0.06);
  // 1 % outliers; nearly every GT point has a kept neighbour within 3 cm.
  EXPECT_NEAR(a.cameras.accuracy, 0.99, 0.002);
  EXPECT_GT(a.cameras.completeness, 0.995);
  EXPECT_NEAR(a.refined.accuracy, a.cameras.accuracy, 0.001);
  EXPECT_NEAR(a.refined.completeness, a.cameras.completeness, 0.001);
  EXPECT_LT(a.refinement_deg, 0.05);
  EXPECT_NEAR(a.refinement.scale, 1, 1e-3);
}

TEST(CloudAccuracy, IcpRemovesARotationTheCamerasLeft) {
  // The cameras' alignment off by 1.5 degrees about an axis 3 m from the scene (as a rotation
  // about the chord of an arc of views): up to 9 cm of error, beyond the 6 cm tolerance.
  const PointCloud gt = Scene();
  Sim3d exact;
  const PointCloud rec = Reconstruction(gt, exact);
  const Eigen::Matrix3d err =
      Eigen::AngleAxisd(1.5 * M_PI / 180, Eigen::Vector3d::UnitX()).matrix();
  const Eigen::Vector3d pivot(0, -3, 0);
  Sim3d off = exact;
  off.rotation = err * exact.rotation;
  off.translation = err * (exact.translation - pivot) + pivot;
  const CloudAccuracy a = CompareClouds(rec, off, gt, 0.06);
  EXPECT_LT(a.cameras.accuracy, 0.9);
  EXPECT_LT(a.cameras.completeness, 0.9);
  EXPECT_NEAR(a.refined.accuracy, 0.99, 0.002);
  EXPECT_GT(a.refined.completeness, 0.995);
  EXPECT_NEAR(a.refinement_deg, 1.5, 0.1);
}

TEST(CloudAccuracy, EmptyCloudsAreRefused) {
  const PointCloud gt = Scene();
  EXPECT_THROW(CompareClouds(PointCloud{}, Sim3d{}, gt, 0.06), UsageError);
  EXPECT_THROW(CompareClouds(gt, Sim3d{}, PointCloud{}, 0.06), UsageError);
}

}  // namespace
}  // namespace hdribr::eval
