// Rigid transform y = R x + t, named by direction at use sites (cam_from_world, ...).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hdribr {

struct Rigid3d {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Rigid3d() = default;
  Rigid3d(const Eigen::Quaterniond& r, const Eigen::Vector3d& t) : rotation(r), translation(t) {}

  Eigen::Vector3d operator*(const Eigen::Vector3d& x) const { return rotation * x + translation; }
  // a_from_b * b_from_c = a_from_c.
  Rigid3d operator*(const Rigid3d& b_from_c) const {
    return {rotation * b_from_c.rotation, rotation * b_from_c.translation + translation};
  }
  Rigid3d Inverse() const {
    const Eigen::Quaterniond inv = rotation.inverse();
    return {inv, -(inv * translation)};
  }
  // 3x4 matrix [R | t].
  Eigen::Matrix<double, 3, 4> Matrix() const;
  // 4x4 homogeneous matrix.
  Eigen::Matrix4d Matrix4() const;
};

// True when q has unit norm within tol (COLMAP stores unit quaternions) and finite entries.
bool IsValidRotation(const Eigen::Quaterniond& q, double tol = 1e-3);

// Rotation that looks from eye to target in COLMAP camera axes (x right, y down, z forward);
// `up` is the world up direction. Returns cam_from_world.
Rigid3d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
               const Eigen::Vector3d& up);

}  // namespace hdribr
