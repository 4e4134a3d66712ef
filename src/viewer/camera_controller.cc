#include "viewer/camera_controller.h"

#include <algorithm>
#include <glm/geometric.hpp>

#include "viewer/glm_eigen.h"

namespace hdribr::viewer {

Eigen::Vector3d SceneUp(const Scene& scene) {
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  for (const Photo& p : scene.photos) {
    up += p.cam_from_world.rotation.inverse() * Eigen::Vector3d(0, -1, 0);
  }
  if (up.norm() < 1e-9) return Eigen::Vector3d::UnitZ();
  return up.normalized();
}

CameraController::CameraController(const Eigen::Vector3d& pivot, double scale,
                                   const Eigen::Vector3d& up)
    : pivot_(ToGlm(pivot)), scale_(scale > 0 ? scale : 1.0), up_(ToGlm(up.normalized())) {
  // Default view: from one scale away, looking at the pivot.
  const Eigen::Vector3d side = up.normalized().unitOrthogonal();
  SetPose(LookAt(pivot + side * scale_, pivot, up.normalized()));
  home_ = pose_;
}

CameraController::Pose CameraController::FromCamFromWorld(const Rigid3d& cam_from_world) {
  return {ToGlm(cam_from_world.Inverse().translation),
          glm::normalize(glm::inverse(ToGlm(cam_from_world.rotation)))};
}

void CameraController::Set(const Pose& pose) {
  pose_ = pose;
  transition_left_s_ = 0;
}

void CameraController::SetPose(const Rigid3d& cam_from_world) {
  Set(FromCamFromWorld(cam_from_world));
}

Rigid3d CameraController::cam_from_world() const {
  const glm::dquat cam_from_world_rot = glm::inverse(pose_.world_from_cam);
  return {ToEigen(cam_from_world_rot), ToEigen(-(cam_from_world_rot * pose_.eye))};
}

Eigen::Vector3d CameraController::eye() const { return ToEigen(pose_.eye); }

Eigen::Vector3d CameraController::pivot() const { return ToEigen(pivot_); }

void CameraController::SetHome(const Rigid3d& cam_from_world) {
  home_ = FromCamFromWorld(cam_from_world);
}

void CameraController::Reset(double duration_s) { StartTransition(home_, duration_s); }

void CameraController::Orbit(double yaw_rad, double pitch_rad) {
  const glm::dvec3 right = pose_.world_from_cam * glm::dvec3(1, 0, 0);
  // Positive pitch moves the camera up (rotation about the camera's right axis, negated: y is
  // down in COLMAP cameras).
  const glm::dquat q = glm::angleAxis(-yaw_rad, up_) * glm::angleAxis(-pitch_rad, right);
  Set({pivot_ + q * (pose_.eye - pivot_), glm::normalize(q * pose_.world_from_cam)});
}

void CameraController::Look(double yaw_rad, double pitch_rad) {
  const glm::dvec3 right = pose_.world_from_cam * glm::dvec3(1, 0, 0);
  const glm::dquat q = glm::angleAxis(-yaw_rad, up_) * glm::angleAxis(-pitch_rad, right);
  Set({pose_.eye, glm::normalize(q * pose_.world_from_cam)});
}

void CameraController::Fly(const Eigen::Vector3d& local, double dt_s) {
  const glm::dvec3 world = pose_.world_from_cam * ToGlm(local);
  Set({pose_.eye + world * (speed_factor * scale_ * dt_s), pose_.world_from_cam});
}

void CameraController::ZoomTowards(const Eigen::Vector3d& cam_ray, double steps) {
  const glm::dvec3 ray = ToGlm(cam_ray);
  if (glm::length(ray) < 1e-12) return;
  const double distance = std::max(glm::distance(pose_.eye, pivot_), 0.01 * scale_);
  const double step = std::max(0.15 * distance, 0.01 * scale_);
  const glm::dvec3 world_ray = pose_.world_from_cam * glm::normalize(ray);
  Set({pose_.eye + world_ray * (step * steps), pose_.world_from_cam});
}

void CameraController::TransitionTo(const Rigid3d& cam_from_world, double duration_s) {
  StartTransition(FromCamFromWorld(cam_from_world), duration_s);
}

void CameraController::StartTransition(const Pose& to, double duration_s) {
  if (duration_s <= 0) {
    Set(to);
    return;
  }
  from_ = pose_;
  to_ = to;
  transition_s_ = transition_left_s_ = duration_s;
}

bool CameraController::Update(double dt_s) {
  if (transition_left_s_ <= 0) return false;
  transition_left_s_ = std::max(0.0, transition_left_s_ - dt_s);
  const double t = 1.0 - transition_left_s_ / transition_s_;
  const double s = t * t * (3 - 2 * t);  // smoothstep
  // slerp takes the shorter arc (q and -q are the same rotation).
  pose_.eye = glm::mix(from_.eye, to_.eye, s);
  pose_.world_from_cam = glm::normalize(glm::slerp(from_.world_from_cam, to_.world_from_cam, s));
  return true;
}

}  // namespace hdribr::viewer
