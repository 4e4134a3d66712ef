// `hdribr render`: outputs on a small synthetic capture (PNG, EXR, debug maps, camera path,
// nearest mode), and clear errors on bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "io/camera_spec.h"
#include "io/exr.h"
#include "io/image.h"
#include "io/workspace.h"
#include "support/cli_capture.h"

namespace hdribr {
namespace {
using test::Exe;

// The setup of the shared fixture SmallCapture1 (tests/render/CMakeLists.txt), read by every
// test of RenderCliTest and by the viewer's soak test.
TEST(Fixture, SmallCapture1) { test::RemakeSmallCaptureFixture(1); }

class RenderCliTest : public test::SmallCaptureTest<1> {};

TEST_F(RenderCliTest, PngAndExrOfAPhotoView) {
  const auto out = test::TempDir("render_cli_png");
  auto r = test::RunCommand(Exe() + " render " + Ws() +
                            " --camera s0_v01.jpg --exclude s0_v01.jpg --out " +
                            (out / "a.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("valid"), std::string::npos) << r.output;
  const cv::Mat png = ReadImage(out / "a.png");
  ASSERT_EQ(png.size(), cv::Size(test::kSmallCaptureWidth, test::kSmallCaptureHeight));
  const cv::Mat photo = ReadImage(Dir() / "workspace" / "images" / "s0_v01.jpg");
  // Left out of its own view, the photo is still reproduced: mean absolute error over the
  // non-black pixels (invalid pixels are written as 0).
  cv::Mat gray;
  cv::cvtColor(png, gray, cv::COLOR_BGR2GRAY);
  const cv::Mat mask = gray > 0;
  ASSERT_GT(cv::countNonZero(mask), test::kSmallCaptureWidth * test::kSmallCaptureHeight / 2);
  cv::Mat diff;
  cv::absdiff(png, photo, diff);
  const cv::Scalar mad = cv::mean(diff, mask);
  EXPECT_LT((mad[0] + mad[1] + mad[2]) / 3, 12.0);

  r = test::RunCommand(Exe() + " render " + Ws() + " --camera s0_v01.jpg --size 64x48 --out " +
                       (out / "a.exr").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat exr = ReadExr(out / "a.exr");
  ASSERT_EQ(exr.size(), cv::Size(64, 48));
  double lo = 0, hi = 0;
  cv::minMaxLoc(exr.reshape(1), &lo, &hi);
  EXPECT_GE(lo, 0.0);
  EXPECT_LE(hi, 1.0 + 1e-6);
  EXPECT_GT(hi, 0.2);
}

TEST_F(RenderCliTest, DebugMapsPathAndNearest) {
  const auto out = test::TempDir("render_cli_debug");
  for (const std::string d : {"count", "weight:s0_v02.jpg", "depth", "normal"}) {
    const auto r = test::RunCommand(Exe() + " render " + Ws() + " --camera s0_v00.jpg --debug " +
                                    d + " --k-best 2 --out " + (out / "d.png").string());
    ASSERT_EQ(r.exit_code, 0) << d << ": " << r.output;
    EXPECT_EQ(ReadImage(out / "d.png").cols, 128) << d;
    // --debug lists the frame's candidate photos, the view itself among them.
    const size_t line = r.output.find("candidates (");
    ASSERT_NE(line, std::string::npos) << r.output;
    const std::string listed = r.output.substr(line, r.output.find('\n', line) - line);
    EXPECT_NE(listed.find(" s0_v00.jpg"), std::string::npos) << listed;
  }
  // A cap of 2: two candidates of the active photos, named in the view's line.
  const auto rc = test::RunCommand(Exe() + " render " + Ws() +
                                   " --camera s0_v00.jpg --candidates 2 --debug count --out " +
                                   (out / "c.png").string());
  ASSERT_EQ(rc.exit_code, 0) << rc.output;
  EXPECT_NE(rc.output.find("candidates 2 of "), std::string::npos) << rc.output;
  EXPECT_NE(rc.output.find("candidates (2, chosen in"), std::string::npos) << rc.output;
  const auto r = test::RunCommand(Exe() + " render " + Ws() +
                                  " --camera s0_v00.jpg --mode nearest --exclude s0_v00.jpg "
                                  "--max-photo-size 64 --out " +
                                  (out / "n.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("mean photos/pixel 1.00"), std::string::npos) << r.output;

  // A camera path between two photo views: 0.5 s at 4 fps = 3 frames.
  const Scene scene = LoadWorkspace(Dir() / "workspace");
  CameraPath path;
  path.fps = 4;
  path.times_s = {0.0, 0.5};
  for (int i : {0, 1}) {
    const Photo& p = scene.photos[static_cast<size_t>(i)];
    path.keyframes.push_back(View{p.name, scene.CameraOf(p), p.cam_from_world});
  }
  WriteCameraPath(out / "path.json", path);
  const auto rp =
      test::RunCommand(Exe() + " render " + Ws() + " --path " + (out / "path.json").string() +
                       " --size 64x48 --out-dir " + (out / "frames").string());
  ASSERT_EQ(rp.exit_code, 0) << rp.output;
  for (const char* f : {"frame_0000.png", "frame_0001.png", "frame_0002.png"}) {
    EXPECT_TRUE(std::filesystem::exists(out / "frames" / f)) << f;
  }
  EXPECT_FALSE(std::filesystem::exists(out / "frames" / "frame_0003.png"));
}

// A GPU memory budget of the depth maps and three quarters of the photos (two full-size slots
// for two candidates): `inspect --gpu` reports the cache, and `render` waits for its photos, so
// its PNG is the all-resident one.
TEST_F(RenderCliTest, GpuMemoryBelowThePhotosRendersTheSamePng) {
  const auto out = test::TempDir("render_cli_gpu_memory");
  // The JSON on stdout, the log lines on stderr.
  auto inspect = [&](const std::string& flags) {
    const auto json = out / "inspect.json";
    const auto r = test::RunCommand("(" + Exe() + " inspect " + Ws() + " --gpu --json" + flags +
                                    " > " + json.string() + ")");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::ifstream in(json);
    return nlohmann::json::parse(in)["gpu"];
  };
  const nlohmann::json all = inspect("");
  EXPECT_FALSE(all["cached"].get<bool>());
  const double depth = all["depth_bytes"].get<double>();
  const double photos = all["total_bytes"].get<double>() - depth;
  const std::string budget = std::to_string((depth + photos * 0.75) / 1048576.0);
  const nlohmann::json cached = inspect(" --gpu-memory " + budget);
  EXPECT_TRUE(cached["cached"].get<bool>());
  EXPECT_LE(cached["resident_bytes"].get<double>(), cached["budget_bytes"].get<double>());
  EXPECT_EQ(cached["total_bytes"], all["total_bytes"]);
  EXPECT_EQ(cached["full_size_slots"].get<int>(), 2);

  const std::string base =
      Exe() + " render " + Ws() + " --camera s0_v01.jpg --exclude s0_v01.jpg --candidates 2 --out ";
  auto r = test::RunCommand(base + (out / "all.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::RunCommand(base + (out / "cached.png").string() + " --gpu-memory " + budget);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("photo cache of"), std::string::npos) << r.output;
  const cv::Mat a = ReadImage(out / "all.png"), b = ReadImage(out / "cached.png");
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
}

TEST_F(RenderCliTest, BadInputAndLookingAway) {
  const auto out = test::TempDir("render_cli_bad");
  const std::string base = Exe() + " render " + Ws();
  auto r = test::RunCommand(base + " --camera nope.jpg --out " + (out / "x.png").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("nope.jpg"), std::string::npos) << r.output;
  r = test::RunCommand(base + " --camera '1 2 0 0 0 0 0' --out " + (out / "x.png").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("unit quaternion"), std::string::npos) << r.output;
  r = test::RunCommand(base + " --camera s0_v00.jpg --out " + (out / "x.jpg").string());
  EXPECT_EQ(r.exit_code, 64) << r.output;
  EXPECT_NE(r.output.find("--out: must end in .png or .exr, got '" + (out / "x.jpg").string()),
            std::string::npos)
      << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  r = test::RunCommand(base + " --camera s0_v00.jpg --exclude zz --out " +
                       (out / "x.png").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("zz"), std::string::npos) << r.output;
  // Tone mapping of an LDR render: refused, not ignored; non-finite values refused too.
  r = test::RunCommand(base + " --camera s0_v00.jpg --exposure 1 --out " +
                       (out / "x.png").string());
  EXPECT_EQ(r.exit_code, 64) << r.output;
  EXPECT_NE(r.output.find("--exposure applies to HDR renders"), std::string::npos) << r.output;
  r = test::RunCommand(base + " --camera s0_v00.jpg --hdr-mode direct --gamma nan --out " +
                       (out / "x.png").string());
  EXPECT_EQ(r.exit_code, 64) << r.output;
  for (const std::string bad : {"--lambda nan", "--lambda -1", "--tolerance 0", "--k-best -2",
                                "--k-best 40 --weights paper", "--k-best 33", "--candidates -1",
                                "--gpu-memory -1", "--gpu-memory 0.001", "--filter 0.7",
                                "--filter -1", "--refine-depth 0.1", "--refine-depth -0.01"}) {
    r = test::RunCommand(base + " --camera s0_v00.jpg " + bad + " --out " +
                         (out / "x.png").string());
    EXPECT_EQ(r.exit_code, 64) << bad << ": " << r.output;
    EXPECT_NE(r.output.find(bad.substr(0, bad.find(' '))), std::string::npos) << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(out / "x.png"));
  // A bad size or an output folder that does not exist: one line as the options are parsed,
  // before the renderer loads anything.
  r = test::RunCommand(base + " --camera s0_v00.jpg --size 64x0 --out " + (out / "x.png").string());
  EXPECT_EQ(r.exit_code, 64) << r.output;
  EXPECT_NE(r.output.find("--size: must be WxH"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  r = test::RunCommand(base + " --camera s0_v00.jpg --out " + (out / "none" / "x.png").string());
  EXPECT_EQ(r.exit_code, 64) << r.output;
  EXPECT_NE(r.output.find("--out: folder " + (out / "none").string() + " does not exist"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out / "none"));
  // An output among the workspace's photos (the next load would take it for one) is refused,
  // with one line naming it; so is an output folder there.
  const auto images = Dir() / "workspace" / "images";
  const size_t photos_before = std::distance(std::filesystem::directory_iterator(images), {});
  r = test::RunCommand(base + " --camera s0_v00.jpg --out " + (images / "new.png").string());
  EXPECT_EQ(r.exit_code, 64) << r.output;
  EXPECT_NE(r.output.find("new.png: inside the workspace's input folder"), std::string::npos)
      << r.output;
  r = test::RunCommand(base + " --path " + (out / "none.json").string() + " --out-dir " +
                       (images / "frames").string());
  EXPECT_EQ(r.exit_code, 64) << r.output;
  r = test::RunCommand(Exe() + " eval " + Ws() + " --leave-one-out --out " +
                       (images / "eval").string());
  EXPECT_EQ(r.exit_code, 64) << r.output;
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(images), {}), photos_before);

  // A photo missing on disk: an error naming the file, no output.
  const auto ws = out / "ws";
  std::filesystem::copy(Dir() / "workspace", ws, std::filesystem::copy_options::recursive);
  std::filesystem::remove(ws / "images" / "s0_v03.jpg");
  r = test::RunCommand(Exe() + " render " + ws.string() + " --camera s0_v00.jpg --out " +
                       (out / "m.png").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("s0_v03.jpg"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out / "m.png"));

  // A photo of another shape than its camera (it would be sampled stretched); another scale
  // is fine (BlendPassTest.PhotoSizesFloatPhotosAndMaxPhotoSize).
  const cv::Mat photo = ReadImage(ws / "images" / "s0_v01.jpg");
  WriteImage(ws / "images" / "s0_v03.jpg", photo.colRange(0, photo.rows).clone());
  r = test::RunCommand(Exe() + " -q render " + ws.string() + " --camera s0_v00.jpg --out " +
                       (out / "m.png").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("s0_v03.jpg: image is"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out / "m.png"));

  // Every point behind the camera: all invalid, a warning, exit 0.
  r = test::RunCommand(base + " --camera '1 0 0 0 0 0 -1000' --out " + (out / "away.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("all invalid"), std::string::npos) << r.output;
  cv::Mat away = ReadImage(out / "away.png");
  EXPECT_EQ(cv::countNonZero(away.reshape(1)), 0);
}

}  // namespace
}  // namespace hdribr
