#include "hdr/response_curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "hdr/exposure_stack.h"
#include "hdr/re_expose.h"
#include "io/atomic_file.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;

ResponseCurve ExampleCurve() {
  ResponseCurve curve;
  curve.source = "test \"quoted\"";
  curve.lambda = 12.5;
  for (int c = 0; c < 3; ++c) {
    curve.log_inverse[c].resize(256);
    for (int z = 0; z < 256; ++z) {
      curve.log_inverse[c][z] = (2.0 + 0.1 * c) * std::log((z + 0.37) / 128.37) + 1e-13 * z;
    }
  }
  return curve;
}

void WriteText(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string ErrorOf(const fs::path& path) {
  try {
    ReadResponseCurve(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ResponseCurve, RoundTripIsExact) {
  const fs::path dir = test::TempDir("response");
  const ResponseCurve curve = ExampleCurve();
  ASSERT_TRUE(curve.IsValid());
  WriteResponseCurve(dir / "r.json", curve);
  const ResponseCurve back = ReadResponseCurve(dir / "r.json");
  EXPECT_EQ(back.source, curve.source);
  ASSERT_TRUE(back.lambda.has_value());
  EXPECT_EQ(*back.lambda, 12.5);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(back.log_inverse[c], curve.log_inverse[c]);
  EXPECT_DOUBLE_EQ(back.Linear(1, 200), std::exp(curve.log_inverse[1][200]));
  // Only the target is left in the folder (atomic write, no temporaries).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(ResponseCurve, LambdaIsOptional) {
  const fs::path dir = test::TempDir("response_nolambda");
  ResponseCurve curve = ExampleCurve();
  curve.lambda.reset();
  WriteResponseCurve(dir / "r.json", curve);
  EXPECT_FALSE(ReadResponseCurve(dir / "r.json").lambda.has_value());
}

TEST(ResponseCurve, TheExampleFileLoads) {
  const ResponseCurve curve =
      ReadResponseCurve(fs::path(HDRIBR_SOURCE_DIR) / "calib/response.example.json");
  EXPECT_TRUE(curve.IsValid());
  EXPECT_DOUBLE_EQ(curve.log_inverse[1][128], 0.0);
}

TEST(ResponseCurve, IsValidChecksSizeFinitenessAndMonotonicity) {
  ResponseCurve curve = ExampleCurve();
  EXPECT_TRUE(curve.IsValid());
  curve.log_inverse[2][100] = NAN;
  EXPECT_FALSE(curve.IsValid());
  curve = ExampleCurve();
  curve.log_inverse[0][50] = curve.log_inverse[0][51] + 1;
  EXPECT_FALSE(curve.IsValid());
  curve = ExampleCurve();
  curve.log_inverse[1].pop_back();
  EXPECT_FALSE(curve.IsValid());
}

TEST(ResponseCurve, BadFilesNameTheFileAndTheProblem) {
  const fs::path dir = test::TempDir("response_bad");
  EXPECT_NE(ErrorOf(dir / "missing.json").find("missing.json"), std::string::npos);

  WriteText(dir / "notjson.json", "{ nope");
  EXPECT_NE(ErrorOf(dir / "notjson.json").find("invalid JSON"), std::string::npos);

  WriteText(dir / "format.json", R"({"format": "hdribr-series", "version": 1})");
  EXPECT_NE(ErrorOf(dir / "format.json").find("not a response file"), std::string::npos);

  WriteText(dir / "version.json", R"({"format": "hdribr-response", "version": 2})");
  EXPECT_NE(ErrorOf(dir / "version.json").find("version"), std::string::npos);

  WriteText(dir / "nog.json", R"({"format": "hdribr-response", "version": 1})");
  EXPECT_NE(ErrorOf(dir / "nog.json").find("log_inverse"), std::string::npos);

  // A valid file, then damaged one way at a time.
  WriteResponseCurve(dir / "good.json", ExampleCurve());
  const nlohmann::json good = nlohmann::json::parse(ReadFileToString(dir / "good.json"));
  auto damaged = [&](const std::string& name, auto&& damage) {
    nlohmann::json j = good;
    damage(j);
    WriteText(dir / name, j.dump());
    return ErrorOf(dir / name);
  };
  EXPECT_NE(damaged("short.json", [](auto& j) { j["log_inverse"]["G"].erase(0); })
                .find("'log_inverse.G' must be an array of 256"),
            std::string::npos);
  EXPECT_NE(
      damaged("nochannel.json", [](auto& j) { j["log_inverse"].erase("R"); }).find("log_inverse.R"),
      std::string::npos);
  EXPECT_NE(damaged("string.json", [](auto& j) { j["log_inverse"]["B"][7] = "x"; })
                .find("'log_inverse.B[7]' is not a number"),
            std::string::npos);
  EXPECT_NE(damaged("decreasing.json", [](auto& j) { j["log_inverse"]["R"][200] = 100.0; })
                .find("decreases at 201"),
            std::string::npos);
  EXPECT_NE(damaged("lambda.json", [](auto& j) { j["lambda"] = -1; }).find("lambda"),
            std::string::npos);
  EXPECT_NE(damaged("source.json", [](auto& j) { j["source"] = 3; }).find("source"),
            std::string::npos);
  EXPECT_EQ(damaged("fine.json", [](auto&) {}), "");
  // Errors name the file.
  EXPECT_NE(damaged("named.json", [](auto& j) { j["version"] = 0; }).find("named.json"),
            std::string::npos);
}

TEST(ShutterTimes, ReadsMemorialStyleAndNamedLines) {
  const fs::path dir = test::TempDir("shutter");
  WriteText(dir / "plain.txt", "32\n16\n\n1/2\n1/1024  # comment\n");
  const ShutterTimes plain = ReadShutterTimes(dir / "plain.txt");
  EXPECT_EQ(plain.times, (std::vector<double>{32, 16, 0.5, 1.0 / 1024}));
  EXPECT_EQ(plain.names, (std::vector<std::string>{"", "", "", ""}));
  WriteText(dir / "named.txt", "# name time\na.png 1/4\nb.png 0.5\n");
  const ShutterTimes named = ReadShutterTimes(dir / "named.txt");
  EXPECT_EQ(named.names, (std::vector<std::string>{"a.png", "b.png"}));
  EXPECT_EQ(named.times, (std::vector<double>{0.25, 0.5}));

  WriteText(dir / "bad.txt", "1/2\n1/0\n");
  try {
    ReadShutterTimes(dir / "bad.txt");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.txt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
  WriteText(dir / "empty.txt", "# nothing\n");
  EXPECT_THROW(ReadShutterTimes(dir / "empty.txt"), InputError);
  WriteText(dir / "three.txt", "a b c\n");
  EXPECT_THROW(ReadShutterTimes(dir / "three.txt"), InputError);
  EXPECT_THROW(ReadShutterTimes(dir / "absent.txt"), InputError);
}

// Re-exposure inverts the response: exp(g(z)) / t exposed for t gives z back for every code of
// every channel, half-way values round to a neighbour, and the ends clip.
TEST(ExposeThroughResponse, InvertsTheResponse) {
  ResponseCurve curve;
  for (int c = 0; c < 3; ++c) {
    curve.log_inverse[c].resize(256);
    for (int z = 0; z < 256; ++z) {
      curve.log_inverse[c][z] = (2.0 + 0.1 * c) * std::log((z + 0.5) / 128.5);
    }
  }
  const double t = 0.25;
  cv::Mat radiance(1, 256, CV_32FC3);
  for (int z = 0; z < 256; ++z) {
    for (int c = 0; c < 3; ++c) {
      radiance.at<cv::Vec3f>(0, z)[c] = static_cast<float>(curve.Linear(c, z) / t);
    }
  }
  const cv::Mat out = ExposeThroughResponse(radiance, curve, t);
  ASSERT_EQ(out.type(), CV_8UC3);
  for (int z = 0; z < 256; ++z) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(out.at<cv::Vec3b>(0, z)[c], z) << z << " " << c;
  }
  // Twice the exposure: brighter; far beyond either end: clipped; no radiance: 0.
  const cv::Mat brighter = ExposeThroughResponse(radiance, curve, 2 * t);
  EXPECT_GT(brighter.at<cv::Vec3b>(0, 100)[1], 100);
  cv::Mat extreme(1, 3, CV_32FC3);
  extreme.at<cv::Vec3f>(0, 0) = cv::Vec3f(1e-12f, 1e-12f, 1e-12f);
  extreme.at<cv::Vec3f>(0, 1) = cv::Vec3f(1e12f, 1e12f, 1e12f);
  extreme.at<cv::Vec3f>(0, 2) = cv::Vec3f(0.0f, -1.0f, std::nanf(""));
  const cv::Mat e = ExposeThroughResponse(extreme, curve, t);
  EXPECT_EQ(e.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(e.at<cv::Vec3b>(0, 1), cv::Vec3b(255, 255, 255));
  EXPECT_EQ(e.at<cv::Vec3b>(0, 2), cv::Vec3b(0, 0, 0));
}

}  // namespace
}  // namespace hdribr
