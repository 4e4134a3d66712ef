#include "viewer/camera_controller.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hdribr::viewer {

Eigen::Vector3d SceneUp(const Scene& scene) {
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  for (const Photo& p : scene.photos) {
    up += p.cam_from_world.rotation.inverse() * Eigen::Vector3d(0, -1, 0);
  }
  if (up.norm() < 1e-9) return Eigen::Vector3d::UnitZ();
  return up.normalized();
}

int NearestPhoto(const Scene& scene, const Rigid3d& cam_from_world) {
  const Eigen::Vector3d centre = cam_from_world.Inverse().translation;
  const Eigen::Vector3d dir = cam_from_world.rotation.inverse() * Eigen::Vector3d::UnitZ();
  const double scale = scene.scene_scale > 0 ? scene.scene_scale : 1.0;
  int best = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    const Photo& p = scene.photos[i];
    const double d = (p.Center() - centre).norm() / scale;
    const double angle = std::acos(std::clamp(p.ViewDirection().dot(dir), -1.0, 1.0));
    const double cost = d + angle;
    if (cost < best_cost) {
      best_cost = cost;
      best = static_cast<int>(i);
    }
  }
  return best;
}

CameraController::CameraController(const Eigen::Vector3d& pivot, double scale,
                                   const Eigen::Vector3d& up)
    : pivot_(pivot), scale_(scale > 0 ? scale : 1.0), up_(up.normalized()) {
  // Default view: from one scale away, looking at the pivot.
  Eigen::Vector3d side = up_.unitOrthogonal();
  SetPose(LookAt(pivot_ + side * scale_, pivot_, up_));
  home_ = cam_from_world();
}

void CameraController::SetPose(const Rigid3d& cam_from_world) {
  world_from_cam_ = cam_from_world.rotation.inverse().normalized();
  eye_ = cam_from_world.Inverse().translation;
  transition_left_s_ = 0;
}

Rigid3d CameraController::cam_from_world() const {
  const Eigen::Quaterniond cam_from_world_rot = world_from_cam_.inverse();
  return {cam_from_world_rot, -(cam_from_world_rot * eye_)};
}

void CameraController::Orbit(double yaw_rad, double pitch_rad) {
  const Eigen::Vector3d right = world_from_cam_ * Eigen::Vector3d::UnitX();
  // Positive pitch moves the camera up (rotation about the camera's right axis, negated: y is
  // down in COLMAP cameras).
  const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(-yaw_rad, up_)) *
                               Eigen::Quaterniond(Eigen::AngleAxisd(-pitch_rad, right));
  eye_ = pivot_ + q * (eye_ - pivot_);
  world_from_cam_ = (q * world_from_cam_).normalized();
  transition_left_s_ = 0;
}

void CameraController::Look(double yaw_rad, double pitch_rad) {
  const Eigen::Vector3d right = world_from_cam_ * Eigen::Vector3d::UnitX();
  const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(-yaw_rad, up_)) *
                               Eigen::Quaterniond(Eigen::AngleAxisd(-pitch_rad, right));
  world_from_cam_ = (q * world_from_cam_).normalized();
  transition_left_s_ = 0;
}

void CameraController::Fly(const Eigen::Vector3d& local, double dt_s) {
  eye_ += world_from_cam_ * local * (speed_factor * scale_ * dt_s);
  transition_left_s_ = 0;
}

void CameraController::ZoomTowards(const Eigen::Vector3d& cam_ray, double steps) {
  if (cam_ray.norm() < 1e-12) return;
  const double distance = std::max((eye_ - pivot_).norm(), 0.01 * scale_);
  const double step = std::max(0.15 * distance, 0.01 * scale_);
  eye_ += (world_from_cam_ * cam_ray.normalized()) * (step * steps);
  transition_left_s_ = 0;
}

void CameraController::TransitionTo(const Rigid3d& cam_from_world, double duration_s) {
  if (duration_s <= 0) {
    SetPose(cam_from_world);
    return;
  }
  from_eye_ = eye_;
  from_rot_ = world_from_cam_;
  to_eye_ = cam_from_world.Inverse().translation;
  to_rot_ = cam_from_world.rotation.inverse().normalized();
  transition_s_ = transition_left_s_ = duration_s;
}

bool CameraController::Update(double dt_s) {
  if (transition_left_s_ <= 0) return false;
  transition_left_s_ = std::max(0.0, transition_left_s_ - dt_s);
  const double t = 1.0 - transition_left_s_ / transition_s_;
  const double s = t * t * (3 - 2 * t);  // smoothstep
  eye_ = from_eye_ + s * (to_eye_ - from_eye_);
  world_from_cam_ = from_rot_.slerp(s, to_rot_).normalized();
  return true;
}

}  // namespace hdribr::viewer
