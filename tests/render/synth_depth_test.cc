// The depth pass on a small ground-truth synthetic capture (hdribr synth): accuracy and
// leakage against the ray-traced depth of the input photos and of the novel views.
#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/imgcodecs.hpp>

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

struct Scores {
  long covered = 0, accurate = 0, leak = 0;
  long too_near = 0, too_deep = 0, missing = 0;  // the misses, by kind
};

void Score(const cv::Mat& depth, const cv::Mat& gt, Scores& s, const std::string& tag = "") {
  if (const char* dump = std::getenv("HDRIBR_TEST_DUMP"); dump && !tag.empty()) {
    // Debug aid: green = within 1%, red = too deep, blue = too near, white = missing.
    cv::Mat img(gt.size(), CV_8UC3, cv::Scalar(0, 0, 0));
    for (int y = 0; y < gt.rows; ++y) {
      for (int x = 0; x < gt.cols; ++x) {
        const float g = gt.at<float>(y, x), d = depth.at<float>(y, x);
        cv::Vec3b c(0, 0, 0);
        if (g > 0 && d <= 0)
          c = {255, 255, 255};
        else if (g <= 0 && d > 0)
          c = {0, 255, 255};
        else if (g > 0 && std::abs(d - g) <= 0.01f * g)
          c = {0, 120, 0};
        else if (g > 0 && d > g)
          c = {0, 0, 255};
        else if (g > 0)
          c = {255, 0, 0};
        img.at<cv::Vec3b>(y, x) = c;
      }
    }
    cv::imwrite(std::string(dump) + "/" + tag + ".png", img);
  }
  for (int y = 0; y < gt.rows; ++y) {
    for (int x = 0; x < gt.cols; ++x) {
      const float g = gt.at<float>(y, x), d = depth.at<float>(y, x);
      if (g <= 0) continue;
      ++s.covered;
      if (d > 0 && std::abs(d - g) <= 0.01f * g) {
        ++s.accurate;
      } else if (d <= 0) {
        ++s.missing;
      } else if (d > g) {
        ++s.too_deep;
      } else {
        ++s.too_near;
      }
      if (d > g * 1.05f) ++s.leak;
    }
  }
}

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
    Scores input, novel_scores;
    auto render = [&](const Camera& cam, const Rigid3d& pose) {
      DepthTarget target = DepthTarget::Create(cam.width, cam.height);
      pass.Process(cam, pose, target);
      return ReadDepthTarget(target).depth;
    };
    for (const Photo& photo : scene.photos) {
      const std::string stem = std::filesystem::path(photo.name).stem().string();
      Score(render(scene.CameraOf(photo), photo.cam_from_world),
            ReadExr(dir / "gt" / "depth" / (stem + ".exr")), input,
            "synth_" + DepthModeName(mode) + "_" + stem);
    }
    for (const auto& [id, image] : novel.images) {
      const std::string stem = std::filesystem::path(image.name).stem().string();
      Score(render(novel.cameras.at(image.camera_id), image.cam_from_world),
            ReadExr(dir / "gt" / "novel" / "depth" / (stem + ".exr")), novel_scores);
    }
    const double acc_in = double(input.accurate) / input.covered;
    const double acc_novel = double(novel_scores.accurate) / novel_scores.covered;
    const double leak_in = double(input.leak) / input.covered;
    const double leak_novel = double(novel_scores.leak) / novel_scores.covered;
    std::printf(
        "[ figures  ] synth %-9s accuracy(1%%) input %.2f%% novel %.2f%%  leakage input "
        "%.3f%% novel %.3f%%\n",
        DepthModeName(mode).c_str(), 100 * acc_in, 100 * acc_novel, 100 * leak_in,
        100 * leak_novel);
    std::printf(
        "[ figures  ] synth %-9s misses (share of covered) input: near %.2f%% deep %.2f%% "
        "missing %.2f%%; novel: near %.2f%% deep %.2f%% missing %.2f%%\n",
        DepthModeName(mode).c_str(), 100.0 * input.too_near / input.covered,
        100.0 * input.too_deep / input.covered, 100.0 * input.missing / input.covered,
        100.0 * novel_scores.too_near / novel_scores.covered,
        100.0 * novel_scores.too_deep / novel_scores.covered,
        100.0 * novel_scores.missing / novel_scores.covered);
    if (mode == DepthMode::kLechelek) {
      // Issue 4 leakage target (met).
      EXPECT_LE(leak_in, 0.005);
      EXPECT_LE(leak_novel, 0.005);
      // The accuracy target (97%) is NOT reached on synth captures (measured 96.4%
      // input, 94.7% novel with the synth's radii: silhouettes grow by the splat overhang,
      // see docs/algorithms.md); it is asserted on the analytic scenes (depth_pass_test).
      // This is a regression floor below the measured figures, not the target.
      EXPECT_GE(acc_in, 0.95);
      EXPECT_GE(acc_novel, 0.93);
    }
  }
  EXPECT_EQ(gl::DrainGlErrors(), "");
}

}  // namespace
}  // namespace hdribr::render
