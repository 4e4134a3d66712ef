// The splat depth pass on analytic scenes (spheres and a plane) with ray-cast ground truth:
// accuracy, leakage, silhouette stability and edge cases, for the three modes.
#include "render/depth_pass.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>

#include "analytic_scene.h"
#include "core/error.h"
#include "depth_compare.h"
#include "gl_test_util.h"
#include "render/photo_depth_maps.h"
#include "render/readback.h"

namespace hdribr::render {
namespace {

using test::AnalyticScene;

class DepthPassTest : public test::GlSuite {
 protected:
  // Depth of `cloud` seen by camera/pose in `mode`, read back.
  DepthImages Render(DepthPass& pass, const Camera& camera, const Rigid3d& cam_from_world,
                     DepthMode mode) {
    pass.options().mode = mode;
    DepthTarget target = DepthTarget::Create(camera.width, camera.height);
    pass.Process(camera, cam_from_world, target);
    return ReadDepthTarget(target);
  }
};

// Views used for accuracy: the capture view (origin, looking +z) and two novel views.
std::vector<Rigid3d> AccuracyViews() {
  const Eigen::Vector3d target(0, 0, 3.2), up(0, -1, 0);
  std::vector<Rigid3d> views = {Rigid3d()};
  for (double deg : {-20.0, 25.0}) {
    const double a = deg * M_PI / 180.0;
    const Eigen::Vector3d eye = target + 3.2 * Eigen::Vector3d(std::sin(a), 0.1, -std::cos(a));
    views.push_back(LookAt(eye, target, up));
  }
  return views;
}

// Every point raster with every depth mode.
std::vector<std::pair<PointRaster, DepthMode>> RastersAndModes() {
  std::vector<std::pair<PointRaster, DepthMode>> all;
  for (PointRaster raster : kAllPointRasters) {
    for (DepthMode mode : AllDepthModes()) all.emplace_back(raster, mode);
  }
  return all;
}

TEST_F(DepthPassTest, PointLandsOnItsPixel) {
  // A point at camera (x, y, z) must cover pixel floor(fx x/z + cx, fy y/z + cy) at depth z.
  const Camera cam = test::TestCamera(64);
  PointCloud pc;
  const Eigen::Vector3f p(0.3f, -0.2f, 2.0f);
  pc.positions = {p};
  pc.normals = {Eigen::Vector3f(0, 0, -1)};
  pc.radii = {0.001f};  // well under a pixel: only the centre pixel
  DepthPass pass(*shaders_);
  pass.SetPoints(pc);
  const Eigen::Vector2d px = cam.PixelFromCam(p.cast<double>());
  for (DepthMode mode : AllDepthModes()) {
    const DepthImages out = Render(pass, cam, Rigid3d(), mode);
    EXPECT_EQ(cv::countNonZero(out.valid), 1) << DepthModeName(mode);
    const int x = static_cast<int>(px.x()), y = static_cast<int>(px.y());
    EXPECT_NEAR(out.depth.at<float>(y, x), 2.0f, 1e-4) << DepthModeName(mode);
    EXPECT_EQ(out.valid.at<uint8_t>(y, x), 255) << DepthModeName(mode);
    const cv::Vec3f n = out.normal.at<cv::Vec3f>(y, x);
    EXPECT_NEAR(n[2], -1.0f, 1e-3) << DepthModeName(mode);
  }
}

TEST_F(DepthPassTest, AccuracyAndLeakage) {
  const AnalyticScene scene = AnalyticScene::SpheresAndPlane();
  const PointCloud pc = scene.Sample(40000);
  const Camera cam = test::TestCamera(256);
  DepthPass pass(*shaders_);
  pass.SetPoints(pc);
  std::map<DepthMode, double> worst_acc, worst_leak;
  for (DepthMode mode : AllDepthModes()) {
    double acc = 0, leak = 0;
    worst_acc[mode] = 1;
    worst_leak[mode] = 0;
    const auto views = AccuracyViews();
    for (const Rigid3d& view : views) {
      const cv::Mat gt = scene.GroundTruthDepth(cam, view);
      const cv::Mat depth = Render(pass, cam, view, mode).depth;
      const test::DepthCounts s = test::CompareDepth(
          depth, gt, DepthModeName(mode) + "_" + std::to_string(&view - views.data()));
      acc += s.accuracy() / views.size();
      leak += s.leakage() / views.size();
      worst_acc[mode] = std::min(worst_acc[mode], s.accuracy());
      worst_leak[mode] = std::max(worst_leak[mode], s.leakage());
    }
    std::printf(
        "[ figures  ] %-9s accuracy(1%%) %.2f%% (worst view %.2f%%)  leakage %.3f%% "
        "(worst %.3f%%)\n",
        DepthModeName(mode).c_str(), 100 * acc, 100 * worst_acc[mode], 100 * leak,
        100 * worst_leak[mode]);
  }
  // Regression bounds a little below / above the figures measured (worst view, Mesa llvmpipe):
  // plain 95.9% / 0.10%, marroquim 92.1% / 7.0%, lechelek 98.7% / 0.07% (silhouette trim on;
  // 98.5% / 0.03% without).
  // plain: constant-depth splats err on slanted surfaces but hardly leak.
  EXPECT_GE(worst_acc[DepthMode::kPlain], 0.955);
  EXPECT_LE(worst_leak[DepthMode::kPlain], 0.002);
  // marroquim: pull-push fills the holes of the foreground with the surfaces behind it.
  EXPECT_GE(worst_acc[DepthMode::kMarroquim], 0.915);
  EXPECT_LE(worst_leak[DepthMode::kMarroquim], 0.08);
  EXPECT_GE(worst_leak[DepthMode::kMarroquim], 0.03);
  // lechelek: the most accurate, and it does not leak.
  EXPECT_GE(worst_acc[DepthMode::kLechelek], 0.985);
  EXPECT_LE(worst_leak[DepthMode::kLechelek], 0.001);
  EXPECT_GT(worst_acc[DepthMode::kLechelek], worst_acc[DepthMode::kPlain]);
  EXPECT_GT(worst_acc[DepthMode::kPlain], worst_acc[DepthMode::kMarroquim]);
  EXPECT_LT(worst_leak[DepthMode::kLechelek], worst_leak[DepthMode::kPlain]);
}

// A preview at a quarter of the size (detail 0.25) draws every 8th point with splats sqrt(8)
// times wider: twice the points per pixel of the full-size pass. Strides are powers of 2 from 4
// up to 1 / (2 detail^2); levels stop at 16384 points. With every point, ~160 a pixel, the nearest
// in each pixel's footprint wins (on slanted surfaces nearer than the depth at the pixel's centre):
// measured on Mesa llvmpipe, accuracy within 1% 93.25% with every point in every mode, 96.02%
// (lechelek) / 94.95% (plain) with every 8th, both covering every pixel; leakage 0.009% (0.061%
// marroquim).
TEST_F(DepthPassTest, ReducedDetailDrawsACoarserLevelOfTheCloud) {
  const AnalyticScene scene = AnalyticScene::SpheresAndPlane();
  const size_t n = 640000;
  DepthPass pass(*shaders_);
  pass.SetPoints(scene.Sample(static_cast<int>(n)));
  const Camera full = test::TestCamera(256);
  const Camera small = full.Scaled(64, 64);
  DepthTarget target = DepthTarget::Create(64, 64);
  const std::map<double, size_t> drawn = {{1.0, n},         {0.6, n},      {0.5, n},
                                          {1.0 / 3, n / 4}, {0.25, n / 8}, {0.2, n / 8},
                                          {0.125, n / 32},  {0.1, n / 32}};
  for (const auto& [detail, count] : drawn) {
    pass.Process(small, Rigid3d(), target, detail);
    EXPECT_NEAR(static_cast<double>(pass.last_point_count()), static_cast<double>(count), 1.0)
        << "detail " << detail;
  }
  // The loop above built each level from the whole cloud (coarsest first); fine to coarse, each
  // is built from the finest one already built (4 -> 8 -> 32): the same points and sizes.
  DepthPass fine_first(*shaders_);
  fine_first.SetPoints(scene.Sample(static_cast<int>(n)));
  DepthTarget other = DepthTarget::Create(64, 64);
  const Rigid3d side = AccuracyViews().back();
  for (double detail : {1.0 / 3, 0.25, 0.125}) {
    fine_first.Process(small, side, other, detail);
    pass.Process(small, side, target, detail);
    EXPECT_EQ(fine_first.last_point_count(), pass.last_point_count()) << "detail " << detail;
    const cv::Mat a = ReadDepthTarget(other).depth, b = ReadDepthTarget(target).depth;
    EXPECT_LE(cv::countNonZero(cv::abs(a - b) > 1e-4f), 4) << "detail " << detail;
  }
  for (const auto& [raster, mode] : RastersAndModes()) {
    pass.options().raster = raster;
    pass.options().mode = mode;
    test::DepthCounts every, coarse;
    for (const Rigid3d& view : AccuracyViews()) {
      const cv::Mat gt = scene.GroundTruthDepth(small, view);
      pass.Process(small, view, target, 1.0);
      every += test::CompareDepth(ReadDepthTarget(target).depth, gt);
      pass.Process(small, view, target, 0.25);
      coarse += test::CompareDepth(ReadDepthTarget(target).depth, gt);
    }
    std::printf(
        "[ figures  ] %-9s %-8s 64x64, every point / every 8th: accuracy(1%%) %.2f%% / "
        "%.2f%%, leakage %.3f%% / %.3f%%, coverage %.2f%% / %.2f%%\n",
        DepthModeName(mode).c_str(), PointRasterName(raster).c_str(), 100 * every.accuracy(),
        100 * coarse.accuracy(), 100 * every.leakage(), 100 * coarse.leakage(),
        100 * every.coverage(), 100 * coarse.coverage());
    EXPECT_GE(coarse.coverage(), every.coverage() - 0.001)
        << DepthModeName(mode) << " " << PointRasterName(raster);
    EXPECT_GE(coarse.accuracy(), every.accuracy())
        << DepthModeName(mode) << " " << PointRasterName(raster);
    EXPECT_LE(coarse.leakage(), 0.001) << DepthModeName(mode) << " " << PointRasterName(raster);
  }
}

TEST_F(DepthPassTest, StepOnePinholesAreCoveredGapsAreNot) {
  // One point per pixel centre of a plane at z = 2 whose splats cover only their own pixel,
  // with points left out: single pixels and a pair (pinholes: every uncovered pixel has at most
  // one uncovered neighbour) and a run of three (its middle has two). lechelek fills the
  // pinholes from the foreground pull-push and keeps the run's middle and the plane's outside
  // invalid; plain (step 1 alone) leaves every left-out pixel invalid.
  const Camera cam = test::TestCamera(64);
  const std::vector<cv::Point> pinholes = {{20, 20}, {40, 25}, {30, 40}, {31, 40}};
  const std::vector<cv::Point> run = {{20, 50}, {21, 50}, {22, 50}};
  const auto left_out = [&](int x, int y) {
    for (const auto& list : {pinholes, run}) {
      for (const cv::Point& q : list) {
        if (q.x == x && q.y == y) return true;
      }
    }
    return false;
  };
  PointCloud pc;
  for (int y = 8; y < 56; ++y) {
    for (int x = 8; x < 56; ++x) {
      if (left_out(x, y)) continue;
      pc.positions.push_back((2.0 * cam.CamFromPixel({x + 0.5, y + 0.5})).cast<float>());
      pc.normals.push_back(Eigen::Vector3f(0, 0, -1));
      pc.radii.push_back(static_cast<float>(0.3 * 2.0 / cam.fx()));  // 0.3 px
    }
  }
  DepthPass pass(*shaders_);
  pass.SetPoints(pc);
  const DepthImages plain = Render(pass, cam, Rigid3d(), DepthMode::kPlain);
  const DepthImages lechelek = Render(pass, cam, Rigid3d(), DepthMode::kLechelek);
  for (const cv::Point& q : pinholes) {
    EXPECT_EQ(plain.valid.at<uint8_t>(q), 0) << q;
    EXPECT_EQ(lechelek.valid.at<uint8_t>(q), 255) << q;
    EXPECT_NEAR(lechelek.depth.at<float>(q) / 2.0f, 1.0f, 0.01f) << q;
  }
  EXPECT_EQ(plain.valid.at<uint8_t>(run[1]), 0);
  EXPECT_EQ(lechelek.valid.at<uint8_t>(run[1]), 0);
  // The plane is 48 x 48 pixels less the left-out ones, the run's middle invalid in lechelek.
  EXPECT_EQ(cv::countNonZero(plain.valid), 48 * 48 - 7);
  EXPECT_EQ(cv::countNonZero(lechelek.valid), 48 * 48 - 1);
}

TEST_F(DepthPassTest, ClassesOfTwoLayers) {
  // A near point (z = 2, splat radius about 2 px) in front of the centre of a far disc (z = 4,
  // radius about 20 px): in step 2 the far point is background (its centre is hidden), the
  // foreground pull-push holds the near point only, so the far disc around it is background
  // filling the foreground's hole (class 2, step 5) and the near pixels are front (class 1).
  // plain and marroquim: 1 on every valid pixel. Class 0 exactly where the output is invalid.
  const Camera cam = test::TestCamera(128);
  const double px_at_4 = 4.0 / cam.fx();  // world units of one pixel at z = 4
  PointCloud pc;
  auto add = [&](const Eigen::Vector3d& p, double radius) {
    pc.positions.push_back(p.cast<float>());
    pc.normals.push_back(Eigen::Vector3f(0, 0, -1));
    pc.radii.push_back(static_cast<float>(radius));
  };
  const Eigen::Vector3d far(3 * px_at_4, -2 * px_at_4, 4.0);
  add(far, 20 * px_at_4);
  add(0.5 * far, 2 * px_at_4 / 2);  // same ray, half as far: 2 px
  DepthPass pass(*shaders_);
  pass.SetPoints(pc);
  for (DepthMode mode : AllDepthModes()) {
    pass.options().mode = mode;
    DepthTarget target = DepthTarget::Create(cam.width, cam.height);
    pass.Process(cam, Rigid3d(), target);
    const DepthImages out = ReadDepthTarget(target);
    const cv::Mat classes = test::ReadTextureR8UI(target.classes);
    const auto is = [&](DepthClass c) { return classes == static_cast<uint8_t>(c); };
    const cv::Mat back = is(DepthClass::kBackground);
    const cv::Mat near_px = (out.depth > 0) & (out.depth < 3.0);
    std::printf("[ figures  ] %-9s classes: front %d background %d invalid %d (near %d)\n",
                DepthModeName(mode).c_str(), cv::countNonZero(is(DepthClass::kFront)),
                cv::countNonZero(back), cv::countNonZero(is(DepthClass::kInvalid)),
                cv::countNonZero(near_px));
    EXPECT_EQ(cv::countNonZero(is(DepthClass::kInvalid) != (out.valid == 0)), 0)
        << DepthModeName(mode);
    EXPECT_EQ(cv::countNonZero(classes > 2), 0) << DepthModeName(mode);
    EXPECT_GT(cv::countNonZero(near_px), 0) << DepthModeName(mode);
    EXPECT_EQ(cv::countNonZero(near_px & ~is(DepthClass::kFront)), 0) << DepthModeName(mode);
    if (mode != DepthMode::kLechelek) {
      EXPECT_EQ(cv::countNonZero(back), 0) << DepthModeName(mode);
      continue;
    }
    EXPECT_GT(cv::countNonZero(back), 0);
    // Background pixels show the wall.
    EXPECT_EQ(cv::countNonZero(back & (cv::abs(out.depth - 4.0f) > 0.04f)), 0);
  }
}

TEST_F(DepthPassTest, SilhouetteStabilityOverOrbit) {
  // Smooth 60-frame orbit (6 degrees in all, about 0.4 pixel of motion per frame) around the
  // spheres. A silhouette moving smoothly crosses a pixel once; a toggle is a pixel of the
  // silhouette band (3 px around the GT silhouette) whose coverage flips and flips back on the
  // next frame (on, off, on or off, on, off): flicker.
  const AnalyticScene scene = AnalyticScene::SpheresOnly();
  const PointCloud pc = scene.Sample(20000);
  const Camera cam = test::TestCamera(256);
  DepthPass pass(*shaders_);
  pass.SetPoints(pc);
  const Eigen::Vector3d target(0, 0.07, 2.8), up(0, -1, 0);
  std::vector<cv::Mat> bands;
  std::vector<Rigid3d> views;
  for (int f = 0; f < 60; ++f) {
    const double a = (-3.0 + 6.0 * f / 59.0) * M_PI / 180.0;
    const Eigen::Vector3d eye = target + 2.8 * Eigen::Vector3d(std::sin(a), 0.0, -std::cos(a));
    views.push_back(LookAt(eye, target, up));
    bands.push_back(test::SilhouetteBand(scene.GroundTruthDepth(cam, views.back()), 3));
  }
  std::map<DepthMode, double> toggles;
  for (DepthMode mode : AllDepthModes()) {
    std::vector<cv::Mat> cov;
    for (const Rigid3d& view : views) cov.push_back(Render(pass, cam, view, mode).depth > 0);
    long count = 0;
    for (size_t f = 1; f + 1 < views.size(); ++f) {
      const cv::Mat flicker = ~(cov[f - 1] ^ cov[f + 1]) & (cov[f] ^ cov[f - 1]);
      count += cv::countNonZero(flicker & bands[f]);
    }
    toggles[mode] = count / double(views.size() - 2);
    std::printf("[ figures  ] %-9s silhouette toggles per frame %.1f\n",
                DepthModeName(mode).c_str(), toggles[mode]);
  }
  // Measured (Mesa llvmpipe): plain 0.3, marroquim 2.5, lechelek 0.3. Pull-push of the
  // whole image (marroquim) makes the silhouette flicker; the constant-depth splats of plain
  // and lechelek's layered pull-push do not.
  EXPECT_GE(toggles[DepthMode::kMarroquim], 1.5);
  EXPECT_LE(toggles[DepthMode::kPlain], 1.0);
  EXPECT_LE(toggles[DepthMode::kLechelek], 1.0);
  EXPECT_LE(toggles[DepthMode::kLechelek], 0.5 * toggles[DepthMode::kMarroquim]);
}

TEST_F(DepthPassTest, LayeredClassificationEqualsTwoDraws) {
  const AnalyticScene scene = AnalyticScene::SpheresAndPlane();
  DepthPass pass(*shaders_);
  pass.options().raster = PointRaster::kPipeline;  // the compute raster has no draws
  pass.SetPoints(scene.Sample(10000));
  const Camera cam = test::TestCamera(128);
  const cv::Mat layered = Render(pass, cam, AccuracyViews()[1], DepthMode::kLechelek).depth;
  pass.options().layered_classify = false;
  const cv::Mat two_draws = Render(pass, cam, AccuracyViews()[1], DepthMode::kLechelek).depth;
  EXPECT_GT(cv::countNonZero(layered), 128 * 128 / 2);
  EXPECT_EQ(cv::norm(layered, two_draws, cv::NORM_INF), 0.0);
}

// The compute raster (default) and the graphics pipeline cover the same pixels with the same
// splats: their depths agree within 1% (the accuracy tolerance) and, the pipeline's points
// being depth-tested on a depth linear in camera z (shaders/points.glsl), within 1e-4 except
// where rounding on a splat's border flips a pixel: plain (step 1 alone) 100.0% (73.6% with
// the perspective depth, which separates splats only to about 0.6% of far with near =
// far * 1e-5), marroquim 99.86%, lechelek 99.79%. The image border is left out: GL clips a
// point sprite whose centre is off-screen, the compute raster still draws its on-screen part.
TEST_F(DepthPassTest, ComputeAndPipelineRastersAgree) {
  const AnalyticScene scene = AnalyticScene::SpheresAndPlane();
  DepthPass pass(*shaders_);
  pass.SetPoints(scene.Sample(20000));
  const Camera cam = test::TestCamera(160);
  for (DepthMode mode : AllDepthModes()) {
    test::DepthCounts counts, tight;
    int n = 0;
    for (const Rigid3d& view : AccuracyViews()) {
      pass.options().raster = PointRaster::kPipeline;
      const DepthImages pipeline = Render(pass, cam, view, mode);
      pass.options().raster = PointRaster::kCompute;
      const DepthImages compute = Render(pass, cam, view, mode);
      const cv::Rect inner(4, 4, cam.width - 8, cam.height - 8);
      counts += test::CompareDepth(compute.depth(inner), pipeline.depth(inner),
                                   "raster_" + DepthModeName(mode) + std::to_string(++n));
      tight += test::CompareDepth(compute.depth(inner), pipeline.depth(inner), "", 1e-4);
    }
    // Pixels valid in one raster only, as a share of all (inner) pixels.
    const double differ =
        double(counts.missing + counts.spurious) / (counts.covered + counts.empty);
    std::printf(
        "[ figures  ] %-9s compute vs pipeline raster: depth within 1%% on %.3f%% of the "
        "pipeline's valid pixels (within 1e-4: %.3f%%), valid in one raster only %.3f%% of "
        "the pixels\n",
        DepthModeName(mode).c_str(), 100 * counts.accuracy(), 100 * tight.accuracy(), 100 * differ);
    EXPECT_GE(counts.accuracy(), 0.995) << DepthModeName(mode);
    EXPECT_GE(tight.accuracy(), mode == DepthMode::kPlain ? 0.999 : 0.995) << DepthModeName(mode);
    EXPECT_LE(differ, 0.002) << DepthModeName(mode);
  }
}

// Clouds beyond one storage block (4M points on llvmpipe) are rasterised in several
// dispatches over ranges of the point buffer: forced here with small ranges, the output is the
// same as in one dispatch.
TEST_F(DepthPassTest, ComputeRasterSplitIntoDispatchesGivesTheSameOutput) {
  const AnalyticScene scene = AnalyticScene::SpheresAndPlane();
  DepthPass pass(*shaders_);
  pass.SetPoints(scene.Sample(10000));
  const Camera cam = test::TestCamera(128);
  for (DepthMode mode : AllDepthModes()) {
    pass.options().points_per_dispatch = 0;
    const DepthImages whole = Render(pass, cam, AccuracyViews()[1], mode);
    pass.options().points_per_dispatch = 999;  // 11 ranges, the last one partial
    const DepthImages split = Render(pass, cam, AccuracyViews()[1], mode);
    EXPECT_GT(cv::countNonZero(whole.depth), 128 * 128 / 2) << DepthModeName(mode);
    EXPECT_EQ(cv::norm(whole.depth, split.depth, cv::NORM_INF), 0.0) << DepthModeName(mode);
  }
}

TEST_F(DepthPassTest, EmptyCloud) {
  DepthPass pass(*shaders_);
  pass.SetPoints(PointCloud{});
  for (DepthMode mode : AllDepthModes()) {
    const DepthImages out = Render(pass, test::TestCamera(32), Rigid3d(), mode);
    EXPECT_EQ(cv::countNonZero(out.valid), 0);
    EXPECT_EQ(cv::countNonZero(out.depth), 0);
  }
}

TEST_F(DepthPassTest, AllPointsBehindCamera) {
  const AnalyticScene scene = AnalyticScene::SpheresAndPlane();
  PointCloud pc = scene.Sample(5000);
  for (auto& p : pc.positions) p.z() = -p.z();
  DepthPass pass(*shaders_);
  pass.SetPoints(pc);
  for (DepthMode mode : AllDepthModes()) {
    const DepthImages out = Render(pass, test::TestCamera(64), Rigid3d(), mode);
    EXPECT_EQ(cv::countNonZero(out.valid), 0) << DepthModeName(mode);
  }
}

TEST_F(DepthPassTest, NoNormalsNoRadiiGiveViewFacingDiscs) {
  // A fronto-parallel plane without normals or radii: the heuristic radius and view-facing
  // discs must still cover it with correct depth.
  AnalyticScene scene;
  scene.has_plane = true;
  scene.plane_z = 3.0;
  scene.plane_half = 1.0;
  PointCloud pc = scene.Sample(20000);
  pc.normals.clear();
  pc.radii.clear();
  EXPECT_GT(DefaultSplatRadius(pc), 0.0f);
  const Camera cam = test::TestCamera(128);
  const cv::Mat gt = scene.GroundTruthDepth(cam, Rigid3d());
  DepthPass pass(*shaders_);
  pass.SetPoints(pc);
  for (DepthMode mode : AllDepthModes()) {
    const DepthImages out = Render(pass, cam, Rigid3d(), mode);
    const test::DepthCounts s = test::CompareDepth(out.depth, gt);
    std::printf("[ figures  ] %-9s no normals: accuracy %.2f%%\n", DepthModeName(mode).c_str(),
                100 * s.accuracy());
    EXPECT_GE(s.accuracy(), 0.9) << DepthModeName(mode);
    const cv::Vec3f n = out.normal.at<cv::Vec3f>(64, 64);  // centre: view-facing = -z
    EXPECT_NEAR(n[2], -1.0f, 1e-2);
  }
}

TEST_F(DepthPassTest, CameraInsideCloud) {
  // Camera at the centre of a sphere of points: every pixel sees the sphere at known depth.
  AnalyticScene scene;
  scene.spheres = {{Eigen::Vector3d(0, 0, 0), 1.0}};
  const PointCloud pc = scene.Sample(20000);
  const Camera cam = test::TestCamera(128);
  const cv::Mat gt = scene.GroundTruthDepth(cam, Rigid3d());
  DepthPass pass(*shaders_);
  pass.SetPoints(pc);
  for (DepthMode mode : AllDepthModes()) {
    const test::DepthCounts s = test::CompareDepth(Render(pass, cam, Rigid3d(), mode).depth, gt);
    std::printf("[ figures  ] %-9s inside the cloud: accuracy %.2f%% coverage %.2f%%\n",
                DepthModeName(mode).c_str(), 100 * s.accuracy(), 100 * s.coverage());
    // Random sampling leaves ~1-2% of pixels uncovered by any splat (plain, lechelek).
    EXPECT_GE(s.coverage(), 0.97) << DepthModeName(mode);
    // Constant-depth splats (plain) err by r tan(off-axis angle) here; pull-push does not.
    if (mode != DepthMode::kPlain) {
      EXPECT_GE(s.accuracy(), 0.97) << DepthModeName(mode);
    }
  }
}

TEST_F(DepthPassTest, AnyResolutionAndDistortedCameraRefused) {
  const AnalyticScene scene = AnalyticScene::SpheresAndPlane();
  DepthPass pass(*shaders_);
  pass.SetPoints(scene.Sample(10000));
  const Camera cam = test::TestCamera(128);
  // Rendering a 128x128 camera into a 96x64 target rescales the intrinsics.
  const Camera scaled = cam.Scaled(96, 64);
  const cv::Mat gt = scene.GroundTruthDepth(scaled, Rigid3d());
  const DepthImages out = Render(pass, cam, Rigid3d(), DepthMode::kLechelek);
  EXPECT_EQ(out.depth.cols, 128);
  DepthTarget small = DepthTarget::Create(96, 64);
  pass.Process(cam, Rigid3d(), small);
  const test::DepthCounts s = test::CompareDepth(ReadDepthTarget(small).depth, gt);
  EXPECT_GE(s.accuracy(), 0.9);

  Camera distorted = cam;
  distorted.model = CameraModel::kSimpleRadial;
  distorted.params = {cam.fx(), cam.cx(), cam.cy(), 0.1};
  EXPECT_THROW(pass.Process(distorted, Rigid3d(), small), UsageError);
}

TEST_F(DepthPassTest, PhotoDepthMapsMatchSingleRenders) {
  const AnalyticScene scene = AnalyticScene::SpheresAndPlane();
  Scene s;
  s.cameras[1] = test::TestCamera(96);
  s.cameras[2] = test::TestCamera(64);
  const auto views = AccuracyViews();
  for (int i = 0; i < 3; ++i) {
    Photo p;
    p.id = i + 1;
    p.name = "p" + std::to_string(i);
    p.camera_id = i == 2 ? 2 : 1;
    p.cam_from_world = views[static_cast<size_t>(i)];
    s.photos.push_back(p);
  }
  s.points = scene.Sample(8000);
  DepthPass pass(*shaders_);
  pass.SetPoints(s.points);
  const PhotoDepthMaps maps(s, pass);
  ASSERT_EQ(maps.count(), 3);
  EXPECT_EQ(maps.depth().layers(), 3);
  EXPECT_EQ(maps.depth().width(), 96);
  for (int i = 0; i < 3; ++i) {
    const Camera& cam = s.CameraOf(s.photos[static_cast<size_t>(i)]);
    const cv::Mat single =
        Render(pass, cam, s.photos[static_cast<size_t>(i)].cam_from_world, DepthMode::kLechelek)
            .depth;
    const cv::Mat layer = ReadTextureLayerR32F(maps.depth(), i);
    const cv::Mat roi = layer(cv::Rect(0, 0, cam.width, cam.height));
    EXPECT_EQ(cv::norm(roi, single, cv::NORM_INF), 0.0) << "layer " << i;
    EXPECT_GT(cv::countNonZero(single), cam.width * cam.height / 2);
  }
}

}  // namespace
}  // namespace hdribr::render
