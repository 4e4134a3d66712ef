#include "core/projection.h"

#include <gtest/gtest.h>

#include "core/rigid3.h"

namespace hdribr {
namespace {

// A world point placed exactly on the centre of pixel (col 37, row 21) must land there: COLMAP
// puts the centre of the top-left pixel at (0.5, 0.5), and row 0 is the top row.
TEST(ClipFromCam, KnownPointLandsOnKnownPixel) {
  const Camera cam = Camera::Pinhole(1, 64, 48, 55.0, 57.0, 31.3, 24.9);
  const Rigid3d cam_from_world =
      LookAt(Eigen::Vector3d(1, 2, -3), Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1, 0));
  const Eigen::Vector2d pixel_centre(37 + 0.5, 21 + 0.5);
  const double depth = 2.5;
  const Eigen::Vector3d p_cam = cam.CamFromPixel(pixel_centre) * depth;
  const Eigen::Vector3d p_world = cam_from_world.Inverse() * p_cam;

  const Eigen::Matrix4f clip_from_cam = ClipFromCam(cam, 0.1f, 100.0f);
  const Eigen::Vector3d back_in_cam = cam_from_world * p_world;
  const Eigen::Vector4f clip = clip_from_cam * back_in_cam.cast<float>().homogeneous();
  EXPECT_GT(clip.w(), 0.0f);
  const Eigen::Vector2d window = WindowFromClip(clip, cam.width, cam.height);
  EXPECT_NEAR(window.x(), 37.5, 1e-4);
  EXPECT_NEAR(window.y(), 21.5, 1e-4);
  EXPECT_EQ(static_cast<int>(window.x()), 37);
  EXPECT_EQ(static_cast<int>(window.y()), 21);
}

TEST(ClipFromCam, DepthRangeMapsToNdc) {
  const Camera cam = Camera::Pinhole(1, 10, 10, 10, 10, 5, 5);
  const Eigen::Matrix4f m = ClipFromCam(cam, 0.5f, 20.0f);
  const Eigen::Vector4f near_clip = m * Eigen::Vector4f(0, 0, 0.5f, 1);
  const Eigen::Vector4f far_clip = m * Eigen::Vector4f(0, 0, 20.0f, 1);
  EXPECT_NEAR(near_clip.z() / near_clip.w(), -1.0f, 1e-5);
  EXPECT_NEAR(far_clip.z() / far_clip.w(), 1.0f, 1e-5);
  // Image corners map to the NDC corners: top-left pixel corner (0,0) -> (-1, +1).
  const Eigen::Vector3d tl = cam.CamFromPixel({0, 0}) * 3.0;
  const Eigen::Vector4f c = m * tl.cast<float>().homogeneous();
  EXPECT_NEAR(c.x() / c.w(), -1.0f, 1e-5);
  EXPECT_NEAR(c.y() / c.w(), 1.0f, 1e-5);
}

}  // namespace
}  // namespace hdribr
