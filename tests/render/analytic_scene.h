// Analytic test scenes for the depth pass: points sampled on spheres and a plane, with exact
// normals and radii, and ground-truth depth by ray casting the same surfaces.
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "core/camera.h"
#include "core/point_cloud.h"
#include "core/rigid3.h"
#include "core/scene.h"

namespace hdribr::test {

struct Sphere {
  Eigen::Vector3d centre;
  double radius;
};

// An optional plane z = plane_z (world), |x|, |y| <= plane_half.
struct AnalyticScene {
  std::vector<Sphere> spheres;
  bool has_plane = false;
  double plane_z = 0.0;
  double plane_half = 0.0;

  // Two overlapping spheres in front of a plane (seen from the origin looking along +z).
  static AnalyticScene SpheresAndPlane();
  // The same spheres without the plane (silhouettes against empty background).
  static AnalyticScene SpheresOnly();

  double Area() const;
  // About `count` points uniformly at random over the surfaces (fixed seed), with unit normals
  // and radius `radius_factor` times the mean point spacing.
  PointCloud Sample(int count, double radius_factor = 1.25, unsigned seed = 7) const;
  // Camera z of the nearest surface through each pixel centre (CV_32FC1, 0 = no surface).
  cv::Mat GroundTruthDepth(const Camera& camera, const Rigid3d& cam_from_world) const;
};

// 256x256 pinhole camera with a 58 degree field of view.
Camera TestCamera(int size = 256);

// `count` poses `distance` from `centre` in directions on the half sphere facing the plane's
// front (z < 0; a Fibonacci spiral, each at least acos 0.15 off the plane), looking at `centre`.
std::vector<Rigid3d> DomePoses(int count, double distance, const Eigen::Vector3d& centre,
                               const Eigen::Vector3d& up);

// Colour (8-bit BGR) of the surface point p (world) in a photo.
using SurfaceShade = std::function<cv::Vec3b(const Eigen::Vector3d& p, const Photo& photo)>;

// A scene of `points` points sampled on `analytic` and, in `images`, one photo per pose ray-cast
// through `camera` (camera 1; photos p0.png, p1.png, ...; black where no surface is).
Scene PhotographScene(const AnalyticScene& analytic, const Camera& camera,
                      const std::vector<Rigid3d>& poses, int points, const SurfaceShade& shade,
                      std::vector<cv::Mat>& images);

// Pixels within `radius` pixels of a GT coverage edge (CV_8UC1, 255 = in the band).
cv::Mat SilhouetteBand(const cv::Mat& gt, int radius = 2);

}  // namespace hdribr::test
