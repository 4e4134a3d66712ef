// Viewer navigation as pure math (no GL): orbit around a pivot, fly, look around, zoom towards a
// cursor ray, snapping to photos with smooth transitions. Poses follow COLMAP conventions
// (camera x right, y down, z forward); speeds are multiples of the scene scale.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/rigid3.h"
#include "core/scene.h"

namespace hdribr::viewer {

// World "up" of a capture: the mean of the photos' camera -y axes (normalised); +z when none.
Eigen::Vector3d SceneUp(const Scene& scene);

// Index of the photo whose viewpoint is nearest `cam_from_world`: centre distance (in scene
// scale units) plus the angle between view directions (radians); -1 for a scene without photos.
int NearestPhoto(const Scene& scene, const Rigid3d& cam_from_world);

class CameraController {
 public:
  // pivot: orbit centre (world); scale: scene scale (metres or SfM units); up: world up.
  CameraController(const Eigen::Vector3d& pivot, double scale, const Eigen::Vector3d& up);

  void SetPose(const Rigid3d& cam_from_world);  // immediate, cancels any transition
  Rigid3d cam_from_world() const;
  Eigen::Vector3d eye() const { return eye_; }
  const Eigen::Vector3d& pivot() const { return pivot_; }
  // The pose Reset() returns to (the first pose set, or the constructor's default view).
  void SetHome(const Rigid3d& cam_from_world) { home_ = cam_from_world; }
  void Reset(double duration_s = 0.5) { TransitionTo(home_, duration_s); }

  // Orbit around the pivot: yaw about world up, pitch about the camera's x axis (radians).
  void Orbit(double yaw_rad, double pitch_rad);
  // Rotate in place (fly mode mouse look), same axes as Orbit.
  void Look(double yaw_rad, double pitch_rad);
  // Moves along camera axes: local = (right, down, forward) in [-1, 1], for dt seconds at
  // speed_factor x scale per second.
  void Fly(const Eigen::Vector3d& local, double dt_s);
  // Moves `steps` (>0 closer) along the camera-space ray `cam_ray` (e.g. through the cursor),
  // each step 15% of the distance to the pivot, at least 1% of the scale.
  void ZoomTowards(const Eigen::Vector3d& cam_ray, double steps);

  // Smooth transition (smoothstep in time: slerp rotation, lerp centre).
  void TransitionTo(const Rigid3d& cam_from_world, double duration_s);
  // Advances a transition; returns true when the pose changed.
  bool Update(double dt_s);
  bool transitioning() const { return transition_left_s_ > 0; }

  double speed_factor = 0.5;  // fly speed in scene scales per second

 private:
  Eigen::Vector3d pivot_;
  double scale_;
  Eigen::Vector3d up_;
  Eigen::Vector3d eye_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond world_from_cam_ = Eigen::Quaterniond::Identity();
  Rigid3d home_;
  // Transition state.
  Eigen::Vector3d from_eye_, to_eye_;
  Eigen::Quaterniond from_rot_, to_rot_;
  double transition_s_ = 0, transition_left_s_ = 0;
};

}  // namespace hdribr::viewer
