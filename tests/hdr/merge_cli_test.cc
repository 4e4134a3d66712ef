// `hdribr merge` end to end: memorial, response files, tone mapping, edge stacks and errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "hdr/debevec.h"
#include "hdr/response_curve.h"
#include "io/exr.h"
#include "io/image.h"
#include "support/exe.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;

// hdribr, quiet.
std::string QuietExe() { return test::Exe() + " -q"; }
std::string Q(const fs::path& p) { return "'" + p.string() + "'"; }

std::string MemorialImages(const fs::path& dir) {
  std::string s;
  for (int i = 61; i <= 76; ++i) s += " " + Q(dir / ("memorial00" + std::to_string(i) + ".png"));
  return s;
}

// A small stack of flat images with the given pixel values.
std::vector<fs::path> FlatImages(const fs::path& dir, const std::vector<int>& values,
                                 cv::Size size = {16, 12}) {
  std::vector<fs::path> paths;
  for (size_t i = 0; i < values.size(); ++i) {
    paths.push_back(dir / ("flat" + std::to_string(i) + ".png"));
    cv::imwrite(paths.back().string(), cv::Mat(size, CV_8UC3, cv::Scalar::all(values[i])));
  }
  return paths;
}

// A 3-image stack with a horizontal ramp, so that calibration is possible.
std::vector<fs::path> RampImages(const fs::path& dir) {
  std::vector<fs::path> paths;
  const double times[3] = {0.25, 1, 4};
  for (int i = 0; i < 3; ++i) {
    cv::Mat im(24, 256, CV_8UC3);
    for (int x = 0; x < 256; ++x) {
      const double e = std::exp(-6.0 + 7.0 * x / 255.0);
      im.col(x).setTo(cv::Scalar::all(
          cv::saturate_cast<uint8_t>(255.0 * std::pow(std::min(1.0, e * times[i]), 1 / 2.2))));
    }
    paths.push_back(dir / ("ramp" + std::to_string(i) + ".png"));
    cv::imwrite(paths.back().string(), im);
  }
  return paths;
}

std::string Join(const std::vector<fs::path>& paths) {
  std::string s;
  for (const auto& p : paths) s += " " + Q(p);
  return s;
}

bool FiniteNonNegative(const cv::Mat& m) { return cv::checkRange(m, true, nullptr, 0.0, 1e38); }

size_t CountFiles(const fs::path& dir, const std::string& ext) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.path().extension() == ext;
  return n;
}

TEST(MergeCli, MemorialWithResponseRoundTripAndToneMap) {
  HDRIBR_REQUIRE_DATASET(data, "memorial");
  const fs::path dir = test::TempDir();
  const auto r = test::RunCommand(QuietExe() + " merge" + MemorialImages(data) + " --times-file " +
                                  Q(data / "shutter_times.txt") + " --out " + Q(dir / "m.exr") +
                                  " --save-response " + Q(dir / "r.json") + " --tonemap " +
                                  Q(dir / "m.png") + " --key 0.18 --gamma 2.2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat e = ReadExr(dir / "m.exr");
  ASSERT_EQ(e.size(), cv::Size(512, 768));
  EXPECT_TRUE(FiniteNonNegative(e));
  const ResponseCurve curve = ReadResponseCurve(dir / "r.json");
  EXPECT_TRUE(curve.IsValid());
  EXPECT_EQ(curve.source, "debevec");
  const cv::Mat png = ReadImage(dir / "m.png");
  EXPECT_EQ(png.size(), e.size());
  const cv::Scalar mean = cv::mean(png);
  EXPECT_GT(mean[1], 30);  // tone-mapped, neither black nor white
  EXPECT_LT(mean[1], 220);

  // Reusing the saved response gives the same radiance (no calibration).
  const auto again =
      test::RunCommand(QuietExe() + " merge" + MemorialImages(data) + " --times-file " +
                       Q(data / "shutter_times.txt") + " --response " + Q(dir / "r.json") +
                       " --out " + Q(dir / "again.exr"));
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const cv::Mat e2 = ReadExr(dir / "again.exr");
  EXPECT_LE(cv::norm(e, e2, cv::NORM_INF), 0.0);

  // --response and --lambda exclude each other.
  const auto both =
      test::RunCommand(QuietExe() + " merge" + MemorialImages(data) + " --times-file " +
                       Q(data / "shutter_times.txt") + " --response " + Q(dir / "r.json") +
                       " --lambda 3 --out " + Q(dir / "x.exr"));
  EXPECT_NE(both.exit_code, 0);
  EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

TEST(MergeCli, NamedTimesFileAndInlineTimes) {
  const fs::path dir = test::TempDir();
  const auto images = RampImages(dir);
  std::ofstream(dir / "times.txt") << "ramp2.png 4\nramp0.png 1/4\nramp1.png 1\n";
  const auto named = test::RunCommand(QuietExe() + " merge" + Join(images) + " --times-file " +
                                      Q(dir / "times.txt") + " --out " + Q(dir / "a.exr"));
  ASSERT_EQ(named.exit_code, 0) << named.output;
  // The extension's case does not matter.
  const auto inline_times = test::RunCommand(QuietExe() + " merge" + Join(images) +
                                             " --times 0.25 1/1 4 --out " + Q(dir / "b.EXR"));
  ASSERT_EQ(inline_times.exit_code, 0) << inline_times.output;
  const cv::Mat a = ReadExr(dir / "a.exr"), b = ReadExr(dir / "b.EXR");
  EXPECT_TRUE(FiniteNonNegative(a));
  EXPECT_LE(cv::norm(a, b, cv::NORM_INF), 0.0);
  // Brighter columns have more radiance.
  EXPECT_GT(a.at<cv::Vec3f>(5, 200)[1], a.at<cv::Vec3f>(5, 100)[1]);
  EXPECT_GT(a.at<cv::Vec3f>(5, 100)[1], a.at<cv::Vec3f>(5, 20)[1]);

  std::ofstream(dir / "missing.txt") << "ramp2.png 4\nramp0.png 1/4\n";
  const auto missing = test::RunCommand(QuietExe() + " merge" + Join(images) + " --times-file " +
                                        Q(dir / "missing.txt") + " --out " + Q(dir / "c.exr"));
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("missing.txt"), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("ramp1.png"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(dir / "c.exr"));

  // Formats the outputs cannot take: one line each, before any work.
  for (const std::string& bad : {" --out " + Q(dir / "d.png"),
                                 " --out " + Q(dir / "d.exr") + " --tonemap " + Q(dir / "d.tif")}) {
    const auto r =
        test::RunCommand(QuietExe() + " merge" + Join(images) + " --times 0.25 1 4" + bad);
    EXPECT_EQ(r.exit_code, 64) << r.output;
    EXPECT_NE(r.output.find("must end in ."), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(dir / "d.exr"));
  }
}

TEST(MergeCli, PlainDebevecFlagSelectsThePublishedCalibration) {
  const fs::path dir = test::TempDir();
  const auto images = RampImages(dir);
  ExposureStack stack;
  stack.times = {0.25, 1, 4};
  for (const auto& p : images) stack.images.push_back(ReadImage(p));
  auto run = [&](const std::string& extra, const std::string& name) {
    return test::RunCommand(QuietExe() + " merge" + Join(images) + " --times 1/4 1 4" + extra +
                            " --save-response " + Q(dir / name) + " --out " + Q(dir / "o.exr"));
  };
  auto max_diff = [](const ResponseCurve& a, const ResponseCurve& b) {
    double d = 0;
    for (int c = 0; c < 3; ++c) {
      for (int z = 0; z < 256; ++z) {
        d = std::max(d, std::abs(a.log_inverse[c][z] - b.log_inverse[c][z]));
      }
    }
    return d;
  };
  const auto robust = run("", "robust.json");
  ASSERT_EQ(robust.exit_code, 0) << robust.output;
  const auto plain = run(" --plain-debevec --lambda 30", "plain.json");
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  CalibrationOptions old_default;
  old_default.lambda = 30;
  const ResponseCurve robust_curve = ReadResponseCurve(dir / "robust.json");
  const ResponseCurve plain_curve = ReadResponseCurve(dir / "plain.json");
  EXPECT_LE(max_diff(robust_curve, CalibrateDebevec(stack)), 1e-9);
  EXPECT_LE(max_diff(plain_curve, CalibrateDebevec(stack, PlainDebevec(old_default))), 1e-9);
  EXPECT_GT(max_diff(plain_curve, robust_curve), 1e-3);  // the flag changes the curve
  // Like --lambda, it has no meaning with a given response.
  const auto both = run(" --plain-debevec --response " + Q(dir / "plain.json"), "x.json");
  EXPECT_NE(both.exit_code, 0) << both.output;
  EXPECT_FALSE(fs::exists(dir / "x.json"));
}

TEST(MergeCli, SaturatedAndBlackStacks) {
  const fs::path dir = test::TempDir();
  const fs::path example = fs::path(HDRIBR_SOURCE_DIR) / "calib/response.example.json";
  const ResponseCurve curve = ReadResponseCurve(example);
  for (int value : {255, 0}) {
    const auto images = FlatImages(dir, {value, value, value});
    // Calibration is impossible: a clear error, nothing written.
    const auto cal = test::RunCommand(QuietExe() + " merge" + Join(images) +
                                      " --times 1/8 1/2 2 --out " + Q(dir / "cal.exr"));
    EXPECT_EQ(cal.exit_code, 2) << cal.output;
    EXPECT_NE(cal.output.find("no pixel is well exposed"), std::string::npos) << cal.output;
    EXPECT_FALSE(fs::exists(dir / "cal.exr"));
    // With a response: the documented bound (shortest exposure when saturated, longest when
    // black), finite everywhere.
    const fs::path out = dir / ("v" + std::to_string(value) + ".exr");
    const auto r = test::RunCommand(QuietExe() + " merge" + Join(images) + " --times 1/8 1/2 2" +
                                    " --response " + Q(example) + " --float --out " + Q(out) +
                                    " --tonemap " + Q(dir / "t.png"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const cv::Mat e = ReadExr(out);
    EXPECT_TRUE(FiniteNonNegative(e));
    const double expected = value == 255 ? std::exp(curve.log_inverse[1][255]) * 8
                                         : std::exp(curve.log_inverse[1][0]) / 2;
    EXPECT_NEAR(e.at<cv::Vec3f>(3, 3)[1] / expected, 1.0, 1e-5) << value;
  }
}

TEST(MergeCli, OneImageStack) {
  const fs::path dir = test::TempDir();
  const auto images = FlatImages(dir, {128});
  const auto cal = test::RunCommand(QuietExe() + " merge" + Join(images) + " --times 0.5 --out " +
                                    Q(dir / "a.exr"));
  EXPECT_EQ(cal.exit_code, 64) << cal.output;
  EXPECT_NE(cal.output.find("--response"), std::string::npos) << cal.output;
  const fs::path example = fs::path(HDRIBR_SOURCE_DIR) / "calib/response.example.json";
  const auto r =
      test::RunCommand(QuietExe() + " merge" + Join(images) + " --times 0.5 --response " +
                       Q(example) + " --out " + Q(dir / "b.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // g(128) = 0 in the example, so E = 1 / 0.5.
  EXPECT_NEAR(ReadExr(dir / "b.exr").at<cv::Vec3f>(0, 0)[2], 2.0, 2e-3);

  // Radiance beyond the half-float range is clamped to 65504 (with a warning), never Inf.
  const auto bright = FlatImages(dir, {255});
  const auto h =
      test::RunCommand(std::string(HDRIBR_EXE) + " merge" + Join(bright) +
                       " --times 1e-6 --response " + Q(example) + " --out " + Q(dir / "h.exr"));
  ASSERT_EQ(h.exit_code, 0) << h.output;
  EXPECT_NE(h.output.find("clamped to 65504"), std::string::npos) << h.output;
  const cv::Mat he = ReadExr(dir / "h.exr");
  EXPECT_TRUE(FiniteNonNegative(he));
  EXPECT_FLOAT_EQ(he.at<cv::Vec3f>(0, 0)[1], 65504.0f);
}

TEST(MergeCli, BadInputGivesOneLineErrorsAndNoOutput) {
  const fs::path dir = test::TempDir();
  auto images = RampImages(dir);
  auto run = [&](const std::string& args) {
    return test::RunCommand(QuietExe() + " merge" + Join(images) + " " + args);
  };
  auto count = run("--times 1 2 --out " + Q(dir / "o.exr"));
  EXPECT_EQ(count.exit_code, 64) << count.output;
  EXPECT_NE(count.output.find("3 images but 2 --times"), std::string::npos) << count.output;

  auto bad_time = run("--times 1 0 4 --out " + Q(dir / "o.exr"));
  EXPECT_EQ(bad_time.exit_code, 64) << bad_time.output;

  auto no_times = run("--out " + Q(dir / "o.exr"));
  EXPECT_NE(no_times.exit_code, 0) << no_times.output;

  auto no_file = run("--times-file " + Q(dir / "nope.txt") + " --out " + Q(dir / "o.exr"));
  EXPECT_EQ(no_file.exit_code, 2) << no_file.output;
  EXPECT_NE(no_file.output.find("nope.txt"), std::string::npos) << no_file.output;

  std::ofstream(dir / "short.txt") << "1\n2\n";
  auto short_file = run("--times-file " + Q(dir / "short.txt") + " --out " + Q(dir / "o.exr"));
  EXPECT_EQ(short_file.exit_code, 2) << short_file.output;
  EXPECT_NE(short_file.output.find("2 exposure times for 3 images"), std::string::npos);

  auto bad_lambda = run("--times 1 2 4 --lambda -1 --out " + Q(dir / "o.exr"));
  EXPECT_EQ(bad_lambda.exit_code, 64) << bad_lambda.output;
  auto bad_gamma =
      run("--times 1 2 4 --gamma 0 --tonemap " + Q(dir / "t.png") + " --out " + Q(dir / "o.exr"));
  EXPECT_EQ(bad_gamma.exit_code, 64) << bad_gamma.output;
  EXPECT_FALSE(fs::exists(dir / "t.png"));

  auto png_out = run("--times 1 2 4 --out " + Q(dir / "o.png"));
  EXPECT_EQ(png_out.exit_code, 64) << png_out.output;

  std::ofstream(dir / "bad.json") << "{}";
  auto bad_response =
      run("--times 1 2 4 --response " + Q(dir / "bad.json") + " --out " + Q(dir / "o.exr"));
  EXPECT_EQ(bad_response.exit_code, 2) << bad_response.output;
  EXPECT_NE(bad_response.output.find("bad.json"), std::string::npos) << bad_response.output;

  cv::imwrite((dir / "small.png").string(), cv::Mat(10, 10, CV_8UC3, cv::Scalar::all(100)));
  images.push_back(dir / "small.png");
  auto size = run("--times 1 2 4 8 --out " + Q(dir / "o.exr"));
  EXPECT_EQ(size.exit_code, 2) << size.output;
  EXPECT_NE(size.output.find("small.png"), std::string::npos) << size.output;
  EXPECT_NE(size.output.find("aligned"), std::string::npos) << size.output;

  images.back() = dir / "absent.png";
  auto absent = run("--times 1 2 4 8 --out " + Q(dir / "o.exr"));
  EXPECT_EQ(absent.exit_code, 2) << absent.output;
  EXPECT_NE(absent.output.find("absent.png"), std::string::npos) << absent.output;

  // One error line each, and no output (not even a temporary) was left behind.
  for (const auto* r : {&count, &no_file, &short_file, &bad_response, &size, &absent}) {
    EXPECT_EQ(std::count(r->output.begin(), r->output.end(), '\n'), 1) << r->output;
  }
  EXPECT_EQ(CountFiles(dir, ".exr"), 0u);
}

TEST(MergeCli, MasksExcludePixels) {
  const fs::path dir = test::TempDir();
  const auto images = RampImages(dir);
  // Image 1 is spoiled on its left half and masked there.
  cv::Mat spoiled = cv::imread(images[1].string());
  spoiled.colRange(0, 128).setTo(cv::Scalar(255, 0, 255));
  cv::imwrite((dir / "spoiled.png").string(), spoiled);
  cv::Mat mask(24, 256, CV_8UC1, cv::Scalar(255));
  mask.colRange(0, 128).setTo(0);
  cv::imwrite((dir / "mask1.png").string(), mask);
  cv::imwrite((dir / "all.png").string(), cv::Mat(24, 256, CV_8UC1, cv::Scalar(255)));
  const fs::path example = fs::path(HDRIBR_SOURCE_DIR) / "calib/response.example.json";
  const std::string stack = " " + Q(images[0]) + " " + Q(dir / "spoiled.png") + " " + Q(images[2]) +
                            " --times 0.25 1 4 --response " + Q(example);
  const auto masked = test::RunCommand(QuietExe() + " merge" + stack + " --masks " +
                                       Q(dir / "all.png") + " " + Q(dir / "mask1.png") + " " +
                                       Q(dir / "all.png") + " --out " + Q(dir / "m.exr"));
  ASSERT_EQ(masked.exit_code, 0) << masked.output;
  const auto two =
      test::RunCommand(QuietExe() + " merge " + Q(images[0]) + " " + Q(images[2]) +
                       " --times 0.25 4 --response " + Q(example) + " --out " + Q(dir / "two.exr"));
  ASSERT_EQ(two.exit_code, 0) << two.output;
  const cv::Mat m = ReadExr(dir / "m.exr"), t = ReadExr(dir / "two.exr");
  EXPECT_LE(cv::norm(m.colRange(0, 128), t.colRange(0, 128), cv::NORM_INF), 0.0);
  const auto wrong_count = test::RunCommand(QuietExe() + " merge" + stack + " --masks " +
                                            Q(dir / "all.png") + " --out " + Q(dir / "w.exr"));
  EXPECT_EQ(wrong_count.exit_code, 64) << wrong_count.output;
}

}  // namespace
}  // namespace hdribr
