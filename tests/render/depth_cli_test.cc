// `hdribr depth`: outputs on a small synthetic capture, and clear errors on bad input.
#include <gtest/gtest.h>

#include <fstream>

#include "io/exr.h"
#include "io/image.h"
#include "support/exe.h"
#include "support/test_capture.h"
#include "test_util.h"

namespace hdribr {
namespace {
using test::Exe;

// The suite's capture, 1 series x 2 views, 160 x 120, in dir/capture.
void WriteSuiteCapture(const std::filesystem::path& dir) {
  test::WriteTestCapture(dir / "capture", {1, 2, 160, 120, 1});
}
constexpr char kCaptureFixture[] = "DepthCliCapture";

// The setup of the shared fixture (tests/render/CMakeLists.txt): the capture, once per CTest
// run, which every test of DepthCliTest reads.
TEST(Fixture, DepthCliCapture) { test::RemakeSharedFixture(kCaptureFixture, WriteSuiteCapture); }

class DepthCliTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(test::SharedFixture(kCaptureFixture, WriteSuiteCapture) /
                                     "capture");
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::filesystem::path* dir_;
};
std::filesystem::path* DepthCliTest::dir_ = nullptr;

TEST_F(DepthCliTest, WritesExrAndPng) {
  const auto out = test::TempDir("depth_cli_out") / "d.exr";
  const auto r = test::RunCommand(Exe() + " depth " + (*dir_ / "workspace").string() +
                                  " --photo s0_v00.jpg --size 80x60 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat depth = ReadExr(out);
  EXPECT_EQ(depth.type(), CV_32FC1);
  EXPECT_EQ(depth.cols, 80);
  EXPECT_EQ(depth.rows, 60);
  // Compare with the ground truth at full size, subsampled: median relative error small.
  const cv::Mat gt = ReadExr(*dir_ / "gt" / "depth" / "s0_v00.exr");
  int close = 0, both = 0;
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 80; ++x) {
      const float g = gt.at<float>(2 * y + 1, 2 * x + 1), d = depth.at<float>(y, x);
      if (g <= 0 || d <= 0) continue;
      ++both;
      if (std::abs(d - g) <= 0.03f * g) ++close;
    }
  }
  EXPECT_GT(both, 80 * 60 / 2);
  EXPECT_GE(close, 0.9 * both);
  auto png = out;
  png.replace_extension(".png");
  EXPECT_EQ(ReadImage(png).cols, 80);
}

TEST_F(DepthCliTest, CameraFile) {
  const auto tmp = test::TempDir("depth_cli_cam");
  std::ofstream(tmp / "cam.json")
      << R"({"width": 64, "height": 48, "fx": 60, "fy": 60, "cx": 32, "cy": 24,
             "cam_from_world": {"qvec": [1, 0, 0, 0], "tvec": [0, 0, 3]}})";
  const auto r = test::RunCommand(Exe() + " depth " + (*dir_ / "workspace").string() +
                                  " --camera " + (tmp / "cam.json").string() +
                                  " --mode marroquim --out " + (tmp / "c.exr").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat compute = ReadExr(tmp / "c.exr");
  EXPECT_EQ(compute.cols, 64);
  // The graphics-pipeline raster gives the same depth map up to a few pixels.
  const auto p =
      test::RunCommand(Exe() + " depth " + (*dir_ / "workspace").string() + " --camera " +
                       (tmp / "cam.json").string() + " --mode marroquim --raster pipeline --out " +
                       (tmp / "p.exr").string());
  ASSERT_EQ(p.exit_code, 0) << p.output;
  const cv::Mat pipeline = ReadExr(tmp / "p.exr");
  cv::Mat differ = cv::abs(compute - pipeline) > 0.01 * pipeline;
  EXPECT_GT(cv::countNonZero(compute), 64 * 48 / 4);
  EXPECT_LE(cv::countNonZero(differ), 64 * 48 / 100);
}

TEST_F(DepthCliTest, BadInputIsOneClearErrorAndNoOutput) {
  const auto tmp = test::TempDir("depth_cli_bad");
  const std::string ws = (*dir_ / "workspace").string();
  const std::string out = (tmp / "x.exr").string();
  auto r = test::RunCommand(Exe() + " depth " + ws + " --photo nope.jpg --out " + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nope.jpg"), std::string::npos) << r.output;
  r = test::RunCommand(Exe() + " depth " + ws + " --out " + out);
  EXPECT_EQ(r.exit_code, 64) << r.output;
  r = test::RunCommand(Exe() + " depth " + ws + " --photo s0_v00.jpg --size 0x5 --out " + out);
  EXPECT_EQ(r.exit_code, 64) << r.output;
  r = test::RunCommand(Exe() + " depth " + ws + " --photo s0_v00.jpg --raster gpu --out " + out);
  EXPECT_EQ(r.exit_code, 64) << r.output;
  EXPECT_NE(r.output.find("--raster: must be one of compute, pipeline, got 'gpu'"),
            std::string::npos)
      << r.output;
  std::ofstream(tmp / "bad.json") << "{\"width\": 3}";
  r = test::RunCommand(Exe() + " depth " + ws + " --camera " + (tmp / "bad.json").string() +
                       " --out " + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.json"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(tmp / "x.png"));
}

}  // namespace
}  // namespace hdribr
