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
#include "support/test_capture.h"
#include "synth/capture.h"
#include "test_util.h"

namespace hdribr::render {
namespace {

TEST(SynthDepthTest, AccuracyOnSyntheticCapture) {
  const std::filesystem::path dir = test::TempDir("synth_depth") / "capture";
  test::WriteTestCapture(dir, {1, 4, 256, 192, 3});
  const Scene scene = LoadWorkspace(dir / "workspace");
  const ColmapModel novel = ReadColmapModel(dir / "gt" / "novel");
  ASSERT_FALSE(scene.points.empty());

  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  DepthPass pass(shaders);
  pass.SetPoints(scene.points);
  // Scores of the current options of `pass` at the input photos and at the novel views.
  struct Scores {
    test::DepthCounts input, novel;
  };
  auto score = [&](const std::string& tag) {
    Scores scores;
    auto render = [&](const Camera& cam, const Rigid3d& pose) {
      DepthTarget target = DepthTarget::Create(cam.width, cam.height);
      pass.Process(cam, pose, target);
      return ReadDepthTarget(target).depth;
    };
    for (const Photo& photo : scene.photos) {
      const std::string stem = std::filesystem::path(photo.name).stem().string();
      scores.input += test::CompareDepth(render(scene.CameraOf(photo), photo.cam_from_world),
                                         ReadExr(dir / "gt" / "depth" / (stem + ".exr")),
                                         "synth_" + tag + "_" + stem);
    }
    for (const auto& [id, image] : novel.images) {
      const std::string stem = std::filesystem::path(image.name).stem().string();
      scores.novel +=
          test::CompareDepth(render(novel.cameras.at(image.camera_id), image.cam_from_world),
                             ReadExr(dir / "gt" / "novel" / "depth" / (stem + ".exr")),
                             "synth_" + tag + "_novel_" + stem);
    }
    const test::DepthCounts& in = scores.input;
    const test::DepthCounts& nv = scores.novel;
    std::printf(
        "[ figures  ] synth %-9s accuracy(1%%) input %.2f%% novel %.2f%%  leakage input "
        "%.3f%% novel %.3f%%\n",
        tag.c_str(), 100 * in.accuracy(), 100 * nv.accuracy(), 100 * in.leakage(),
        100 * nv.leakage());
    std::printf(
        "[ figures  ] synth %-9s misses (share of covered) input: near %.2f%% deep %.2f%% "
        "missing %.2f%%; novel: near %.2f%% deep %.2f%% missing %.2f%%\n",
        tag.c_str(), 100 * in.Share(in.too_near), 100 * in.Share(in.too_deep),
        100 * in.Share(in.missing), 100 * nv.Share(nv.too_near), 100 * nv.Share(nv.too_deep),
        100 * nv.Share(nv.missing));
    return scores;
  };
  Scores trimmed;  // lechelek with the default options (silhouette trim on)
  for (DepthMode mode : AllDepthModes()) {
    pass.options().mode = mode;
    const Scores scores = score(DepthModeName(mode));
    if (mode == DepthMode::kLechelek) {
      trimmed = scores;
      // Leakage: at most 0.5 % of the covered pixels show a farther surface.
      EXPECT_LE(scores.input.leakage(), 0.005);
      EXPECT_LE(scores.novel.leakage(), 0.005);
      // Accuracy with the silhouette trim (docs/decisions/0011).
      EXPECT_GE(scores.input.accuracy(), 0.985);
      EXPECT_GE(scores.novel.accuracy(), 0.978);
    }
  }
  // The silhouette trim (resolve) takes the overhang band of the front splats off the
  // foreground: fewer too-near pixels at both kinds of view, more accurate overall.
  pass.options().mode = DepthMode::kLechelek;
  pass.options().silhouette_trim = 0;
  const Scores untrimmed = score("no-trim");
  EXPECT_LT(trimmed.input.too_near, untrimmed.input.too_near);
  EXPECT_LT(trimmed.novel.too_near, untrimmed.novel.too_near);
  EXPECT_GT(trimmed.input.accuracy(), untrimmed.input.accuracy());
  EXPECT_GT(trimmed.novel.accuracy(), untrimmed.novel.accuracy());
  EXPECT_EQ(gl::DrainGlErrors(), "");
}

}  // namespace
}  // namespace hdribr::render
