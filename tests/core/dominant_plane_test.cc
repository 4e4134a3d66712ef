#include "core/dominant_plane.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/rigid3.h"

namespace hdribr {
namespace {

// A scene of `cameras` photos on a circle of radius 8 at height `height` (z up), looking at
// the origin, and no points.
Scene CirclingCameras(int cameras, double height) {
  Scene scene;
  scene.cameras.emplace(1, Camera::Pinhole(1, 64, 48, 50, 50, 32, 24));
  for (int i = 0; i < cameras; ++i) {
    const double a = 2.0 * M_PI * i / cameras;
    Photo p;
    p.camera_id = 1;
    p.cam_from_world = LookAt(Eigen::Vector3d(8 * std::cos(a), 8 * std::sin(a), height),
                              Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1));
    scene.photos.push_back(p);
  }
  return scene;
}

// n points uniform in the box [lo, hi].
void AddBox(PointCloud& cloud, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int n,
            std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3f t(u(rng), u(rng), u(rng));
    cloud.positions.push_back(lo + t.cwiseProduct(hi - lo));
  }
}

// The ground under an object: the plane z = 0 found under the cameras, facing them, its
// extent the ground's points widened by the margin; the object's points do not tilt it.
TEST(DominantPlane, FindsTheGroundUnderAnObject) {
  Scene scene = CirclingCameras(12, 1.6);
  std::mt19937 rng(3);
  AddBox(scene.points, {-4, -2, -0.005f}, {4, 2, 0.005f}, 20000, rng);  // ground, 8 x 4
  AddBox(scene.points, {-1, -1, 0.1f}, {1, 1, 2}, 15000, rng);          // the object
  scene.UpdateDerived();
  const DominantPlane plane = FindDominantPlane(scene);
  ASSERT_TRUE(plane.valid());
  EXPECT_GT(plane.normal.z(), 0.999);  // toward the cameras
  EXPECT_NEAR(plane.offset, 0.0, 0.01);
  EXPECT_NEAR(plane.inlier_share, 20000.0 / 35000.0, 0.03);
  // The long axis first: 8 m of ground between the 1st and 99th percentiles (7.84 m), widened.
  const double long_side = (1.0 + 2.0 * kDominantPlaneMargin) * 0.98 * 8.0;
  const double short_side = (1.0 + 2.0 * kDominantPlaneMargin) * 0.98 * 4.0;
  EXPECT_NEAR(std::abs(plane.axis_u.x()), 1.0, 0.01);
  EXPECT_NEAR(plane.extent[1] - plane.extent[0], long_side, 0.1);
  EXPECT_NEAR(plane.extent[3] - plane.extent[2], short_side, 0.1);
  EXPECT_NEAR(plane.axis_u.dot(plane.normal), 0.0, 1e-9);
  EXPECT_NEAR(plane.axis_v.dot(plane.normal), 0.0, 1e-9);
  // The same cloud again: the same plane.
  const DominantPlane again = FindDominantPlane(scene);
  EXPECT_EQ(again.normal, plane.normal);
  EXPECT_EQ(again.extent, plane.extent);
}

// A plane with cameras on both sides (a wall the photos circle) is no background, nor is a
// cloud without a plane holding enough of its points.
TEST(DominantPlane, NoneWithoutAPlaneThePhotosFace) {
  std::mt19937 rng(5);
  Scene wall = CirclingCameras(12, 0.0);
  AddBox(wall.points, {-0.005f, -3, -3}, {0.005f, 3, 3}, 20000, rng);  // the plane x = 0
  wall.UpdateDerived();
  EXPECT_FALSE(FindDominantPlane(wall).valid());
  Scene cloud = CirclingCameras(12, 1.6);
  AddBox(cloud.points, {-3, -3, 0.5f}, {3, 3, 6.5f}, 20000, rng);
  cloud.UpdateDerived();
  EXPECT_FALSE(FindDominantPlane(cloud).valid());
  Scene empty = CirclingCameras(12, 1.6);
  empty.UpdateDerived();
  EXPECT_FALSE(FindDominantPlane(empty).valid());
}

}  // namespace
}  // namespace hdribr
