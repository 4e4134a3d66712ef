// Viewer navigation (orbit, fly, zoom, transitions, scene up), the Eigen <-> GLM conversions,
// the demo orbit and the camera-path recorder: pure math, no GL.
#include "viewer/camera_controller.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/projection.h"
#include "viewer/glm_eigen.h"
#include "viewer/orbit.h"
#include "viewer/recorder.h"

namespace hdribr::viewer {
namespace {

// Eight photos on a circle of radius 4 around the origin at height 1 (world up = +z), looking
// at the origin.
Scene RingScene() {
  Scene s;
  s.cameras[1] = Camera::Pinhole(1, 160, 120, 150, 150, 80, 60);
  for (int i = 0; i < 8; ++i) {
    Photo p;
    p.id = i + 1;
    p.name = "p" + std::to_string(i) + ".jpg";
    p.camera_id = 1;
    const double a = 2 * M_PI * i / 8;
    p.cam_from_world = LookAt({4 * std::cos(a), 4 * std::sin(a), 1}, {0, 0, 0}, {0, 0, 1});
    s.photos.push_back(p);
  }
  s.scene_scale = 4;
  s.centroid = Eigen::Vector3d::Zero();
  return s;
}

TEST(CameraController, SetPoseRoundTrips) {
  CameraController c({0, 0, 0}, 1, {0, 0, 1});
  const Rigid3d pose = LookAt({1, 2, 3}, {0, 0, 0}, {0, 0, 1});
  c.SetPose(pose);
  EXPECT_TRUE(c.cam_from_world().rotation.isApprox(pose.rotation, 1e-12) ||
              c.cam_from_world().rotation.coeffs().isApprox(-pose.rotation.coeffs(), 1e-12));
  EXPECT_TRUE(c.cam_from_world().translation.isApprox(pose.translation, 1e-12));
  EXPECT_TRUE(c.eye().isApprox(Eigen::Vector3d(1, 2, 3), 1e-12));
}

TEST(CameraController, OrbitKeepsDistanceAndTheCentreInView) {
  CameraController c({1, 1, 0}, 2, {0, 0, 1});
  c.SetPose(LookAt({4, 1, 0.5}, {1, 1, 0}, {0, 0, 1}));
  const double d0 = (c.eye() - c.pivot()).norm();
  c.Orbit(0.7, 0.2);
  EXPECT_NEAR((c.eye() - c.pivot()).norm(), d0, 1e-9);
  EXPECT_GT((c.eye() - Eigen::Vector3d(4, 1, 0.5)).norm(), 0.5);  // it moved
  // The pivot stays on the optical axis.
  const Eigen::Vector3d pc = c.cam_from_world() * c.pivot();
  EXPECT_NEAR(pc.x(), 0, 1e-9);
  EXPECT_NEAR(pc.y(), 0, 1e-9);
  EXPECT_NEAR(pc.z(), d0, 1e-9);
  // Positive pitch raises the camera (along world up).
  const double z0 = c.eye().z();
  c.Orbit(0, 0.1);
  EXPECT_GT(c.eye().z(), z0);
}

TEST(CameraController, FlyMovesAlongCameraAxesAtSceneSpeed) {
  CameraController c({0, 0, 0}, 10, {0, 0, 1});
  c.SetPose(LookAt({5, 0, 0}, {0, 0, 0}, {0, 0, 1}));
  c.speed_factor = 0.5;
  c.Fly({0, 0, 1}, 0.2);  // forward: 0.5 x 10 x 0.2 = 1 unit towards the origin
  EXPECT_TRUE(c.eye().isApprox(Eigen::Vector3d(4, 0, 0), 1e-12));
  c.Fly({0, -1, 0}, 0.2);  // camera y is down: -y is world up
  EXPECT_TRUE(c.eye().isApprox(Eigen::Vector3d(4, 0, 1), 1e-12));
  // Look does not move the eye.
  c.Look(0.3, 0.1);
  EXPECT_TRUE(c.eye().isApprox(Eigen::Vector3d(4, 0, 1), 1e-12));
}

TEST(CameraController, ZoomMovesTowardsTheCursorRay) {
  CameraController c({0, 0, 0}, 1, {0, 0, 1});
  c.SetPose(LookAt({10, 0, 0}, {0, 0, 0}, {0, 0, 1}));
  const Eigen::Vector3d ray(0.2, 0, 1);  // right of centre
  c.ZoomTowards(ray, 1);
  // 15% of the distance (10) along the world ray.
  const Eigen::Vector3d world_ray = c.cam_from_world().rotation.inverse() * ray.normalized();
  EXPECT_TRUE(c.eye().isApprox(Eigen::Vector3d(10, 0, 0) + 1.5 * world_ray, 1e-9));
  c.ZoomTowards(ray, -1);  // and back out
  EXPECT_LT(c.eye().x(), 10 - 1.5 * 0.98 + 1.5);
}

TEST(CameraController, TransitionIsSmoothAndEndsOnTheTarget) {
  CameraController c({0, 0, 0}, 1, {0, 0, 1});
  c.SetPose(LookAt({4, 0, 0}, {0, 0, 0}, {0, 0, 1}));
  const Rigid3d target = LookAt({0, 4, 0}, {0, 0, 0}, {0, 0, 1});
  c.TransitionTo(target, 1.0);
  EXPECT_TRUE(c.transitioning());
  EXPECT_TRUE(c.Update(0.5));
  const Eigen::Vector3d mid = c.eye();
  EXPECT_NEAR(mid.x(), 2, 1e-9);  // smoothstep(0.5) = 0.5
  EXPECT_NEAR(mid.y(), 2, 1e-9);
  c.Update(0.6);
  EXPECT_FALSE(c.transitioning());
  EXPECT_TRUE(c.eye().isApprox(Eigen::Vector3d(0, 4, 0), 1e-9));
  EXPECT_TRUE((c.cam_from_world() * Eigen::Vector3d(1, 2, 3))
                  .isApprox(target * Eigen::Vector3d(1, 2, 3), 1e-9));
  EXPECT_FALSE(c.Update(0.1));
  // Reset goes back home.
  c.SetHome(LookAt({4, 0, 0}, {0, 0, 0}, {0, 0, 1}));
  c.Reset(0);
  EXPECT_TRUE(c.eye().isApprox(Eigen::Vector3d(4, 0, 0), 1e-9));
}

TEST(Navigation, SceneUp) {
  const Scene s = RingScene();
  EXPECT_TRUE(SceneUp(s).isApprox(Eigen::Vector3d(0, 0, 1), 0.1));
  EXPECT_TRUE(SceneUp(Scene{}).isApprox(Eigen::Vector3d(0, 0, 1)));
}

TEST(GlmEigen, RoundTripsAreExact) {
  const Eigen::Vector3d v(0.1, -2.5e7, 1.0 / 3.0);
  const glm::dvec3 gv = ToGlm(v);
  EXPECT_EQ(gv.x, v.x());
  EXPECT_EQ(gv.y, v.y());
  EXPECT_EQ(gv.z, v.z());
  EXPECT_EQ(ToEigen(gv), v);
  const Eigen::Vector3f vf(0.1f, -3.0f, 1e-30f);
  EXPECT_EQ(ToEigen(ToGlm(vf)), vf);

  // GLM's quaternion constructor is (w, x, y, z), its storage x, y, z, w: same rotation.
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -3).normalized()));
  const glm::dquat gq = ToGlm(q);
  EXPECT_EQ(gq.w, q.w());
  EXPECT_EQ(gq.x, q.x());
  EXPECT_EQ(gq.y, q.y());
  EXPECT_EQ(gq.z, q.z());
  EXPECT_EQ(ToEigen(gq).coeffs(), q.coeffs());
  EXPECT_TRUE(ToEigen(gq * ToGlm(v)).isApprox(q * v, 1e-15));

  // A rigid pose: its parts round-trip exactly, its GL matrix is Matrix4() and acts the same.
  const Rigid3d pose = LookAt({1, 2, 3}, {0, 0.5, 0}, {0, 0, 1});
  const Rigid3d back(ToEigen(ToGlm(pose.rotation)), ToEigen(ToGlm(pose.translation)));
  EXPECT_EQ(back.rotation.coeffs(), pose.rotation.coeffs());
  EXPECT_EQ(back.translation, pose.translation);
  const glm::dmat4 m = ToGlm(pose);
  EXPECT_EQ(ToEigen(m), pose.Matrix4());
  const glm::dvec4 x = m * glm::dvec4(ToGlm(v), 1.0);
  EXPECT_TRUE(ToEigen(glm::dvec3(x)).isApprox(pose * v, 1e-12));
  EXPECT_EQ(x.w, 1.0);

  // Matrices: element (row r, column c) is GLM's [c][r], in float and double.
  Eigen::Matrix4d md;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) md(r, c) = 10 * r + c + 0.125;
  }
  EXPECT_EQ(ToGlm(md)[2][1], md(1, 2));
  EXPECT_EQ(ToEigen(ToGlm(md)), md);
  const Eigen::Matrix4f clip =
      ClipFromCam(Camera::Pinhole(1, 160, 120, 150, 140, 81, 59.5), 0.1f, 50.0f);
  const glm::mat4 gclip = ToGlm(clip);
  EXPECT_EQ(ToEigen(gclip), clip);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) EXPECT_EQ(gclip[c][r], clip(r, c));
  }
  const Eigen::Vector4f p(0.3f, -0.2f, 2.0f, 1.0f);
  const glm::vec4 gp = gclip * glm::vec4(p.x(), p.y(), p.z(), p.w());
  const Eigen::Vector4f ep = clip * p;
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(gp[i], ep(i), 1e-6f);
}

// The controller's GLM math against the same navigation written with Eigen.
TEST(CameraController, GlmPosesEqualTheEigenExpectation) {
  const Eigen::Vector3d pivot(1, 1, 0), up(0, 0, 1);
  const double scale = 2;
  CameraController c(pivot, scale, up);
  const Rigid3d start = LookAt({4, 1, 0.5}, pivot, up);
  c.SetPose(start);
  Eigen::Vector3d eye = start.Inverse().translation;
  Eigen::Quaterniond world_from_cam = start.rotation.inverse();
  const auto expect_pose = [&](const char* what) {
    SCOPED_TRACE(what);
    const Rigid3d got = c.cam_from_world();
    const Eigen::Quaterniond rot = world_from_cam.inverse();
    EXPECT_TRUE(got.rotation.coeffs().isApprox(rot.coeffs(), 1e-12));
    EXPECT_TRUE(got.translation.isApprox(-(rot * eye), 1e-12));
    EXPECT_TRUE(c.eye().isApprox(eye, 1e-12));
  };
  expect_pose("SetPose");

  Eigen::Vector3d right = world_from_cam * Eigen::Vector3d::UnitX();
  Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(-0.7, up)) *
                         Eigen::Quaterniond(Eigen::AngleAxisd(-0.2, right));
  c.Orbit(0.7, 0.2);
  eye = pivot + q * (eye - pivot);
  world_from_cam = (q * world_from_cam).normalized();
  expect_pose("Orbit");

  right = world_from_cam * Eigen::Vector3d::UnitX();
  q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, up)) *
      Eigen::Quaterniond(Eigen::AngleAxisd(-0.1, right));
  c.Look(-0.3, 0.1);
  world_from_cam = (q * world_from_cam).normalized();
  expect_pose("Look");

  c.speed_factor = 0.5;
  c.Fly({0.5, -1, 0.25}, 0.1);
  eye += world_from_cam * Eigen::Vector3d(0.5, -1, 0.25) * (0.5 * scale * 0.1);
  expect_pose("Fly");

  const Eigen::Vector3d ray(0.2, -0.1, 1);
  const double step = 0.15 * (eye - pivot).norm();
  c.ZoomTowards(ray, 2);
  eye += world_from_cam * ray.normalized() * (step * 2);
  expect_pose("ZoomTowards");

  const Rigid3d target = LookAt({-3, 2, 1}, pivot, up);
  c.TransitionTo(target, 1.0);
  c.Update(0.3);
  const double s = 0.3 * 0.3 * (3 - 2 * 0.3);
  const Eigen::Vector3d target_eye = target.Inverse().translation;
  eye += s * (target_eye - eye);
  world_from_cam = world_from_cam.slerp(s, target.rotation.inverse()).normalized();
  expect_pose("Update");
}

TEST(Orbit, LooksAtTheCentroidFromThePhotosDistance) {
  const Scene s = RingScene();
  const CameraPath path = OrbitPath(s, 24, 12, 80, 60);
  ASSERT_EQ(path.FrameCount(), 24);
  EXPECT_EQ(path.keyframes[5].name, "frame_0005");
  EXPECT_EQ(path.keyframes[0].camera.width, 80);
  double min_d = 1e9, max_d = 0;
  for (const View& v : path.keyframes) {
    const Eigen::Vector3d c = v.cam_from_world * s.centroid;
    EXPECT_NEAR(c.x(), 0, 1e-9);
    EXPECT_NEAR(c.y(), 0, 1e-9);
    const double d = v.cam_from_world.Inverse().translation.norm();
    min_d = std::min(min_d, d);
    max_d = std::max(max_d, d);
  }
  EXPECT_NEAR(min_d, std::sqrt(17.0), 1e-9);  // radius 4, height 1: on the photos' circle
  EXPECT_NEAR(max_d, std::sqrt(17.0), 1e-9);
  // Frames differ (it moves).
  EXPECT_GT((path.keyframes[0].cam_from_world.Inverse().translation -
             path.keyframes[6].cam_from_world.Inverse().translation)
                .norm(),
            1.0);
  EXPECT_THROW(OrbitPath(Scene{}, 4), std::exception);
  EXPECT_THROW(OrbitPath(s, 0), std::exception);
}

TEST(Recorder, KeyframesAtMostAtTheFrameRateAndPlayback) {
  const Scene s = RingScene();
  Recorder r;
  EXPECT_FALSE(r.recording());
  r.Start(10);
  for (int i = 0; i < 40; ++i) {  // 40 frames at 100 Hz over 0.4 s
    r.Add(100.0 + i * 0.01,
          View{"f", s.cameras.at(1), s.photos[static_cast<size_t>(i % 8)].cam_from_world});
  }
  const CameraPath p =
      r.Stop(std::make_pair(100.5, View{"f", s.cameras.at(1), s.photos[0].cam_from_world}));
  EXPECT_FALSE(r.recording());
  // Keyframes at 0, 0.1, 0.2, 0.3 (+- rounding) and the final one at 0.5.
  ASSERT_GE(p.keyframes.size(), 4u);
  ASSERT_LE(p.keyframes.size(), 6u);
  EXPECT_DOUBLE_EQ(p.times_s.front(), 0.0);
  EXPECT_NEAR(p.times_s.back(), 0.5, 1e-9);
  for (size_t i = 1; i < p.times_s.size(); ++i) EXPECT_GT(p.times_s[i], p.times_s[i - 1]);
  Player player(p);
  ASSERT_TRUE(player.At(0).has_value());
  EXPECT_TRUE(player.At(0)->cam_from_world.translation.isApprox(
      p.keyframes[0].cam_from_world.translation, 1e-9));
  EXPECT_FALSE(player.At(10).has_value());
  EXPECT_FALSE(player.At(-1).has_value());
}

}  // namespace
}  // namespace hdribr::viewer
