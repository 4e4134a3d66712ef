// Evaluation reports, GT radiance conversion and point colours from photos (OpenGL-free).
#include "eval/report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "eval/gt_views.h"
#include "eval/point_colors.h"
#include "io/atomic_file.h"
#include "test_util.h"

namespace hdribr::eval {
namespace {

EvalReport TwoViewReport() {
  EvalReport r;
  r.kind = "leave-one-out";
  r.workspace = "ws";
  r.series = "series1";
  for (int v = 0; v < 2; ++v) {
    ViewReport view;
    view.name = "view" + std::to_string(v);
    view.width = 4;
    view.height = 3;
    MethodScores a;
    a.method = "hdribr";
    a.scores.psnr_db = 30.0 + 2.0 * v;
    a.scores.ssim = 0.9;
    a.scores.coverage = 0.5;
    a.scores.pixels = 6;
    a.own_coverage = 0.75;
    a.point_coverage = 0.625;
    a.own_scores.psnr_db = 28.0 + v;
    a.own_scores.ssim = 0.8;
    a.own_scores.pixels = 9;
    if (v == 1) {  // filled in view 1 only: the fill's PSNR is averaged over that view alone
      a.filled_coverage = 0.25;
      a.fill_scores.psnr_db = 15.0;
      a.fill_scores.pixels = 3;
    }
    MethodScores b = a;
    b.method = "point_colors";
    b.scores.psnr_db = 20.0;
    if (v == 1) b.scores = {};  // no common pixel in view 1
    view.methods = {a, b};
    r.views.push_back(view);
  }
  return r;
}

TEST(Report, MeansSkipViewsWithoutPixels) {
  const std::vector<MethodScores> mean = MeanScores(TwoViewReport());
  ASSERT_EQ(mean.size(), 2u);
  EXPECT_EQ(mean[0].method, "hdribr");
  EXPECT_DOUBLE_EQ(mean[0].scores.psnr_db, 31.0);
  EXPECT_EQ(mean[0].scores.pixels, 12);
  EXPECT_EQ(mean[1].method, "point_colors");
  EXPECT_DOUBLE_EQ(mean[1].scores.psnr_db, 20.0);  // view 1 has no pixel: not averaged
  EXPECT_DOUBLE_EQ(mean[1].scores.coverage, 0.25);
}

TEST(Report, CsvAndJsonHoldEveryRowAndTheMeans) {
  const EvalReport r = TwoViewReport();
  const std::string csv = FormatCsv(r);
  EXPECT_EQ(csv.rfind("view,method,psnr_db,ssim,coverage,own_coverage,point_coverage,"
                      "own_psnr_db,own_ssim,pixels,filled_coverage,fill_psnr_db\n",
                      0),
            0u);
  EXPECT_NE(csv.find("view0,hdribr,30.0000,0.90000,0.50000,0.75000,0.62500,28.0000,0.80000,6,"
                     "0.00000,0.0000\n"),
            std::string::npos);
  EXPECT_NE(csv.find("view1,hdribr,32.0000,0.90000,0.50000,0.75000,0.62500,29.0000,0.80000,6,"
                     "0.25000,15.0000\n"),
            std::string::npos);
  EXPECT_NE(csv.find("mean,hdribr,31.0000,0.90000,0.50000,0.75000,0.62500,28.5000,"),
            std::string::npos);
  EXPECT_NE(csv.find("mean,hdribr,31.0000"), std::string::npos);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 4 + 2);
  const nlohmann::json j = nlohmann::json::parse(FormatJson(r));
  EXPECT_EQ(j["kind"], "leave-one-out");
  EXPECT_EQ(j["views"].size(), 2u);
  EXPECT_EQ(j["views"][1]["methods"][0]["psnr_db"], 32.0);
  EXPECT_EQ(j["mean"][0]["method"], "hdribr");
  EXPECT_DOUBLE_EQ(j["mean"][0]["psnr_db"].get<double>(), 31.0);
  EXPECT_DOUBLE_EQ(j["mean"][0]["own_psnr_db"].get<double>(), 28.5);
  EXPECT_DOUBLE_EQ(j["mean"][0]["point_coverage"].get<double>(), 0.625);
  EXPECT_DOUBLE_EQ(j["mean"][0]["filled_coverage"].get<double>(), 0.125);
  EXPECT_DOUBLE_EQ(j["mean"][0]["fill_psnr_db"].get<double>(), 15.0);

  const auto dir = test::TempDir("eval_report");
  WriteReport(r, dir / "e.csv", dir / "e.json");
  EXPECT_EQ(ReadFileToString(dir / "e.csv"), csv);
  EXPECT_NE(FormatMeanTable(r).find("hdribr"), std::string::npos);
}

TEST(Report, CommonMaskIsTheIntersection) {
  cv::Mat a(2, 2, CV_8UC1, cv::Scalar(255)), b(2, 2, CV_8UC1, cv::Scalar(0));
  a.at<uint8_t>(0, 0) = 0;
  b.at<uint8_t>(0, 0) = 1;
  b.at<uint8_t>(1, 1) = 7;
  const cv::Mat m = CommonMask({a, b});
  EXPECT_EQ(m.at<uint8_t>(0, 0), 0);
  EXPECT_EQ(m.at<uint8_t>(0, 1), 0);
  EXPECT_EQ(m.at<uint8_t>(1, 1), 255);
  EXPECT_THROW(CommonMask({a, cv::Mat(3, 2, CV_8UC1)}), std::invalid_argument);
}

TEST(Report, ToLdrRoundsAndClamps) {
  cv::Mat f(1, 1, CV_32FC3, cv::Scalar(0.5, -1.0, 2.0));
  const cv::Mat b = ToLdr8(f);
  ASSERT_EQ(b.type(), CV_8UC3);
  EXPECT_EQ(b.at<cv::Vec3b>(0, 0), cv::Vec3b(128, 0, 255));
}

TEST(Report, ErrorMapAndSideBySide) {
  cv::Mat ref(4, 6, CV_8UC3, cv::Scalar(100, 100, 100));
  cv::Mat test = ref.clone();
  test.at<cv::Vec3b>(1, 1) = cv::Vec3b(200, 200, 200);
  cv::Mat mask(4, 6, CV_8UC1, cv::Scalar(255));
  mask.at<uint8_t>(3, 5) = 0;
  const cv::Mat err = ErrorMap(ref, test, mask);
  EXPECT_NE(err.at<cv::Vec3b>(1, 1), err.at<cv::Vec3b>(0, 0));  // error shows
  EXPECT_EQ(err.at<cv::Vec3b>(3, 5), cv::Vec3b(0, 0, 0));       // masked out
  const cv::Mat sheet = SideBySide({ref, test, err}, {"a", "b", "c"}, mask);
  EXPECT_EQ(sheet.cols, 3 * 6 + 2 * 4);
  EXPECT_GT(sheet.rows, 4);
  EXPECT_THROW(SideBySide({ref, cv::Mat(2, 2, CV_8UC3)}, {}), std::invalid_argument);
}

TEST(GtViews, RadianceToLdrMatchesTheCaptureResponseWithoutNoise) {
  synth::SyntheticResponse response;
  cv::Mat radiance(1, 3, CV_32FC3);
  radiance.at<cv::Vec3f>(0, 0) = cv::Vec3f(0, 0, 0);
  radiance.at<cv::Vec3f>(0, 1) = cv::Vec3f(0.2f, 0.5f, 1.0f);
  radiance.at<cv::Vec3f>(0, 2) = cv::Vec3f(100, 100, 100);
  const double t = 1.0 / 128;
  const cv::Mat ldr = RadianceToLdr(radiance, response, t);
  EXPECT_EQ(ldr.at<cv::Vec3b>(0, 2), cv::Vec3b(255, 255, 255));  // saturated
  for (int c = 0; c < 3; ++c) {
    const double z = response.ValueFromExposure(c, radiance.at<cv::Vec3f>(0, 1)[c] * t);
    EXPECT_EQ(ldr.at<cv::Vec3b>(0, 1)[c], std::lround(z));
    // The inverse response brings the value back (round trip through the true curve).
    EXPECT_NEAR(response.ExposureFromValue(c, z) / t, radiance.at<cv::Vec3f>(0, 1)[c], 1e-3);
  }
  // Monotonic in exposure time.
  const cv::Mat brighter = RadianceToLdr(radiance, response, 4 * t);
  EXPECT_GT(brighter.at<cv::Vec3b>(0, 1)[1], ldr.at<cv::Vec3b>(0, 1)[1]);
}

TEST(GtViews, ReadsTheCaptureResponseAndRejectsBadFiles) {
  const auto dir = test::TempDir("eval_gt");
  std::filesystem::create_directories(dir / "gt");
  WriteFileAtomic(dir / "gt/capture.json",
                  R"({"response": {"gamma_bgr": [2, 2.1, 2.2], "knee_bgr": [0.5, 0.4, 0.3],
                      "x_sat": 0.02}})");
  const synth::SyntheticResponse r = ReadCaptureResponse(dir);
  EXPECT_DOUBLE_EQ(r.gamma[2], 2.2);
  EXPECT_DOUBLE_EQ(r.knee[0], 0.5);
  EXPECT_DOUBLE_EQ(r.x_sat, 0.02);
  WriteFileAtomic(dir / "gt/capture.json", R"({"response": {}})");
  EXPECT_THROW(ReadCaptureResponse(dir), InputError);
  EXPECT_THROW(ReadGtNovelViews(dir), InputError);  // no gt/novel model
}

// Two points: one on the plane z = 2 the camera sees, one hidden behind it.
TEST(PointColors, SamplesVisiblePointsAndLeavesAPhotoOut) {
  PointCloud cloud;
  cloud.positions = {Eigen::Vector3f(0, 0, 2), Eigen::Vector3f(0, 0, 3)};
  const Camera camera = Camera::Pinhole(1, 8, 8, 8, 8, 4, 4);
  Rigid3d cam_from_world;  // identity
  cv::Mat depth(8, 8, CV_32FC1, cv::Scalar(2.0f));
  cv::Mat red(16, 16, CV_8UC3, cv::Scalar(0, 0, 255));
  cv::Mat blue(16, 16, CV_8UC3, cv::Scalar(255, 0, 0));
  PointColorSampler sampler(cloud);
  EXPECT_EQ(sampler.AddPhoto(10, red, depth, camera, cam_from_world), 1u);
  EXPECT_EQ(sampler.AddPhoto(11, blue, depth, camera, cam_from_world), 1u);
  const auto all = sampler.Colors();
  EXPECT_TRUE(all[0].isApprox(Eigen::Vector3f(0.5f, 0, 0.5f)));
  EXPECT_LT(all[1].maxCoeff(), 0.0f);  // occluded in every photo: no colour
  const auto without_red = sampler.Colors(10);
  EXPECT_TRUE(without_red[0].isApprox(Eigen::Vector3f(1, 0, 0)));
  const auto without_blue = sampler.Colors(11);
  EXPECT_TRUE(without_blue[0].isApprox(Eigen::Vector3f(0, 0, 1)));
}

}  // namespace
}  // namespace hdribr::eval
