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

// Three photos looking at the origin from -z at distances 2, 3 and 10, and one from +x.
Scene RingScene() {
  Scene scene;
  scene.points.positions = {{-1, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, -2, 0}};
  for (double d : {2.0, 3.0, 10.0}) {
    Photo p;
    p.cam_from_world =
        LookAt(Eigen::Vector3d(0, 0, -d), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0));
    scene.photos.push_back(p);
  }
  Photo side;
  side.cam_from_world =
      LookAt(Eigen::Vector3d(2.5, 0, 0), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0));
  scene.photos.push_back(side);
  scene.UpdateDerived();
  return scene;
}

TEST(Scene, NearestPhotoWeighsCentreDistanceAndViewDirection) {
  const Scene scene = RingScene();
  EXPECT_EQ(scene.NearestPhoto(scene.photos[1].cam_from_world), 1);  // a photo's own view
  // 2.6 units out on -z, looking at the origin: photo 1 (3.0, same direction) is nearest.
  const Rigid3d view =
      LookAt(Eigen::Vector3d(0, 0, -2.6), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(scene.NearestPhoto(view), 1);
  // Beside the side photo, looking at the origin: the side photo; without it, photo 0 (the
  // nearer of the -z photos, at the same angle).
  const Rigid3d side =
      LookAt(Eigen::Vector3d(2.4, 0, -0.3), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(scene.NearestPhoto(side), 3);
  EXPECT_EQ(scene.NearestPhoto(side, {0, 1, 2}), 0);
  // Among candidates only; none gives -1.
  EXPECT_EQ(scene.NearestPhoto(view, {0, 2, 3}), 0);
  EXPECT_EQ(scene.NearestPhoto(view, {}), -1);
  EXPECT_EQ(Scene().NearestPhoto(view), -1);
}

TEST(Scene, RelativeExposureIsTheSeriesWhenThePhotoHasOne) {
  Scene scene = RingScene();
  scene.photos[0].exposure.time_s = 1.0 / 100;
  scene.photos[0].exposure.iso = 100;
  scene.photos[0].exposure.f_number = 1;
  EXPECT_NEAR(scene.RelativeExposureOf(scene.photos[0]), scene.photos[0].exposure.Relative(),
              1e-15);
  ExposureSeries series;
  series.relative_exposure = 0.25;
  series.photo_indices = {0};
  scene.series.push_back(series);
  scene.photos[0].series_id = 0;
  EXPECT_DOUBLE_EQ(scene.RelativeExposureOf(scene.photos[0]), 0.25);
  scene.photos[0].series_id = 7;  // out of range: the photo's own
  EXPECT_NEAR(scene.RelativeExposureOf(scene.photos[0]), 0.01, 1e-15);
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
