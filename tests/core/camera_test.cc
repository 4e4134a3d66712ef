#include "core/camera.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace hdribr {
namespace {

TEST(Camera, ModelNamesRoundTrip) {
  for (int id = 0; id <= 10; ++id) {
    const CameraModel m = CameraModelFromId(id);
    EXPECT_EQ(CameraModelFromName(CameraModelName(m)), m);
  }
  EXPECT_EQ(CameraModelNumParams(CameraModel::kPinhole), 4);
  EXPECT_EQ(CameraModelNumParams(CameraModel::kSimplePinhole), 3);
  EXPECT_THROW(CameraModelFromName("BOGUS"), std::invalid_argument);
  EXPECT_THROW(CameraModelFromId(42), std::invalid_argument);
}

TEST(Camera, SimplePinholeSharesFocal) {
  Camera c;
  c.model = CameraModel::kSimplePinhole;
  c.width = 100;
  c.height = 80;
  c.params = {120, 50, 40};
  EXPECT_TRUE(c.IsPinhole());
  EXPECT_DOUBLE_EQ(c.fx(), 120);
  EXPECT_DOUBLE_EQ(c.fy(), 120);
  EXPECT_DOUBLE_EQ(c.cx(), 50);
  EXPECT_DOUBLE_EQ(c.cy(), 40);
}

TEST(Camera, ZeroDistortionIsDetected) {
  Camera c;
  c.model = CameraModel::kOpenCV;
  c.params = {100, 100, 50, 50, 0, 0, 0, 0};
  EXPECT_TRUE(c.HasZeroDistortion());
  c.params[4] = 0.01;
  EXPECT_FALSE(c.HasZeroDistortion());
}

TEST(Camera, PixelRoundTripAndScaling) {
  const Camera c = Camera::Pinhole(1, 640, 480, 500, 510, 320, 240);
  const Eigen::Vector3d p(0.3, -0.2, 2.0);
  const Eigen::Vector2d px = c.PixelFromCam(p);
  EXPECT_NEAR(px.x(), 500 * 0.15 + 320, 1e-12);
  EXPECT_NEAR(px.y(), 510 * -0.1 + 240, 1e-12);
  const Eigen::Vector3d ray = c.CamFromPixel(px);
  EXPECT_TRUE((ray * 2.0).isApprox(p, 1e-12));
  // Half resolution: the same point lands at half the pixel coordinates.
  const Camera half = c.Scaled(320, 240);
  EXPECT_TRUE(half.PixelFromCam(p).isApprox(px * 0.5, 1e-12));
  // Images that are the frame at another scale fit (rounding within a pixel); other shapes not.
  EXPECT_TRUE(c.FitsImage(640, 480));
  EXPECT_TRUE(c.FitsImage(320, 240));
  EXPECT_TRUE(c.FitsImage(321, 240));
  EXPECT_TRUE(c.FitsImage(1280, 960));
  EXPECT_FALSE(c.FitsImage(480, 480));
  EXPECT_FALSE(c.FitsImage(640, 470));
  EXPECT_FALSE(c.FitsImage(0, 0));
}

}  // namespace
}  // namespace hdribr
