// `hdribr calibrate` end to end: an auto-exposure synthetic capture with EXIF 5 % off is
// calibrated within the targets, the result is written to calib/ and loaded with the
// workspace; a workspace that cannot be calibrated gives one clear error and writes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "eval/metrics.h"
#include "hdr/re_expose.h"
#include "hdr/response_curve.h"
#include "io/exr.h"
#include "io/image.h"
#include "io/radiometric_calibration.h"
#include "io/workspace.h"
#include "support/cli_capture.h"
#include "synth/capture.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;

// The numbers after `prefix` in `text` (as many as `count`), or an empty vector.
std::vector<double> NumbersAfter(const std::string& text, const std::string& prefix, int count) {
  const size_t at = text.find(prefix);
  if (at == std::string::npos) return {};
  std::vector<double> out;
  const std::regex number(R"([0-9]+\.[0-9]+)");
  std::string rest = text.substr(at + prefix.size());
  for (std::sregex_iterator it(rest.begin(), rest.end(), number), end;
       it != end && static_cast<int>(out.size()) < count; ++it) {
    out.push_back(std::stod(it->str()));
  }
  return out;
}

// Options of a capture of `series` x `views` photos of w x h, without novel views.
synth::CaptureOptions Photos(int series, int views, int w, int h) {
  synth::CaptureOptions o;
  o.series = series;
  o.views = views;
  o.width = w;
  o.height = h;
  o.novel_views = 0;
  return o;
}

TEST(CalibrateCli, AutoExposureCaptureMeetsTheTargets) {
  const fs::path cap = test::TempDir("calibrate_cli") / "capture";
  synth::CaptureOptions o = Photos(3, 12, 256, 192);  // 36 photos over 4 stops
  o.exposure = "auto";
  o.exif_error = 0.05;
  o.seed = 4;
  synth::WriteCapture(o, cap);
  const fs::path ws = cap / "workspace";
  const auto r = test::RunCommand(std::string(HDRIBR_EXE) + " calibrate " + ws.string() +
                                  " --truth " + cap.string() + " 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::cout << r.output;
  EXPECT_NE(r.output.find("calibrated 36 of 36 photos"), std::string::npos) << r.output;
  const std::vector<double> rms = NumbersAfter(r.output, "over 10-245 DN:", 3);
  ASSERT_EQ(rms.size(), 3u) << r.output;
  for (double e : rms) EXPECT_LE(e, 0.03);
  const std::vector<double> exposure = NumbersAfter(r.output, "calibrated median", 2);
  const std::vector<double> exif = NumbersAfter(r.output, "EXIF median", 2);
  ASSERT_EQ(exposure.size(), 2u) << r.output;
  ASSERT_EQ(exif.size(), 2u) << r.output;
  EXPECT_LE(exposure[1], 2.0);  // percent, largest
  EXPECT_GT(exif[1], 5.0);      // EXIF alone is off by more
  // Exposures over 4 stops fix the response: the cross-validation picks no prior or a weak one
  // (measured: 1e2, which takes the response error from 0.0105 / 0.0133 / 0.0183 to 0.0102 /
  // 0.0080 / 0.0096).
  const size_t prior_at = r.output.find("response prior ");
  ASSERT_NE(prior_at, std::string::npos) << r.output;
  EXPECT_LE(std::stod(r.output.substr(prior_at + 15)), 100.0) << r.output;

  // The workspace carries the calibration: every photo's refined exposure.
  const RadiometricCalibration c = ReadRadiometricCalibration(ws / kCalibFolder / kCalibExposures);
  EXPECT_EQ(c.photos.size(), 36u);
  EXPECT_TRUE(c.exponent_from_exif);
  const Scene scene = LoadWorkspace(ws);
  for (const Photo& p : scene.photos) {
    ASSERT_TRUE(p.calibrated_exposure.has_value()) << p.name;
    EXPECT_DOUBLE_EQ(scene.RelativeExposureOf(p), c.photos.at(p.name).relative);
  }

  // `render --as-photo`: radiance from every photo through the calibrated response at that
  // photo's exposure looks like the photo; at another exposure time it is brighter or darker.
  const fs::path out = test::TempDir("calibrate_cli_render");
  const std::string photo = scene.photos[13].name;
  const std::string render = std::string(HDRIBR_EXE) + " -q render " + ws.string() + " --camera " +
                             photo + " --hdr-mode direct --no-fill ";
  auto rr = test::RunCommand(render + "--as-photo " + photo + " --out " +
                             (out / "as.png").string() + " 2>&1");
  ASSERT_EQ(rr.exit_code, 0) << rr.output;
  const cv::Mat as_photo = ReadImage(out / "as.png");
  const cv::Mat original = ReadImage(ws / "images" / photo);
  const double psnr = cv::PSNR(as_photo, original);
  std::cout << "render --as-photo " << photo << ": " << psnr << " dB against the photo\n";
  EXPECT_GT(psnr, 28.0);
  // Left out of its own view (`--exclude`: the radiance of the other photos, as `eval
  // --leave-one-out` renders it), the photo is still reproduced, less closely than with itself.
  rr = test::RunCommand(render + "--exclude " + photo + " --as-photo " + photo + " --out " +
                        (out / "loo.png").string() + " 2>&1");
  ASSERT_EQ(rr.exit_code, 0) << rr.output;
  const cv::Mat loo = cv::imread((out / "loo.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(loo.channels(), 4);
  cv::Mat loo_alpha, loo_bgr;
  cv::extractChannel(loo, loo_alpha, 3);
  cv::cvtColor(loo, loo_bgr, cv::COLOR_BGRA2BGR);
  ASSERT_GT(cv::countNonZero(loo_alpha), loo.total() * 9 / 10);
  const double loo_psnr = CompareImages(original, loo_bgr, loo_alpha).psnr_db;
  std::cout << "render --exclude " << photo << " --as-photo: " << loo_psnr
            << " dB against the photo\n";
  EXPECT_GT(loo_psnr, 28.0);
  EXPECT_LT(loo_psnr, psnr);
  rr = test::RunCommand(std::string(HDRIBR_EXE) + " render " + ws.string() + " --camera " + photo +
                        " --exclude " + photo + " --hdr-mode onthefly --out " +
                        (out / "x.png").string() + " 2>&1");
  EXPECT_EQ(rr.exit_code, 64) << rr.output;
  EXPECT_NE(rr.output.find("--exclude needs --hdr-mode direct"), std::string::npos) << rr.output;
  const double time = *scene.photos[13].exposure.time_s;
  rr = test::RunCommand(render + "--exposure-time " + std::to_string(4 * time) + " --out " +
                        (out / "bright.png").string() + " 2>&1");
  ASSERT_EQ(rr.exit_code, 0) << rr.output;
  EXPECT_GT(cv::mean(ReadImage(out / "bright.png"))[1], cv::mean(as_photo)[1] + 20);
  // Without --hdr-mode, a calibrated workspace with several exposures renders its radiance
  // through the response (auto); --hdr-mode ldr blends display values.
  const std::string plain = std::string(HDRIBR_EXE) + " render " + ws.string() + " --camera " +
                            photo + " --out " + (out / "plain.png").string();
  rr = test::RunCommand(plain + " 2>&1");
  ASSERT_EQ(rr.exit_code, 0) << rr.output;
  EXPECT_NE(rr.output.find("HDR mode direct"), std::string::npos) << rr.output;
  EXPECT_GT(cv::PSNR(ReadImage(out / "plain.png"), original), 20.0);
  rr = test::RunCommand(plain + " --hdr-mode ldr 2>&1");
  ASSERT_EQ(rr.exit_code, 0) << rr.output;
  EXPECT_EQ(rr.output.find("HDR mode"), std::string::npos) << rr.output;
  rr = test::RunCommand(render + "--as-photo nope.jpg --out " + (out / "x.png").string() + " 2>&1");
  EXPECT_NE(rr.exit_code, 0);
  EXPECT_NE(rr.output.find("no photo named 'nope.jpg'"), std::string::npos) << rr.output;
  EXPECT_FALSE(fs::exists(out / "x.png"));

  // The viewer opens the calibrated workspace on its radiance (direct) and, with --tonemap
  // camera, shows it through the response at the photos' median exposure: its screenshot is the
  // CPU re-exposure of its own linear EXR.
  if (!test::HaveXvfb()) GTEST_SKIP() << "xvfb-run missing: viewer part skipped";
  const auto v =
      test::RunUnderXvfb(std::string(HDRIBR_EXE) + " view " + ws.string() + " --camera " + photo +
                         " --tonemap camera --screenshot " + (out / "view.png").string() + " 2>&1");
  ASSERT_EQ(v.exit_code, 0) << v.output;
  EXPECT_NE(v.output.find("(direct)"), std::string::npos) << v.output;
  std::vector<double> exposures;
  for (const Photo& p : scene.photos) exposures.push_back(scene.RelativeExposureOf(p));
  std::nth_element(exposures.begin(), exposures.begin() + exposures.size() / 2, exposures.end());
  const cv::Mat radiance = ReadExr(out / "view.exr");
  const cv::Mat want =
      ExposeThroughResponse(radiance, ReadResponseCurve(ws / kCalibFolder / kCalibResponse),
                            exposures[exposures.size() / 2]);
  const cv::Mat got = ReadImage(out / "view.png");
  ASSERT_EQ(got.size(), want.size());
  cv::Mat diff;
  cv::absdiff(got, want, diff);
  double worst = 0;
  cv::minMaxLoc(diff.reshape(1), nullptr, &worst);
  EXPECT_LE(worst, 1.0);
  EXPECT_GT(cv::mean(got)[1], 20.0);
}

TEST(CalibrateCli, OnePhotoIsOneClearErrorAndWritesNothing) {
  const fs::path cap = test::TempDir("calibrate_cli_one") / "capture";
  synth::WriteCapture(Photos(1, 1, 64, 48), cap);
  const fs::path ws = cap / "workspace";
  const std::string exe = HDRIBR_EXE;
  auto r = test::RunCommand(exe + " calibrate " + ws.string() + " 2>&1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("at least two photos"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(ws / kCalibFolder));
  // `hdr --calibration cloud` without a calibration names the missing file.
  r = test::RunCommand(exe + " hdr " + ws.string() + " --calibration cloud 2>&1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("hdribr calibrate"), std::string::npos) << r.output;
}

// `hdribr hdr PHOTOS/`: a folder of photos becomes a workspace beside it (reconstructed and
// calibrated from its cloud), reused by the next command.
TEST(CalibrateCli, PhotoFolderToHdrInOneCommand) {
  const fs::path cap = test::TempDir("calibrate_cli_photos") / "capture";
  synth::WriteCapture(Photos(2, 6, 320, 240), cap);
  const fs::path photos = cap / "photos";
  const std::string exe = HDRIBR_EXE;
  auto r = test::RunCommand(exe + " hdr " + photos.string() + " --no-aligned 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path ws = cap / "photos-hdribr";
  EXPECT_NE(r.output.find("is a folder of photos: its workspace is " + ws.string()),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(ws / kCalibFolder / kCalibExposures));
  EXPECT_NE(r.output.find("response from the point cloud"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(ws / "hdr" / "hdr_set.json"));
  // The photo folder holds only its photos still.
  for (const auto& e : fs::directory_iterator(photos)) {
    EXPECT_EQ(e.path().extension(), ".jpg") << e.path();
  }
  // Second time: the workspace is reused, nothing is reconstructed again.
  r = test::RunCommand(exe + " hdr " + photos.string() + " --no-aligned 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("dense: done before, skipped"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace hdribr
