#include "core/rigid3.h"

#include <cmath>

namespace hdribr {

Eigen::Matrix<double, 3, 4> Rigid3d::Matrix() const {
  Eigen::Matrix<double, 3, 4> m;
  m.leftCols<3>() = rotation.toRotationMatrix();
  m.col(3) = translation;
  return m;
}

Eigen::Matrix4d Rigid3d::Matrix4() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topRows<3>() = Matrix();
  return m;
}

bool IsValidRotation(const Eigen::Quaterniond& q, double tol) {
  if (!q.coeffs().allFinite()) return false;
  return std::abs(q.norm() - 1.0) <= tol;
}

Rigid3d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
               const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = (target - eye).normalized();  // forward
  Eigen::Vector3d x = z.cross(up);                        // right (y is down)
  if (x.squaredNorm() < 1e-12) x = z.unitOrthogonal();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);  // down
  Eigen::Matrix3d world_from_cam_r;
  world_from_cam_r.col(0) = x;
  world_from_cam_r.col(1) = y;
  world_from_cam_r.col(2) = z;
  const Eigen::Matrix3d r = world_from_cam_r.transpose();
  return {Eigen::Quaterniond(r).normalized(), -(r * eye)};
}

}  // namespace hdribr
