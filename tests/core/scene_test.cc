#include "core/scene.h"

#include <gtest/gtest.h>

namespace hdribr {
namespace {

TEST(Scene, ScaleIsMedianCameraDistanceToCentroid) {
  Scene scene;
  scene.points.positions = {{-1, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, -2, 0}};
  const double distances[] = {2.0, 3.0, 10.0};
  for (double d : distances) {
    Photo p;
    p.cam_from_world =
        LookAt(Eigen::Vector3d(0, 0, -d), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0));
    scene.photos.push_back(p);
  }
  scene.UpdateDerived();
  EXPECT_TRUE(scene.centroid.isZero(1e-12));
  EXPECT_NEAR(scene.scene_scale, 3.0, 1e-9);
  EXPECT_TRUE(scene.point_bounds.valid);
  EXPECT_NEAR(scene.point_bounds.Diagonal(), std::sqrt(4.0 + 16.0), 1e-6);
}

TEST(PointCloud, ConsistencyChecksSizesAndFiniteness) {
  PointCloud pc;
  pc.positions = {{0, 0, 0}, {1, 1, 1}};
  EXPECT_TRUE(pc.IsConsistent());
  pc.radii = {0.1f};
  EXPECT_FALSE(pc.IsConsistent());
  pc.radii = {0.1f, 0.2f};
  EXPECT_TRUE(pc.IsConsistent());
  pc.positions[1].x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(pc.IsConsistent());
}

}  // namespace
}  // namespace hdribr
