// Colour-per-point splats on the GPU: colour, position, depth test, uncoloured points skipped.
#include "render/point_color_pass.h"

#include <gtest/gtest.h>

#include "gl/context.h"

namespace hdribr::render {
namespace {

TEST(PointColorPass, SplatsNearestColourAtTheProjectedPixel) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  PointColorPass pass(shaders);
  // Camera at the origin looking down +z; 64x48, f = 50, the optical axis through the centre of
  // pixel (32, 24).
  const Camera camera = Camera::Pinhole(1, 64, 48, 50, 50, 32.5, 24.5);
  const Rigid3d cam_from_world;
  PointCloud cloud;
  // A near red point and a far green one on the optical axis, a blue one off-axis that lands
  // in pixel 42: x = 32.5 + 50 * 0.41 / 2 = 42.75; one without colour.
  cloud.positions = {Eigen::Vector3f(0, 0, 2), Eigen::Vector3f(0, 0, 4),
                     Eigen::Vector3f(0.41f, 0, 2), Eigen::Vector3f(-0.4f, 0, 2)};
  cloud.radii = {0.04f, 0.2f, 0.01f, 0.04f};
  const std::vector<Eigen::Vector3f> bgr = {Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(0, 1, 0),
                                            Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(-1, -1, -1)};
  pass.SetPoints(cloud, bgr);
  EXPECT_EQ(pass.size(), 3u);
  const PointColorImages out = pass.Render(camera, cam_from_world, 64, 48);
  ASSERT_EQ(out.color.size(), cv::Size(64, 48));
  // Centre: the red point is in front of the larger green splat.
  EXPECT_EQ(out.valid.at<uint8_t>(24, 32), 255);
  EXPECT_EQ(out.color.at<cv::Vec3f>(24, 32), cv::Vec3f(0, 0, 1));
  // Around the red splat (radius 1 px) the far green splat (2.5 px) shows.
  EXPECT_EQ(out.color.at<cv::Vec3f>(24, 34), cv::Vec3f(0, 1, 0));
  // The blue point's centre pixel.
  EXPECT_EQ(out.color.at<cv::Vec3f>(24, 42), cv::Vec3f(1, 0, 0));
  // The uncoloured point is not drawn; far from every splat nothing is valid.
  EXPECT_EQ(out.valid.at<uint8_t>(24, 22), 0);
  EXPECT_EQ(out.valid.at<uint8_t>(2, 2), 0);
  EXPECT_EQ(out.color.at<cv::Vec3f>(2, 2), cv::Vec3f(0, 0, 0));
  // Half size: intrinsics rescaled, the red point still at the centre.
  const PointColorImages half = pass.Render(camera, cam_from_world, 32, 24);
  EXPECT_EQ(half.color.at<cv::Vec3f>(12, 16), cv::Vec3f(0, 0, 1));
}

}  // namespace
}  // namespace hdribr::render
