// Viewer navigation as pure math (no GL): orbit around a pivot, fly, look around, zoom towards a
// cursor ray, snapping to photos with smooth transitions. Poses follow COLMAP conventions
// (camera x right, y down, z forward); speeds are multiples of the scene scale. The state and
// the math are GLM (double precision); the API takes and returns core's Eigen types.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "core/rigid3.h"
#include "core/scene.h"

namespace hdribr::viewer {

// World "up" of a capture: the mean of the photos' camera -y axes (normalised); +z when none.
Eigen::Vector3d SceneUp(const Scene& scene);

class CameraController {
 public:
  // pivot: orbit centre (world); scale: scene scale (metres or SfM units); up: world up.
  CameraController(const Eigen::Vector3d& pivot, double scale, const Eigen::Vector3d& up);

  void SetPose(const Rigid3d& cam_from_world);  // immediate, cancels any transition
  Rigid3d cam_from_world() const;
  Eigen::Vector3d eye() const;  // camera centre (world)
  Eigen::Vector3d pivot() const;
  // The pose Reset() returns to (the constructor's default view until set).
  void SetHome(const Rigid3d& cam_from_world);
  void Reset(double duration_s = 0.5);

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
  // A viewpoint as the controller moves it: camera centre and camera-to-world rotation.
  struct Pose {
    glm::dvec3 eye{0.0};
    glm::dquat world_from_cam{1.0, 0.0, 0.0, 0.0};
  };
  static Pose FromCamFromWorld(const Rigid3d& cam_from_world);
  void Set(const Pose& pose);
  void StartTransition(const Pose& to, double duration_s);

  glm::dvec3 pivot_;
  double scale_;
  glm::dvec3 up_;  // unit
  Pose pose_;
  Pose home_;
  Pose from_, to_;  // transition end points
  double transition_s_ = 0, transition_left_s_ = 0;
};

}  // namespace hdribr::viewer
