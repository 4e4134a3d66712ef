#include "core/rigid3.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hdribr {
namespace {

TEST(Rigid3d, InverseAndCompose) {
  const Rigid3d b_from_a(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())),
      Eigen::Vector3d(0.5, -1, 2));
  const Eigen::Vector3d x(0.1, 0.2, 0.3);
  EXPECT_TRUE((b_from_a.Inverse() * (b_from_a * x)).isApprox(x, 1e-12));
  EXPECT_TRUE(((b_from_a * b_from_a.Inverse()) * x).isApprox(x, 1e-12));
  EXPECT_TRUE(b_from_a.Matrix4().inverse().isApprox(b_from_a.Inverse().Matrix4(), 1e-12));
}

TEST(Rigid3d, RotationValidity) {
  EXPECT_TRUE(IsValidRotation(Eigen::Quaterniond::Identity()));
  EXPECT_FALSE(IsValidRotation(Eigen::Quaterniond(2, 0, 0, 0)));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(IsValidRotation(Eigen::Quaterniond(nan, 0, 0, 0)));
}

TEST(Rigid3d, LookAtUsesColmapAxes) {
  const Eigen::Vector3d eye(0, 0, -5);
  const Rigid3d cam_from_world = LookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0));
  // The target is straight ahead (+z), world up is image up (-y in camera frame).
  const Eigen::Vector3d target_cam = cam_from_world * Eigen::Vector3d::Zero();
  EXPECT_NEAR(target_cam.x(), 0, 1e-12);
  EXPECT_NEAR(target_cam.y(), 0, 1e-12);
  EXPECT_NEAR(target_cam.z(), 5, 1e-12);
  const Eigen::Vector3d above = cam_from_world * Eigen::Vector3d(0, 1, 0);
  EXPECT_LT(above.y(), 0);
  EXPECT_TRUE(cam_from_world.Inverse().translation.isApprox(eye, 1e-12));
  EXPECT_NEAR(cam_from_world.rotation.toRotationMatrix().determinant(), 1.0, 1e-12);
}

}  // namespace
}  // namespace hdribr
