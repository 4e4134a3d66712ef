#include "io/camera_spec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/error.h"
#include "test_util.h"

namespace hdribr {
namespace {

Scene TwoPhotoScene() {
  Scene scene;
  scene.cameras[1] = Camera::Pinhole(1, 64, 48, 50, 50, 32, 24);
  scene.cameras[7] = Camera::Pinhole(7, 32, 32, 30, 30, 16, 16);
  Photo a;
  a.id = 1;
  a.name = "a.png";
  a.camera_id = 1;
  a.cam_from_world = LookAt({0, 0, -3}, {0, 0, 0}, {0, -1, 0});
  Photo b = a;
  b.id = 2;
  b.name = "sub/b.png";
  b.camera_id = 7;
  b.cam_from_world = LookAt({3, 0, 0}, {0, 0, 0}, {0, -1, 0});
  scene.photos = {a, b};
  return scene;
}

TEST(CameraSpec, PhotoName) {
  const Scene scene = TwoPhotoScene();
  const View v = ParseCameraSpec("sub/b.png", scene);
  EXPECT_EQ(v.name, "sub/b.png");
  EXPECT_EQ(v.camera.width, 32);
  EXPECT_TRUE(v.cam_from_world.translation.isApprox(scene.photos[1].cam_from_world.translation));
}

TEST(CameraSpec, PoseLine) {
  const Scene scene = TwoPhotoScene();
  View v = ParseCameraSpec("1 0 0 0 0.5 0 2", scene);
  EXPECT_EQ(v.camera.width, 64);  // first photo's camera
  EXPECT_NEAR(v.cam_from_world.translation.x(), 0.5, 1e-12);
  EXPECT_EQ(v.name, "view");
  v = ParseCameraSpec("0 1 0 0 0 0 2 7 mine", scene);
  EXPECT_EQ(v.camera.id, 7);
  EXPECT_EQ(v.name, "mine");
  EXPECT_THROW(ParseCameraSpec("1 0 0 0 0 0 2 9", scene), UsageError);  // unknown id
  EXPECT_THROW(ParseCameraSpec("1 1 0 0 0 0 2", scene), UsageError);    // not unit
  EXPECT_THROW(ParseCameraSpec("1 0 0 0 0 0 2 x", scene), UsageError);  // bad id
  EXPECT_THROW(ParseCameraSpec("1 0 0 0 0 0 2 1 n extra", scene), UsageError);
  EXPECT_THROW(ParseCameraSpec("nope.png", scene), UsageError);
  EXPECT_THROW(ParseCameraSpec("", scene), UsageError);
}

TEST(CameraSpec, CameraFileRoundTrip) {
  const Scene scene = TwoPhotoScene();
  const auto dir = test::TempDir("camera_spec");
  View v{"x", Camera::Pinhole(0, 100, 80, 90, 91, 50.5, 40.25),
         LookAt({1, 2, 3}, {0, 0, 0}, {0, -1, 0})};
  WriteCameraFile(dir / "cam.json", v);
  const View r = ParseCameraSpec((dir / "cam.json").string(), scene);
  EXPECT_EQ(r.camera.width, 100);
  EXPECT_DOUBLE_EQ(r.camera.fy(), 91);
  EXPECT_DOUBLE_EQ(r.camera.cy(), 40.25);
  EXPECT_TRUE(r.cam_from_world.translation.isApprox(v.cam_from_world.translation, 1e-12));
  EXPECT_NEAR(r.cam_from_world.rotation.angularDistance(v.cam_from_world.rotation), 0, 1e-9);
  EXPECT_THROW(ParseCameraSpec((dir / "missing.json").string(), scene), InputError);
  std::ofstream(dir / "bad.json") << R"({"width": 10, "height": 10, "fx": -1, "fy": 1, "cx": 5,
    "cy": 5, "cam_from_world": {"qvec": [1,0,0,0], "tvec": [0,0,0]}})";
  EXPECT_THROW(ReadCameraFile(dir / "bad.json"), InputError);
  std::ofstream(dir / "trunc.json") << R"({"width": 10)";
  EXPECT_THROW(ReadCameraFile(dir / "trunc.json"), InputError);
}

TEST(CameraPath, RoundTripAndInterpolation) {
  const auto dir = test::TempDir("camera_path");
  CameraPath path;
  path.fps = 4;
  const Camera cam = Camera::Pinhole(0, 40, 30, 35, 35, 20, 15);
  path.times_s = {0.0, 1.0};
  path.keyframes = {View{"k0", cam, LookAt({0, 0, -2}, {0, 0, 0}, {0, -1, 0})},
                    View{"k1", cam, LookAt({2, 0, 0}, {0, 0, 0}, {0, -1, 0})}};
  WriteCameraPath(dir / "p.json", path);
  const CameraPath r = ReadCameraPath(dir / "p.json");
  ASSERT_EQ(r.keyframes.size(), 2u);
  EXPECT_EQ(r.FrameCount(), 5);
  EXPECT_EQ(r.Frame(3).name, "frame_0003");
  const auto centre = [](const View& v) { return v.cam_from_world.Inverse().translation; };
  EXPECT_TRUE(centre(r.Frame(0)).isApprox(Eigen::Vector3d(0, 0, -2), 1e-9));
  EXPECT_TRUE(centre(r.Frame(4)).isApprox(Eigen::Vector3d(2, 0, 0), 1e-9));
  EXPECT_TRUE(centre(r.Frame(2)).isApprox(Eigen::Vector3d(1, 0, -1), 1e-9));
  // Halfway rotation: the view direction bisects the two keyframe directions.
  const Eigen::Vector3d dir2 =
      r.Frame(2).cam_from_world.rotation.inverse() * Eigen::Vector3d::UnitZ();
  EXPECT_TRUE(dir2.isApprox(Eigen::Vector3d(-1, 0, 1).normalized(), 1e-9));
  std::ofstream(dir / "bad.json") << R"({"format": "hdribr-camera-path", "version": 1,
    "fps": 30, "keyframes": []})";
  EXPECT_THROW(ReadCameraPath(dir / "bad.json"), InputError);
  std::ofstream(dir / "other.json") << R"({"format": "x"})";
  EXPECT_THROW(ReadCameraPath(dir / "other.json"), InputError);
}

}  // namespace
}  // namespace hdribr
