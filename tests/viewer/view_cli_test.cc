// `hdribr view` scripted under Xvfb (xvfb-run): its screenshot equals `hdribr render` of the
// same camera, exposure reaches the picture, a camera path plays back, and bad input fails
// cleanly. Skips with a message when xvfb-run is absent.
#include <gtest/gtest.h>

#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/camera_spec.h"
#include "io/exr.h"
#include "io/workspace.h"
#include "synth/capture.h"
#include "test_util.h"

namespace hdribr {
namespace {

// BGRA as written (ReadImage drops alpha).
cv::Mat ReadPng(const std::filesystem::path& path) {
  const cv::Mat m = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  EXPECT_FALSE(m.empty()) << path;
  return m;
}

bool HaveXvfb() { return std::system("command -v xvfb-run > /dev/null 2>&1") == 0; }

class ViewCliTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(test::TempDir("view_cli") / "capture");
    synth::CaptureOptions opt;
    opt.series = 2;
    opt.views = 4;
    opt.width = 128;
    opt.height = 96;
    opt.novel_views = 1;
    opt.threads = 2;
    synth::WriteCapture(opt, *dir_);
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override {
    if (!HaveXvfb()) GTEST_SKIP() << "xvfb-run is not installed: skipping the viewer tests";
  }
  static std::string Exe() { return HDRIBR_EXE; }
  static std::string Ws() { return (*dir_ / "workspace").string(); }
  static test::CommandResult View(const std::string& args) {
    return test::RunCommand("xvfb-run -a -s '-screen 0 640x480x24' " + Exe() + " view " + Ws() +
                            " " + args);
  }
  static std::filesystem::path* dir_;
};
std::filesystem::path* ViewCliTest::dir_ = nullptr;

// Mean absolute difference (8-bit levels) over pixels valid in both, and the fraction of
// pixels whose validity (alpha) differs.
struct Comparison {
  double mad = 0;
  double max_diff = 0;
  double validity_mismatch = 0;
  int valid = 0;
};
Comparison Compare(const cv::Mat& a, const cv::Mat& b) {
  EXPECT_EQ(a.size(), b.size());
  EXPECT_EQ(a.type(), CV_8UC4);
  EXPECT_EQ(b.type(), CV_8UC4);
  std::vector<cv::Mat> ca, cb;
  cv::split(a, ca);
  cv::split(b, cb);
  const cv::Mat both = (ca[3] > 0) & (cb[3] > 0);
  Comparison c;
  c.validity_mismatch = cv::countNonZero(ca[3] != cb[3]) / static_cast<double>(a.total());
  c.valid = cv::countNonZero(both);
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  cv::cvtColor(diff, diff, cv::COLOR_BGRA2BGR);
  const cv::Scalar m = cv::mean(diff, both);
  c.mad = (m[0] + m[1] + m[2]) / 3;
  std::vector<cv::Mat> d;
  cv::split(diff, d);
  for (const cv::Mat& channel : d) {
    double v = 0;
    cv::minMaxLoc(channel, nullptr, &v, nullptr, nullptr, both);
    c.max_diff = std::max(c.max_diff, v);
  }
  return c;
}

TEST_F(ViewCliTest, ScreenshotMatchesOfflineRender) {
  const auto out = test::TempDir("view_cli_shot");
  auto r =
      View("--hdr ldr --camera s1_v01.jpg --frames 3 --screenshot " + (out / "view.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("screenshot"), std::string::npos) << r.output;
  r = test::RunCommand(Exe() + " render " + Ws() + " --camera s1_v01.jpg --out " +
                       (out / "render.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat view = ReadPng(out / "view.png");
  const cv::Mat render = ReadPng(out / "render.png");
  ASSERT_EQ(view.size(), cv::Size(128, 96));
  const Comparison c = Compare(view, render);
  std::printf("viewer vs render: %d valid pixels, validity mismatch %.5f, MAD %.3f, max %.0f\n",
              c.valid, c.validity_mismatch, c.mad, c.max_diff);
  EXPECT_GT(c.valid, 128 * 96 / 2);
  EXPECT_LT(c.validity_mismatch, 0.001);
  EXPECT_LT(c.mad, 0.5);       // 8-bit levels: rounding only
  EXPECT_LE(c.max_diff, 2.0);  // float -> unorm conversion on the GPU vs cv::saturate_cast
  // The comparison does tell views apart: another photo's viewpoint is far off.
  r = test::RunCommand(Exe() + " render " + Ws() + " --camera s1_v02.jpg --out " +
                       (out / "other.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Comparison other = Compare(view, ReadPng(out / "other.png"));
  EXPECT_GT(other.mad + 100 * other.validity_mismatch, 2.0);
  // The linear EXR next to it holds the blended values.
  const cv::Mat exr = ReadExr(out / "view.exr");
  ASSERT_EQ(exr.size(), cv::Size(128, 96));
}

TEST_F(ViewCliTest, ExposureChangesOnlyTheToneMappedPicture) {
  const auto out = test::TempDir("view_cli_exposure");
  for (const std::string ev : {"0", "1"}) {
    const auto r = View("--hdr ldr --camera s0_v02.jpg --tonemap on --gamma 2.2 --exposure " + ev +
                        " --screenshot " + (out / ("ev" + ev + ".png")).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const cv::Mat a = ReadPng(out / "ev0.png");
  const cv::Mat b = ReadPng(out / "ev1.png");
  std::vector<cv::Mat> ca, cb;
  cv::split(a, ca);
  cv::split(b, cb);
  EXPECT_EQ(cv::countNonZero(ca[3] != cb[3]), 0);  // same geometry
  const cv::Mat valid = ca[3] > 0;
  cv::Mat ga, gb;
  cv::cvtColor(a, ga, cv::COLOR_BGRA2GRAY);
  cv::cvtColor(b, gb, cv::COLOR_BGRA2GRAY);
  EXPECT_GT(cv::mean(gb, valid)[0], cv::mean(ga, valid)[0] + 10);  // +1 EV is brighter
  // The linear radiance does not depend on the exposure.
  const cv::Mat ea = ReadExr(out / "ev0.exr"), eb = ReadExr(out / "ev1.exr");
  EXPECT_LT(cv::norm(ea, eb, cv::NORM_INF), 1e-6);
}

TEST_F(ViewCliTest, BenchmarkReportsExposureVsCameraMove) {
  const auto r = View("--hdr ldr --camera s0_v00.jpg --benchmark");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("camera move"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("exposure change"), std::string::npos) << r.output;
}

TEST_F(ViewCliTest, PlaysACameraPath) {
  const auto out = test::TempDir("view_cli_play");
  const Scene scene = LoadWorkspace(Ws());
  CameraPath path;
  path.fps = 10;
  path.times_s = {0.0};
  path.keyframes = {ParseCameraSpec("s1_v03.jpg", scene)};
  WriteCameraPath(out / "path.json", path);
  auto r = View("--hdr ldr --camera s1_v00.jpg --play " + (out / "path.json").string() +
                " --frames 2 --screenshot " + (out / "play.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::RunCommand(Exe() + " render " + Ws() + " --camera s1_v03.jpg --out " +
                       (out / "render.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Comparison c = Compare(ReadPng(out / "play.png"), ReadPng(out / "render.png"));
  EXPECT_LT(c.validity_mismatch, 0.001);
  EXPECT_LT(c.mad, 0.5);
}

TEST_F(ViewCliTest, BadInputIsOneClearError) {
  auto r = View("--camera no_such_photo.jpg --frames 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("no_such_photo.jpg"), std::string::npos) << r.output;
  r = test::RunCommand(Exe() + " view /nonexistent/ws --frames 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("/nonexistent/ws"), std::string::npos) << r.output;
  r = View("--hdr precomputed --frames 1");  // no HDR set in this workspace
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("hdr"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace hdribr
