// The depth pass on a small ground-truth synthetic capture (hdribr synth): accuracy and
// leakage against the ray-traced depth of the input photos and of the novel views.
#include <gtest/gtest.h>

#include <cstdio>

#include "depth_compare.h"
#include "gl/context.h"
#include "gl/debug.h"
#include "io/colmap_model.h"
#include "io/exr.h"
#include "io/workspace.h"
#include "render/depth_pass.h"
#include "render/readback.h"
#include "synth/capture.h"
#include "test_util.h"

namespace hdribr::render {
namespace {

TEST(SynthDepthTest, AccuracyOnSyntheticCapture) {
  const std::filesystem::path dir = test::TempDir("synth_depth") / "capture";
  synth::CaptureOptions opt;
  opt.series = 1;
  opt.views = 4;
  opt.width = 256;
  opt.height = 192;
  opt.novel_views = 3;
  opt.threads = 2;
  synth::WriteCapture(opt, dir);
  const Scene scene = LoadWorkspace(dir / "workspace");
  const ColmapModel novel = ReadColmapModel(dir / "gt" / "novel");
  ASSERT_FALSE(scene.points.empty());

  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  DepthPass pass(shaders);
  pass.SetPoints(scene.points);
  for (DepthMode mode : AllDepthModes()) {
    pass.options().mode = mode;
    test::DepthCounts input, novel_scores;
    auto render = [&](const Camera& cam, const Rigid3d& pose) {
      DepthTarget target = DepthTarget::Create(cam.width, cam.height);
      pass.Process(cam, pose, target);
      return ReadDepthTarget(target).depth;
    };
    for (const Photo& photo : scene.photos) {
      const std::string stem = std::filesystem::path(photo.name).stem().string();
      input += test::CompareDepth(render(scene.CameraOf(photo), photo.cam_from_world),
                                  ReadExr(dir / "gt" / "depth" / (stem + ".exr")),
                                  "synth_" + DepthModeName(mode) + "_" + stem);
    }
    for (const auto& [id, image] : novel.images) {
      const std::string stem = std::filesystem::path(image.name).stem().string();
      novel_scores +=
          test::CompareDepth(render(novel.cameras.at(image.camera_id), image.cam_from_world),
                             ReadExr(dir / "gt" / "novel" / "depth" / (stem + ".exr")),
                             "synth_" + DepthModeName(mode) + "_novel_" + stem);
    }
    const double acc_in = input.accuracy();
    const double acc_novel = novel_scores.accuracy();
    const double leak_in = input.leakage();
    const double leak_novel = novel_scores.leakage();
    std::printf(
        "[ figures  ] synth %-9s accuracy(1%%) input %.2f%% novel %.2f%%  leakage input "
        "%.3f%% novel %.3f%%\n",
        DepthModeName(mode).c_str(), 100 * acc_in, 100 * acc_novel, 100 * leak_in,
        100 * leak_novel);
    std::printf(
        "[ figures  ] synth %-9s misses (share of covered) input: near %.2f%% deep %.2f%% "
        "missing %.2f%%; novel: near %.2f%% deep %.2f%% missing %.2f%%\n",
        DepthModeName(mode).c_str(), 100 * input.Share(input.too_near),
        100 * input.Share(input.too_deep), 100 * input.Share(input.missing),
        100 * novel_scores.Share(novel_scores.too_near),
        100 * novel_scores.Share(novel_scores.too_deep),
        100 * novel_scores.Share(novel_scores.missing));
    if (mode == DepthMode::kLechelek) {
      // Issue 4 leakage target (met).
      EXPECT_LE(leak_in, 0.005);
      EXPECT_LE(leak_novel, 0.005);
      // Issue 4 accuracy target (met since the synth's radii follow the local point spacing
      // like a reconstructed cloud's: 98.1% input, 97.1% novel views).
      EXPECT_GE(acc_in, 0.97);
      EXPECT_GE(acc_novel, 0.97);
    }
  }
  EXPECT_EQ(gl::DrainGlErrors(), "");
}

}  // namespace
}  // namespace hdribr::render
