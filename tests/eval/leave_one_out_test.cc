// The evaluation driver through the library (no CLI): leave-one-out on a small synthetic
// capture, every method scored on the same pixels, held-out photo really left out.
#include "eval/leave_one_out.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <optional>

#include "core/error.h"
#include "eval/hdr_novel.h"
#include "gl/context.h"
#include "io/workspace.h"
#include "support/test_capture.h"
#include "synth/capture.h"
#include "test_util.h"

namespace hdribr::eval {
namespace {

namespace fs = std::filesystem;

// HDRIBR_EVAL_CAPTURE=DIR evaluates an existing capture instead (for measurements by hand).
fs::path SmallCapture() {
  if (const char* env = std::getenv("HDRIBR_EVAL_CAPTURE")) return env;
  const fs::path dir = test::TempDir("loo_capture") / "cap";
  test::WriteTestCapture(dir, {2, 6, 200, 150, 2});
  return dir;
}

TEST(LeaveOneOut, ScoresEveryMethodOnTheSamePixels) {
  const fs::path cap = SmallCapture();
  const Scene scene = LoadWorkspace(cap / "workspace");
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  EvalOptions options;
  options.size_scale = std::getenv("HDRIBR_EVAL_CAPTURE") ? 0.5 : 1.0;
  options.out_dir = test::TempDir("loo_out");
  options.depth_source = "splat";
  const EvalReport report = RunEvaluation(scene, shaders, options);
  std::cout << FormatMeanTable(report);
  EXPECT_EQ(report.kind, "leave-one-out");
  ASSERT_FALSE(report.views.empty());
  for (const ViewReport& v : report.views) {
    ASSERT_EQ(v.methods.size(), 3u);
    EXPECT_GT(v.methods[0].scores.pixels, 0);
    for (const MethodScores& m : v.methods) {
      EXPECT_EQ(m.scores.pixels, v.methods[0].scores.pixels);
      EXPECT_GE(m.own_coverage, m.scores.coverage);
      EXPECT_GE(m.own_coverage, m.point_coverage);
      EXPECT_NEAR(static_cast<double>(m.own_scores.pixels), m.own_coverage * v.width * v.height,
                  0.5);
    }
    // The background adds pixels to hdribr's own; the colour-per-point baseline has none.
    EXPECT_GT(v.methods[0].own_coverage, v.methods[0].point_coverage);
    EXPECT_EQ(v.methods[2].own_coverage, v.methods[2].point_coverage);
  }
  const std::vector<MethodScores> mean = MeanScores(report);
  EXPECT_GT(mean[0].scores.psnr_db, mean[2].scores.psnr_db);  // hdribr beats colour per point
  EXPECT_TRUE(fs::exists(options.out_dir / "eval.json"));
  // The depth pass against the held-out photos' GT depth (full size only).
  std::cout << FormatDepthLine(report);
  const std::optional<DepthCounts> depth = TotalDepthCounts(report);
  if (options.size_scale == 1.0) {
    ASSERT_TRUE(depth.has_value());
    for (const ViewReport& v : report.views) {
      ASSERT_TRUE(v.depth.has_value());
      EXPECT_EQ(v.depth->covered + v.depth->empty, static_cast<long>(v.width) * v.height);
    }
    EXPECT_GT(depth->accuracy(), 0.97);
    EXPECT_LT(depth->leakage(), 0.005);
  } else {
    EXPECT_FALSE(depth.has_value());
    EXPECT_EQ(report.settings.at("depth_accuracy"), "needs --size-scale 1");
  }

  // Ground truth novel views of the same capture, with the perfect-depth reference ("auto"
  // finds the capture's GT depth): scored on the same pixels, close to hdribr.
  options.gt_capture = cap;
  options.out_dir.clear();
  options.depth_source = "auto";
  const EvalReport gt = RunEvaluation(scene, shaders, options);
  std::cout << FormatMeanTable(gt);
  EXPECT_EQ(gt.kind, "gt-novel");
  ASSERT_FALSE(gt.views.empty());
  for (const ViewReport& v : gt.views) {
    ASSERT_EQ(v.methods.size(), 4u);
    EXPECT_EQ(v.methods[1].method, "gt_depth");
    EXPECT_EQ(v.methods[1].scores.pixels, v.methods[0].scores.pixels);
    EXPECT_GT(v.methods[1].own_coverage, 0.9 * v.methods[0].own_coverage);
    EXPECT_NEAR(v.methods[1].scores.psnr_db, v.methods[0].scores.psnr_db, 3.0);
    EXPECT_EQ(v.depth.has_value(), options.size_scale == 1.0);
  }
  std::cout << FormatDepthLine(gt);
  // HDR-NeRF's figures at the same views: radiance re-exposed at the input and at new
  // exposures, and the mu-law HDR score.
  const HdrNovelReport hdr = RunHdrNovelEvaluation(scene, shaders, options);
  std::cout << FormatHdrNovelTable(hdr);
  EXPECT_EQ(hdr.oe_times_s.size(), 2u);
  EXPECT_EQ(hdr.ne_times_s.size(), 3u);
  ASSERT_EQ(hdr.methods.size(), 2u);
  EXPECT_EQ(hdr.views, static_cast<int>(gt.views.size()));
  EXPECT_GT(hdr.methods[0].ldr_oe.psnr_db, 25.0);
  EXPECT_GT(hdr.methods[0].ldr_ne.psnr_db, 25.0);
  EXPECT_GT(hdr.methods[0].hdr.psnr_db, 25.0);
  EXPECT_LT(hdr.methods[0].log_ratio, 0.1);
  EXPECT_GT(hdr.methods[0].ldr_oe.psnr_db, hdr.methods[1].ldr_oe.psnr_db);

  // "gt" on a workspace whose cameras are not the capture's is refused.
  Scene moved = scene;
  moved.photos[0].cam_from_world.translation.x() += 0.1;
  options.depth_source = "gt";
  EXPECT_THROW(RunEvaluation(moved, shaders, options), UsageError);
  options.depth_source = "depth";
  EXPECT_THROW(RunEvaluation(scene, shaders, options), UsageError);
  options.depth_source = "auto";

  // --series all with two exposures: every photo rendered in radiance from all the others and
  // re-exposed at its own exposure (LDR-OE), the response calibrated from the cloud on the fly.
  options.gt_capture.clear();
  options.series = "all";
  const EvalReport all = RunEvaluation(scene, shaders, options);
  std::cout << FormatMeanTable(all);
  EXPECT_EQ(all.views.size(), scene.photos.size());
  EXPECT_EQ(all.settings.at("response"), "calibrated from the point cloud");
  ASSERT_EQ(all.views[0].methods.size(), 3u);  // no colour per point in radiance
  const std::vector<MethodScores> all_mean = MeanScores(all);
  EXPECT_EQ(all_mean[2].method, "nearest_photo");
  EXPECT_GT(all_mean[0].scores.psnr_db, all_mean[2].scores.psnr_db);
  EXPECT_GT(all_mean[0].scores.psnr_db, 25.0);
  options.series.clear();

  options.photos = {"missing.jpg"};
  EXPECT_THROW(RunEvaluation(scene, shaders, options), UsageError);
}

}  // namespace
}  // namespace hdribr::eval
