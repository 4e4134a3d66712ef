// `hdribr hdr` and `hdribr render --hdr-mode` end to end on a tiny synthetic capture: outputs
// exist and are sane, one-series workspaces give one clear error line and write nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "io/exr.h"
#include "io/image.h"
#include "render/hdr_photo_set.h"
#include "support/cli_capture.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;

TEST(HdrCli, BuildsTheSetAndRendersTheThreeModes) {
  const fs::path cap = test::WriteSmallCapture("hdr_cli", 2);
  const fs::path ws = cap / "workspace";
  const std::string exe = HDRIBR_EXE;
  auto r = test::RunCommand(exe + " hdr " + ws.string() + " --truth " + cap.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("HDR photo set: 4 views x 2 series"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("merged HDR vs GT radiance"), std::string::npos) << r.output;
  const render::HdrPhotoSet set = render::ReadHdrPhotoSet(ws);
  ASSERT_EQ(set.views.size(), 4u);
  const cv::Mat radiance = ReadExr(set.folder / set.views[0].radiance_file);
  EXPECT_EQ(radiance.size(), cv::Size(test::kSmallCaptureWidth, test::kSmallCaptureHeight));
  EXPECT_TRUE(cv::checkRange(radiance));
  EXPECT_TRUE(fs::exists(set.folder / set.views[0].mask_files[1]));

  const fs::path out = test::TempDir("hdr_cli_out");
  for (const std::string mode : {"precomputed", "onthefly", "direct"}) {
    const fs::path png = out / (mode + ".png");
    r = test::RunCommand(exe + " render " + ws.string() + " --camera " + set.views[1].view.name +
                         " --hdr-mode " + mode + " --exposure 0.5 --out " + png.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const cv::Mat img = ReadImage(png);
    EXPECT_EQ(img.size(), cv::Size(test::kSmallCaptureWidth, test::kSmallCaptureHeight));
    EXPECT_GT(cv::mean(img)[1], 20) << mode;  // tone-mapped, not black
  }
  const fs::path exr = out / "direct.exr";
  r = test::RunCommand(exe + " render " + ws.string() + " --camera " + set.views[1].view.name +
                       " --hdr-mode direct --out " + exr.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(cv::checkRange(ReadExr(exr)));
  r = test::RunCommand(exe + " render " + ws.string() + " --camera " + set.views[1].view.name +
                       " --hdr-mode precomputed --hdr-set " + (out / "none").string() + " --out " +
                       (out / "x.png").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("hdr_set.json"), std::string::npos) << r.output;
}

TEST(HdrCli, OneSeriesIsAClearError) {
  const fs::path ws = test::WriteSmallCapture("hdr_cli_one", 1) / "workspace";
  const auto r = test::RunCommand(std::string(HDRIBR_EXE) + " hdr " + ws.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("at least two"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(ws / "hdr"));
}

}  // namespace
}  // namespace hdribr
