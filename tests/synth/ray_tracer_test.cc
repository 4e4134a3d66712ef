// The synthetic scenes and the CPU ray tracer: conventions, determinism, appearance.
#include "synth/ray_tracer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "synth/camera_response.h"
#include "synth/scene_layouts.h"
#include "synth/synth_scene.h"

namespace hdribr::synth {
namespace {

// A scene with a single fronto-parallel wall at world z = 2 seen by the identity camera.
SynthScene WallScene() {
  SynthScene s;
  Material m;
  m.texture.kind = TextureKind::kChecker;
  m.texture.colour_a = Eigen::Vector3d::Constant(0.2);
  m.texture.colour_b = Eigen::Vector3d::Constant(0.8);
  m.texture.scale = 10;
  s.materials.push_back(m);
  Shape wall;
  wall.kind = ShapeKind::kRectangle;
  wall.centre = Eigen::Vector3d(0, 0, 2);
  wall.half_size = Eigen::Vector3d(10, 10, 0);
  s.shapes.push_back(wall);
  Shape ball;
  ball.kind = ShapeKind::kSphere;
  ball.centre = Eigen::Vector3d(0.31, -0.19, 1.0);
  ball.radius = 0.05;
  s.shapes.push_back(ball);
  return s;
}

TEST(RayTracer, DepthIsCameraZAndPixelCentresAreAtHalf) {
  const SynthScene scene = WallScene();
  const Camera cam = Camera::Pinhole(1, 64, 48, 50, 50, 32, 24);
  RenderOptions ro;
  ro.antialias = false;
  const RenderedView v = RenderView(scene, cam, Rigid3d(), ro);
  // Corner pixels see the wall at the same camera z (2), not the same distance.
  EXPECT_FLOAT_EQ(v.depth.at<float>(0, 0), 2.f);
  EXPECT_FLOAT_EQ(v.depth.at<float>(47, 63), 2.f);
  // The sphere centre projects onto the centre of pixel (47, 14), at (47.5, 14.5): that pixel's
  // ray passes through the centre and meets the sphere at distance |C| - r. A half-pixel
  // convention error would move the hit by 0.01 units off-axis and change its depth by ~1e-3.
  const Eigen::Vector3d c = scene.shapes[1].centre;
  const Eigen::Vector2d px = cam.PixelFromCam(c);
  EXPECT_NEAR(px.x(), 47.5, 1e-12);
  EXPECT_NEAR(px.y(), 14.5, 1e-12);
  EXPECT_EQ(v.shape.at<int>(14, 47), 1);
  EXPECT_NEAR(v.depth.at<float>(14, 47), (c.norm() - 0.05) * c.z() / c.norm(), 2e-6);
  // 3 pixels away (sphere radius 2.5 pixels) the wall is seen.
  EXPECT_EQ(v.shape.at<int>(14, 50), 0);
  EXPECT_EQ(v.shape.at<int>(17, 47), 0);
  EXPECT_EQ(v.shape.at<int>(14, 44), 0);
  EXPECT_EQ(v.shape.at<int>(11, 47), 0);
  // Normals face the camera.
  EXPECT_NEAR(v.normal.at<cv::Vec3f>(0, 0)[2], -1.f, 1e-6);
}

TEST(RayTracer, ResultDoesNotDependOnThreads) {
  const SynthScene scene = MakeScene("default");
  const Camera cam = Camera::Pinhole(1, 96, 72, 86, 86, 48, 36);
  const Rigid3d cam_from_world =
      LookAt(Eigen::Vector3d(0.5, -2, 1), scene.look_at, Eigen::Vector3d::UnitZ());
  RenderOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const RenderedView a = RenderView(scene, cam, cam_from_world, one);
  const RenderedView b = RenderView(scene, cam, cam_from_world, two);
  EXPECT_EQ(cv::norm(a.radiance, b.radiance, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0);
}

TEST(Scenes, NamedScenesExistAndUnknownNamesAreRefused) {
  for (const std::string& name : SceneNames()) {
    const SynthScene s = MakeScene(name);
    EXPECT_EQ(s.name, name);
    bool glossy = false, emissive = false;
    for (const Material& m : s.materials) {
      glossy |= m.specular > 0;
      emissive |= m.emission.maxCoeff() > 0;
    }
    EXPECT_TRUE(glossy) << name;
    EXPECT_TRUE(emissive) << name;
  }
  EXPECT_THROW(MakeScene("nope"), UsageError);
  // The thin scene has structures thinner than 1% of the scene size.
  const SynthScene thin = MakeScene("thin");
  int thin_shapes = 0;
  for (const Shape& s : thin.shapes) {
    const bool rod = s.kind == ShapeKind::kCylinder && s.radius < 0.01 * thin.size;
    const bool plate = s.kind == ShapeKind::kBox && s.half_size.minCoeff() < 0.005 * thin.size;
    thin_shapes += rod || plate;
  }
  EXPECT_GE(thin_shapes, 5);
}

TEST(Scenes, SunShadowsAreHard) {
  const SynthScene scene = MakeScene("default");
  // A ground point in the shadow of the glossy sphere (straight down-sun from its centre) and a
  // free ground point: the sun term makes them differ by far more than the ambient term.
  const Eigen::Vector3d sphere = scene.shapes[4].centre;
  const Eigen::Vector3d shadow =
      sphere - sphere.z() / scene.sun_direction.z() * scene.sun_direction;
  const Eigen::Vector3d lit(-1.2, -1.2, 0);
  auto radiance_at = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d eye = p + Eigen::Vector3d(0, -0.5, 2);
    const Ray r{eye, (p - eye).normalized()};
    Hit hit;
    const Eigen::Vector3d l = scene.Trace(r, &hit);
    EXPECT_EQ(hit.shape, 0);  // the ground
    return l.mean() / scene.materials[0].texture.Albedo(hit.position).mean();
  };
  EXPECT_GT(radiance_at(lit) / radiance_at(shadow), 5.0);
}

TEST(Scenes, GlossyHighlightMovesWithTheViewpoint) {
  const SynthScene scene = MakeScene("default");
  const Camera cam = Camera::Pinhole(1, 160, 120, 144, 144, 80, 60);
  std::vector<Eigen::Vector3d> highlights;
  for (double az : {-0.6, 0.6}) {
    const Eigen::Vector3d eye =
        scene.look_at + Eigen::Vector3d(2.2 * std::sin(az), -2.2 * std::cos(az), 0.9);
    const Rigid3d cam_from_world = LookAt(eye, scene.look_at, Eigen::Vector3d::UnitZ());
    const RenderedView v = RenderView(scene, cam, cam_from_world);
    // Brightest pixel on the glossy sphere (shape 4).
    double best = -1;
    Eigen::Vector3d where = Eigen::Vector3d::Zero();
    for (int y = 0; y < v.depth.rows; ++y) {
      for (int x = 0; x < v.depth.cols; ++x) {
        if (v.shape.at<int>(y, x) != 4) continue;
        const cv::Vec3f l = v.radiance.at<cv::Vec3f>(y, x);
        if (l[2] > best) {
          best = l[2];
          where = cam_from_world.Inverse() *
                  (cam.CamFromPixel({x + 0.5, y + 0.5}) * double(v.depth.at<float>(y, x)));
        }
      }
    }
    ASSERT_GT(best, 1.0) << "no highlight";
    highlights.push_back(where);
  }
  EXPECT_GT((highlights[0] - highlights[1]).norm(), 0.02);
}

TEST(SyntheticResponse, IsInvertibleNonLinearAndPerChannel) {
  const SyntheticResponse r;
  for (int c = 0; c < 3; ++c) {
    for (double z : {1.0, 10.0, 64.0, 128.0, 200.0, 254.0}) {
      EXPECT_NEAR(r.ValueFromExposure(c, r.ExposureFromValue(c, z)), z, 1e-9);
    }
    // Non-linear: half the saturation exposure does not give half the range.
    EXPECT_GT(r.ValueFromExposure(c, 0.5 * r.x_sat), 170.0);
    EXPECT_EQ(r.ValueFromExposure(c, 2 * r.x_sat), 255.0);
  }
  // Per channel: blue and red differ by several levels in the shadows (5.2 at 1% of
  // saturation; the linear toe brings the curves closer together below that).
  EXPECT_GT(
      std::abs(r.ValueFromExposure(2, 0.01 * r.x_sat) - r.ValueFromExposure(0, 0.01 * r.x_sat)),
      5.0);
  const ResponseCurve curve = r.Curve();
  ASSERT_EQ(curve.log_inverse[1].size(), 256u);
  for (int c = 0; c < 3; ++c) {
    for (int z = 1; z < 256; ++z) EXPECT_GT(curve.log_inverse[c][z], curve.log_inverse[c][z - 1]);
    EXPECT_NEAR(curve.log_inverse[c][255], std::log(r.x_sat), 1e-12);
  }
}

TEST(SyntheticResponse, LinearToeJoinsTheGammaCurveSmoothly) {
  const SyntheticResponse r;
  SyntheticResponse pure = r;
  pure.toe = 0.0;
  for (int c = 0; c < 3; ++c) {
    // Linear below the toe: half the exposure gives half the value.
    const double below = 0.5 * r.toe * r.x_sat;
    EXPECT_NEAR(r.Encode(c, 0.5 * r.toe), 2.0 * r.Encode(c, 0.25 * r.toe), 1e-12);
    EXPECT_NEAR(r.ExposureFromValue(c, r.ValueFromExposure(c, below)), below, 1e-15);
    // Value and slope continuous at the toe (one-sided differences over 1e-7 of it).
    const double h = 1e-7 * r.toe;
    const double left = r.Encode(c, r.toe - h), at = r.Encode(c, r.toe),
                 right = r.Encode(c, r.toe + h);
    EXPECT_NEAR(left, at, 1e-6 * at);
    EXPECT_NEAR((at - left) / h, (right - at) / h, 1e-4 * (at - left) / h);
    EXPECT_NEAR(r.Encode(c, 1.0), 1.0, 1e-12);
    // The toe lies in the lowest codes (about 24-27): the curve above is the gamma curve, and
    // code 10 is well above the read noise (the pure power law puts it below: SNR < 1).
    const double toe_code = r.ValueFromExposure(c, r.toe * r.x_sat);
    EXPECT_GT(toe_code, 20.0);
    EXPECT_LT(toe_code, 30.0);
    EXPECT_GT(r.ExposureFromValue(c, 10.0) / r.x_sat, 3.0 * r.read) << c;
    EXPECT_LT(pure.ExposureFromValue(c, 10.0) / pure.x_sat, r.read) << c;
    // Without a toe: the pure power law s(x) = x^(1/gamma) of captures made before it.
    EXPECT_NEAR(pure.Encode(c, 0.2), std::pow(0.2, 1.0 / pure.gamma[c]), 1e-12);
  }
}

TEST(SyntheticResponse, NoiseIsMildAndDeterministic) {
  const SyntheticResponse r;
  cv::Mat radiance(64, 64, CV_32FC3, cv::Scalar(0.3, 0.3, 0.3));
  const double t = 1.0 / 64;
  const cv::Mat a = r.Expose(radiance, t, 7), b = r.Expose(radiance, t, 7),
                c = r.Expose(radiance, t, 8);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_INF), 0.0);
  cv::Scalar mean, stddev;
  cv::meanStdDev(a, mean, stddev);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(mean[ch], r.ValueFromExposure(ch, 0.3 * t), 0.3);
    EXPECT_GT(stddev[ch], 0.1);
    EXPECT_LT(stddev[ch], 1.0);
  }
}

}  // namespace
}  // namespace hdribr::synth
