// The scene's dominant plane (the ground, a wall): a background surface beyond the points'
// holes, where the points say the scene is flat.
#pragma once

#include <Eigen/Core>

#include "core/scene.h"

namespace hdribr {

// Inlier distance of the plane fit, in scene scales.
inline constexpr double kDominantPlaneTolerance = 0.01;
// Widening of the extent on each side, as a share of its length: the dense stage's points thin
// out toward a surface's edges, where its texture falls under the stage's floor.
inline constexpr double kDominantPlaneMargin = 0.1;
// Least share of the points on the plane for it to count as the scene's dominant plane.
inline constexpr double kDominantPlaneMinShare = 0.05;

// A plane n . X + offset = 0 (world frame, unit n, the cameras on its positive side), bounded to
// the rectangle of its points along its two in-plane axes, widened by kDominantPlaneMargin.
struct DominantPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double offset = 0.0;
  Eigen::Vector3d axis_u = Eigen::Vector3d::Zero();  // in-plane principal axes of the inliers
  Eigen::Vector3d axis_v = Eigen::Vector3d::Zero();
  Eigen::Vector4d extent = Eigen::Vector4d::Zero();  // u min, u max, v min, v max (world units)
  double inlier_share = 0.0;  // of the points within kDominantPlaneTolerance of the plane (0: none)

  // True when the plane holds enough of the points to serve as the background.
  bool valid() const { return inlier_share >= kDominantPlaneMinShare; }
};

// The plane holding the most points (RANSAC, Fischler & Bolles 1981, on at most 50 000 of them,
// refined by least squares on its inliers) among those with at least 90 % of the cameras on one
// side (a surface the photos face: a plane through the cameras is no background); its extent
// is the 1st to 99th percentile of its inliers along its axes, widened by kDominantPlaneMargin.
// Invalid without one holding kDominantPlaneMinShare of the points. Deterministic.
DominantPlane FindDominantPlane(const Scene& scene);

}  // namespace hdribr
