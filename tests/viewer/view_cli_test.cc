// `hdribr view` scripted under Xvfb (xvfb-run): its screenshot equals `hdribr render` of the
// same camera, exposure reaches the picture, a camera path plays back, and bad input fails
// cleanly. Skips with a message when xvfb-run is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "io/camera_spec.h"
#include "io/exr.h"
#include "io/workspace.h"
#include "support/cli_capture.h"

namespace hdribr {
namespace {
using test::Exe;

// BGRA as written (ReadImage drops alpha).
cv::Mat ReadPng(const std::filesystem::path& path) {
  const cv::Mat m = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  EXPECT_FALSE(m.empty()) << path;
  return m;
}

// The setup of the shared fixture SmallCapture2 (tests/viewer/CMakeLists.txt), read by every
// test of ViewCliTest.
TEST(Fixture, SmallCapture2) { test::RemakeSmallCaptureFixture(2); }

class ViewCliTest : public test::SmallCaptureTest<2> {
 protected:
  void SetUp() override {
    if (!test::HaveXvfb()) GTEST_SKIP() << "xvfb-run is not installed: skipping the viewer tests";
  }
  static test::CommandResult View(const std::string& args) {
    return test::RunUnderXvfb(Exe() + " view " + Ws() + " " + args);
  }
};

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
  ASSERT_EQ(view.size(), cv::Size(test::kSmallCaptureWidth, test::kSmallCaptureHeight));
  const Comparison c = Compare(view, render);
  std::printf("viewer vs render: %d valid pixels, validity mismatch %.5f, MAD %.3f, max %.0f\n",
              c.valid, c.validity_mismatch, c.mad, c.max_diff);
  EXPECT_GT(c.valid, test::kSmallCaptureWidth * test::kSmallCaptureHeight / 2);
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
  ASSERT_EQ(exr.size(), cv::Size(test::kSmallCaptureWidth, test::kSmallCaptureHeight));
  // The renderer options reach the viewer: without the background and the fill, the sky stays
  // empty in both, and the viewer matches render again.
  r = View("--hdr ldr --camera s1_v01.jpg --background none --no-fill --frames 3 --screenshot " +
           (out / "view_none.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::RunCommand(Exe() + " render " + Ws() +
                       " --camera s1_v01.jpg --background none --no-fill --out " +
                       (out / "render_none.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Comparison none = Compare(ReadPng(out / "view_none.png"), ReadPng(out / "render_none.png"));
  EXPECT_LT(none.validity_mismatch, 0.001);
  EXPECT_LT(none.mad, 0.5);
  std::printf("valid pixels: default background %d, none %d\n", c.valid, none.valid);
  EXPECT_LT(none.valid, c.valid - test::kSmallCaptureWidth * test::kSmallCaptureHeight / 50);
}

// Photos beyond the GPU memory budget load while the viewer draws (coarse copies meanwhile);
// the screenshot waits for them and equals the all-resident render.
TEST_F(ViewCliTest, PhotosBeyondTheGpuBudgetGiveTheSameScreenshot) {
  const auto out = test::TempDir("view_cli_budget");
  auto r = View(
      "--hdr ldr --camera s1_v01.jpg --candidates 4 --gpu-memory 0.7 --frames 3 "
      "--screenshot " +
      (out / "view.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("photo cache of 4 full-size slots"), std::string::npos) << r.output;
  r = test::RunCommand(Exe() + " render " + Ws() + " --camera s1_v01.jpg --candidates 4 --out " +
                       (out / "render.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("photo cache"), std::string::npos) << r.output;
  const Comparison c = Compare(ReadPng(out / "view.png"), ReadPng(out / "render.png"));
  EXPECT_LT(c.validity_mismatch, 0.001);
  EXPECT_LT(c.mad, 0.5);
  EXPECT_LE(c.max_diff, 2.0);
  // A budget that cannot hold the photos names the flag.
  r = View("--hdr ldr --camera s1_v01.jpg --gpu-memory 0.01 --frames 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--gpu-memory"), std::string::npos) << r.output;
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
  // The progressive orbit at a budget no frame meets: the smallest size, then full quality.
  EXPECT_NE(r.output.find("progressive, budget 100 ms"), std::string::npos) << r.output;
  const auto tiny = View("--hdr ldr --camera s0_v00.jpg --benchmark --frame-budget 0.01");
  ASSERT_EQ(tiny.exit_code, 0) << tiny.output;
  EXPECT_NE(tiny.output.find("mean size 12.5% of the window"), std::string::npos) << tiny.output;
  EXPECT_NE(tiny.output.find("full quality"), std::string::npos) << tiny.output;
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
  // With a frame budget no frame meets, the moving frame is reduced, and the screenshot is
  // still the full-quality picture.
  r = View("--hdr ldr --camera s1_v00.jpg --play " + (out / "path.json").string() +
           " --frame-budget 0.01 --frames 2 --screenshot " + (out / "play_budget.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Comparison b = Compare(ReadPng(out / "play_budget.png"), ReadPng(out / "render.png"));
  EXPECT_LT(b.validity_mismatch, 0.001);
  EXPECT_LT(b.mad, 0.5);
}

// The GPU-coloured debug displays equal `hdribr render --debug` of the same camera.
TEST_F(ViewCliTest, DebugDisplaysMatchRenderDebugMaps) {
  const auto out = test::TempDir("view_cli_debug");
  const std::pair<std::string, std::string> modes[] = {
      {"depth", "depth"}, {"normals", "normal"}, {"count", "count"}};
  for (const auto& [display, debug] : modes) {
    const std::string shot = (out / ("view_" + display + ".png")).string();
    auto r = View("--hdr ldr --camera s1_v01.jpg --display " + display + " --screenshot " + shot);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string ref = (out / ("render_" + debug + ".png")).string();
    r = test::RunCommand(Exe() + " render " + Ws() + " --camera s1_v01.jpg --debug " + debug +
                         " --out " + ref);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const cv::Mat view = ReadPng(shot);
    const cv::Mat render = cv::imread(ref, cv::IMREAD_COLOR);
    ASSERT_EQ(view.size(), render.size());
    std::vector<cv::Mat> c;
    cv::split(view, c);
    const cv::Mat valid = c[3] > 0;
    EXPECT_GT(cv::countNonZero(valid), test::kSmallCaptureWidth * test::kSmallCaptureHeight / 2)
        << display;
    cv::Mat bgr, diff, gray;
    cv::cvtColor(view, bgr, cv::COLOR_BGRA2BGR);
    cv::absdiff(bgr, render, diff);
    cv::cvtColor(diff, gray, cv::COLOR_BGR2GRAY);
    // Rounding only: a turbo index may step by one where t * 255 + 0.5 is at a boundary.
    const int off = cv::countNonZero(gray > 2);
    std::printf("display %s vs render --debug %s: %d of %d pixels differ by > 2\n", display.c_str(),
                debug.c_str(), off, cv::countNonZero(valid));
    EXPECT_LE(off, cv::countNonZero(valid) / 100) << display;
    // Pixels without depth are black in both.
    cv::Mat render_gray;
    cv::cvtColor(render, render_gray, cv::COLOR_BGR2GRAY);
    EXPECT_EQ(cv::countNonZero(render_gray & (valid == 0)), 0) << display;
  }
}

// Front/back classes of the depth pass: plain splatting marks every valid pixel front; the
// paper's mode marks each valid pixel front or background-filled.
TEST_F(ViewCliTest, ClassesDisplay) {
  const auto out = test::TempDir("view_cli_classes");
  for (const std::string mode : {"plain", "lechelek"}) {
    const std::string shot = (out / (mode + ".png")).string();
    const auto r = View("--hdr ldr --camera s1_v01.jpg --display classes --depth-mode " + mode +
                        " --screenshot " + shot);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const cv::Mat png = ReadPng(shot);
    std::vector<cv::Mat> c;
    cv::split(png, c);
    const int valid = cv::countNonZero(c[3]);
    cv::Mat bgr, front, filled;
    cv::cvtColor(png, bgr, cv::COLOR_BGRA2BGR);
    cv::inRange(bgr, cv::Scalar(25, 139, 254), cv::Scalar(27, 141, 255), front);   // orange
    cv::inRange(bgr, cv::Scalar(254, 114, 50), cv::Scalar(255, 116, 52), filled);  // blue
    const int n_front = cv::countNonZero(front), n_filled = cv::countNonZero(filled);
    std::printf("classes %s: %d valid, %d front, %d background-filled\n", mode.c_str(), valid,
                n_front, n_filled);
    EXPECT_GT(valid, test::kSmallCaptureWidth * test::kSmallCaptureHeight / 2) << mode;
    EXPECT_EQ(n_front + n_filled, valid) << mode;
    EXPECT_GT(n_front, valid / 2) << mode;
    if (mode == "plain") {
      EXPECT_EQ(n_filled, 0);
    }
  }
}

// Colour-per-point splats show the scene; the 3D frustums add only lines of their colours.
TEST_F(ViewCliTest, SplatsAndFrustums) {
  const auto out = test::TempDir("view_cli_splats");
  auto r = View("--hdr ldr --camera s1_v01.jpg --display splats --screenshot " +
                (out / "splats.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat splats = ReadPng(out / "splats.png");
  std::vector<cv::Mat> c;
  cv::split(splats, c);
  EXPECT_GT(cv::countNonZero(c[3]), test::kSmallCaptureWidth * test::kSmallCaptureHeight / 2);
  cv::Mat gray;
  cv::cvtColor(splats, gray, cv::COLOR_BGRA2GRAY);
  cv::Scalar mean, stddev;
  cv::meanStdDev(gray, mean, stddev, c[3]);
  EXPECT_GT(mean[0], 10.0);
  EXPECT_GT(stddev[0], 5.0);

  // The whole window (no panel) with and without frustums, from 1.5 scene scales behind the
  // first photo: the photos' frustums are in front, between the viewer and the object.
  const Scene scene = LoadWorkspace(Ws());
  Rigid3d pose = scene.photos[0].cam_from_world;
  pose.translation.z() += 1.5 * scene.scene_scale;
  const Eigen::Quaterniond& q = pose.rotation;
  char spec[256];
  std::snprintf(spec, sizeof(spec), "'%.9f %.9f %.9f %.9f %.9f %.9f %.9f'", q.w(), q.x(), q.y(),
                q.z(), pose.translation.x(), pose.translation.y(), pose.translation.z());
  for (const std::string f : {"", "--frustums"}) {
    r = View("--hdr ldr --camera " + std::string(spec) + " --hide-panel " + f +
             " --frames 3 --window-screenshot " + (out / ("window" + f + ".png")).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const cv::Mat plain = cv::imread((out / "window.png").string());
  const cv::Mat with = cv::imread((out / "window--frustums.png").string());
  ASSERT_EQ(plain.size(), with.size());
  auto candidate_lines = [](const cv::Mat& bgr) {  // the frame's candidate photos (green)
    cv::Mat green;
    cv::inRange(bgr, cv::Scalar(88, 254, 88), cv::Scalar(90, 255, 90), green);
    return cv::countNonZero(green);
  };
  auto lines = [&](const cv::Mat& bgr) {  // pixels of the frustum colours (BGR)
    cv::Mat a, b;
    cv::inRange(bgr, cv::Scalar(254, 198, 78), cv::Scalar(255, 200, 80), a);
    cv::inRange(bgr, cv::Scalar(0, 198, 254), cv::Scalar(1, 200, 255), b);
    return cv::countNonZero(a | b) + candidate_lines(bgr);
  };
  std::printf("frustum-coloured pixels: %d with (%d of candidates), %d without\n", lines(with),
              candidate_lines(with), lines(plain));
  EXPECT_GT(lines(with), 50);
  EXPECT_GT(candidate_lines(with), 10);
  EXPECT_LE(lines(plain), 2);
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
  // Screenshots in a format they cannot be written in: one line, before the window opens.
  for (const std::string bad : {"--screenshot shot.jpg", "--window-screenshot shot.exr"}) {
    r = View(bad);
    EXPECT_EQ(r.exit_code, 64) << bad << ": " << r.output;
    EXPECT_NE(r.output.find(bad.substr(0, bad.find(' ')) + ": must end in ."), std::string::npos)
        << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
}

}  // namespace
}  // namespace hdribr
