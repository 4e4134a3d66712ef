// `hdribr demo --headless` end to end on a tiny capture: the printed output paths exist, the
// orbit's PNG frames and EXRs are valid and show the scene, and a second run reuses the
// capture and the HDR photo set and renders the same frames.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>

#include "io/exr.h"
#include "test_util.h"

namespace hdribr {
namespace {

namespace fs = std::filesystem;

// The path printed after `label` on a line of the demo's summary ("  orbit:     /x/y/...").
std::string PrintedPath(const std::string& output, const std::string& label) {
  std::smatch m;
  const std::regex re("\\n  " + label + ":\\s+(\\S+)");
  return std::regex_search(output, m, re) ? m[1].str() : std::string();
}

struct DemoRun {
  test::CommandResult result;
  double seconds = 0;
};

DemoRun RunDemo(const fs::path& out) {
  const auto t0 = std::chrono::steady_clock::now();
  DemoRun r;
  r.result = test::RunCommand(std::string(HDRIBR_EXE) + " demo --headless --out " + out.string() +
                              " --size 96x72 --series 2 --views 3 --frames 3 --threads 2");
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("demo run: %.1f s\n", r.seconds);
  return r;
}

TEST(DemoCliTest, HeadlessOrbitThenReuse) {
  const fs::path out = test::TempDir("demo") / "demo";
  const DemoRun first = RunDemo(out);
  ASSERT_EQ(first.result.exit_code, 0) << first.result.output;
  const std::string& log = first.result.output;
  EXPECT_NE(log.find("[1/4] capture: rendering"), std::string::npos) << log;
  EXPECT_NE(log.find("[3/4] HDR photo set: calibrating"), std::string::npos) << log;

  // Every path of the summary exists.
  const fs::path capture = PrintedPath(log, "capture");
  const fs::path workspace = PrintedPath(log, "workspace");
  const std::string orbit_pattern = PrintedPath(log, "orbit");
  ASSERT_FALSE(capture.empty() || workspace.empty() || orbit_pattern.empty()) << log;
  EXPECT_TRUE(fs::is_directory(capture)) << capture;
  EXPECT_TRUE(fs::exists(workspace / "series.json")) << workspace;
  EXPECT_TRUE(fs::exists(workspace / "hdr" / "hdr_set.json")) << workspace;
  const fs::path orbit = fs::path(orbit_pattern).parent_path();
  EXPECT_EQ(orbit, out / "orbit");
  EXPECT_TRUE(fs::exists(orbit / "path.json"));
  EXPECT_TRUE(fs::exists(orbit / "frame_0002.png"));
  EXPECT_FALSE(fs::exists(orbit / "frame_0003.png"));  // --frames 3

  std::vector<cv::Mat> frames;
  for (const char* name : {"frame_0000", "frame_0001"}) {
    const cv::Mat png = cv::imread((orbit / (std::string(name) + ".png")).string());
    ASSERT_FALSE(png.empty()) << name;
    ASSERT_EQ(png.size(), cv::Size(96, 72)) << name;
    // Non-trivial: most pixels show the scene, with some contrast.
    cv::Mat gray;
    cv::cvtColor(png, gray, cv::COLOR_BGR2GRAY);
    cv::Scalar mean, stddev;
    cv::meanStdDev(gray, mean, stddev);
    EXPECT_GT(cv::countNonZero(gray > 0), 96 * 72 / 2) << name;
    EXPECT_GT(stddev[0], 5.0) << name;
    EXPECT_GT(mean[0], 20.0) << name;
    EXPECT_LT(mean[0], 235.0) << name;
    const cv::Mat exr = ReadExr(orbit / (std::string(name) + ".exr"));
    ASSERT_EQ(exr.size(), cv::Size(96, 72)) << name;
    ASSERT_EQ(exr.type(), CV_32FC3) << name;
    double lo = 0, hi = 0;
    cv::minMaxLoc(exr.reshape(1), &lo, &hi);
    EXPECT_TRUE(std::isfinite(lo) && std::isfinite(hi)) << name;
    EXPECT_GE(lo, 0.0) << name;
    EXPECT_GT(hi, 0.0) << name;
    frames.push_back(png);
  }
  // Frames 0 and 1 are different viewpoints of the orbit (a swing of +-30 degrees).
  cv::Mat diff;
  cv::absdiff(frames[0], frames[1], diff);
  EXPECT_GT(cv::mean(diff)[0] + cv::mean(diff)[1] + cv::mean(diff)[2], 1.0);

  // Second run: capture and HDR set reused (not rebuilt), the same frames again.
  const auto capture_time = fs::last_write_time(capture / "workspace" / "series.json");
  const DemoRun second = RunDemo(out);
  ASSERT_EQ(second.result.exit_code, 0) << second.result.output;
  EXPECT_NE(second.result.output.find("[1/4] capture: reusing"), std::string::npos)
      << second.result.output;
  EXPECT_NE(second.result.output.find("[3/4] HDR photo set: reusing"), std::string::npos)
      << second.result.output;
  EXPECT_EQ(fs::last_write_time(capture / "workspace" / "series.json"), capture_time);
  const cv::Mat again = cv::imread((orbit / "frame_0000.png").string());
  ASSERT_EQ(again.size(), frames[0].size());
  cv::absdiff(again, frames[0], diff);
  double max_diff = 0;
  cv::minMaxLoc(diff.reshape(1), nullptr, &max_diff);
  EXPECT_LE(max_diff, 2.0);

  // A shorter orbit replaces the frames of the longer one.
  const auto shorter =
      test::RunCommand(std::string(HDRIBR_EXE) + " demo --headless --out " + out.string() +
                       " --size 96x72 --series 2 --views 3 --frames 1");
  ASSERT_EQ(shorter.exit_code, 0) << shorter.output;
  EXPECT_TRUE(fs::exists(orbit / "frame_0000.png"));
  EXPECT_FALSE(fs::exists(orbit / "frame_0001.png"));
  EXPECT_FALSE(fs::exists(orbit / "frame_0001.exr"));

  // Bad options, the capture's own included: one clear error, nothing written.
  for (const std::string opt : {"--size 96", "--size 8x8", "--threads -1"}) {
    const auto bad = test::RunCommand(std::string(HDRIBR_EXE) + " demo --headless --out " +
                                      (out.parent_path() / "bad").string() + " " + opt);
    EXPECT_NE(bad.exit_code, 0) << opt;
    EXPECT_NE(bad.output.find(opt.substr(0, opt.find(' '))), std::string::npos) << bad.output;
    EXPECT_FALSE(fs::exists(out.parent_path() / "bad")) << opt;
  }
}

}  // namespace
}  // namespace hdribr
