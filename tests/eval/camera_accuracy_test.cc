// Camera accuracy against ground truth: similarity-aligned centres and rotations.
#include "eval/camera_accuracy.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace hdribr::eval {
namespace {

ColmapImage Image(const std::string& name, const Eigen::Vector3d& centre, double yaw) {
  ColmapImage im;
  im.name = name;
  const Eigen::Quaterniond r(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()));
  im.cam_from_world = Rigid3d(r, -(r * centre));
  return im;
}

// Five cameras on an arc (GT), and the same cameras in another frame: scaled by 2.5, rotated
// about z and shifted, as an SfM reconstruction would place them.
struct Models {
  ColmapModel gt, rec;
};

Models ArcModels() {
  Models m;
  const Eigen::Quaterniond frame(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d shift(3, -1, 4);
  for (int i = 0; i < 5; ++i) {
    const double a = 0.3 * i;
    const Eigen::Vector3d c(4 * std::sin(a), 0.2 * i, -4 * std::cos(a));
    const ColmapImage g = Image("p" + std::to_string(i) + ".jpg", c, -a);
    m.gt.images[i + 1] = g;
    ColmapImage r = g;
    // rec_from_gt: x_rec = 2.5 * frame * x_gt + shift; cam_from_rec = cam_from_gt * gt_from_rec.
    const Eigen::Vector3d c_rec = 2.5 * (frame * c) + shift;
    const Eigen::Quaterniond rot = g.cam_from_world.rotation * frame.inverse();
    r.cam_from_world = Rigid3d(rot, -(rot * c_rec));
    m.rec.images[10 + i] = r;  // other ids: matched by name
  }
  return m;
}

TEST(CameraAccuracy, ExactSimilarityGivesZeroErrors) {
  const Models m = ArcModels();
  const CameraAccuracy a = CompareCameras(m.rec, m.gt);
  EXPECT_EQ(a.matched, 5);
  EXPECT_EQ(a.gt_images, 5);
  EXPECT_TRUE(a.missing.empty());
  EXPECT_NEAR(a.alignment.dst_from_src.scale, 1 / 2.5, 1e-9);
  EXPECT_LT(a.alignment.max, 1e-9);
  EXPECT_LT(a.rotation_max_deg, 1e-6);
  EXPECT_GT(a.extent, 1.0);
}

TEST(CameraAccuracy, ErrorsAndMissingPhotosAreReported) {
  Models m = ArcModels();
  // Photo 2 turned by 1 degree in the reconstruction, photo 4 not registered.
  ColmapImage& r = m.rec.images.at(12);
  const Eigen::Vector3d c = r.cam_from_world.Inverse().translation;
  r.cam_from_world.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 180, Eigen::Vector3d::UnitX())) *
      r.cam_from_world.rotation;
  r.cam_from_world.translation = -(r.cam_from_world.rotation * c);
  m.rec.images.erase(14);
  const CameraAccuracy a = CompareCameras(m.rec, m.gt);
  EXPECT_EQ(a.matched, 4);
  ASSERT_EQ(a.missing.size(), 1u);
  EXPECT_EQ(a.missing[0], "p4.jpg");
  EXPECT_NEAR(a.rotation_max_deg, 1.0, 1e-6);
  EXPECT_LT(a.rotation_median_deg, 1e-6);
  EXPECT_LT(a.alignment.max, 1e-9);  // the centre did not move
  EXPECT_NE(FormatCameraAccuracy(a).find("not registered: p4.jpg"), std::string::npos);
  // A shifted centre shows in the centre error, in per cent of the GT extent.
  ColmapImage& s = m.rec.images.at(11);
  const Eigen::Vector3d moved = s.cam_from_world.Inverse().translation + Eigen::Vector3d(0.5, 0, 0);
  s.cam_from_world.translation = -(s.cam_from_world.rotation * moved);
  const CameraAccuracy b = CompareCameras(m.rec, m.gt);
  EXPECT_GT(b.alignment.max, 0.01);
  EXPECT_NEAR(b.centre_max_pct, 100 * b.alignment.max / b.extent, 1e-9);
}

TEST(CameraAccuracy, TooFewMatchesIsAUsageError) {
  Models m = ArcModels();
  m.rec.images.erase(12);
  m.rec.images.erase(13);
  m.rec.images.erase(14);
  EXPECT_THROW(CompareCameras(m.rec, m.gt), UsageError);
}

}  // namespace
}  // namespace hdribr::eval
