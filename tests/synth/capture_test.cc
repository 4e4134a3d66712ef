// A small synthetic capture checked against its own ground truth: geometry, photos, EXIF,
// response, radiance range, determinism, workspace, refusal to overwrite.
#include "synth/capture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "hdr/response_curve.h"
#include "io/colmap_model.h"
#include "io/exif.h"
#include "io/exr.h"
#include "io/image.h"
#include "io/ply.h"
#include "io/workspace.h"
#include "support/test_capture.h"
#include "test_util.h"

namespace hdribr::synth {
namespace {
namespace fs = std::filesystem;

CaptureOptions SmallOptions() { return test::TestCaptureOptions({3, 3, 256, 192, 2, 5}); }

// The capture of the suite Capture, in dir/capture, and WriteCapture's summary of it in
// dir/summary.txt ("photos novel").
void WriteSuiteCapture(const fs::path& dir) {
  const CaptureSummary summary = WriteCapture(SmallOptions(), dir / "capture");
  std::ofstream(dir / "summary.txt") << summary.photos << " " << summary.novel << "\n";
}
constexpr char kCaptureFixture[] = "SynthCapture";

// The setup of the shared fixture (tests/synth/CMakeLists.txt): the capture, once per CTest
// run, which every test of Capture reads.
TEST(Fixture, SynthCapture) { test::RemakeSharedFixture(kCaptureFixture, WriteSuiteCapture); }

class Capture : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const fs::path fixture = test::SharedFixture(kCaptureFixture, WriteSuiteCapture);
    dir_ = fixture / "capture";
    std::ifstream(fixture / "summary.txt") >> summary_.photos >> summary_.novel;
    model_ = ReadColmapModelText(dir_ / "gt");
    points_ = ReadPly(dir_ / "gt/points.ply");
  }
  static std::string Stem(const ColmapImage& im) { return fs::path(im.name).stem().string(); }

  static inline fs::path dir_;
  static inline CaptureSummary summary_;
  static inline ColmapModel model_;
  static inline PointCloud points_;
};

// Inverse depth interpolated bilinearly (exact for planes) where the 4 neighbours agree within
// 2%; the nearest pixel's depth otherwise (silhouettes). 0 outside or on sky.
double SampleDepth(const cv::Mat& depth, const Eigen::Vector2d& px) {
  const double fx = px.x() - 0.5, fy = px.y() - 0.5;
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= depth.cols || y0 + 1 >= depth.rows) return 0;
  const double a = fx - x0, b = fy - y0;
  const double d00 = depth.at<float>(y0, x0), d10 = depth.at<float>(y0, x0 + 1);
  const double d01 = depth.at<float>(y0 + 1, x0), d11 = depth.at<float>(y0 + 1, x0 + 1);
  const double lo = std::min({d00, d10, d01, d11}), hi = std::max({d00, d10, d01, d11});
  if (lo <= 0 || hi > 1.02 * lo) {
    return depth.at<float>(static_cast<int>(px.y()), static_cast<int>(px.x()));
  }
  const double inv = (1 - a) * (1 - b) / d00 + a * (1 - b) / d10 + (1 - a) * b / d01 + a * b / d11;
  return 1.0 / inv;
}

TEST_F(Capture, WritesEveryFile) {
  EXPECT_EQ(summary_.photos, 9);
  EXPECT_EQ(summary_.novel, 2);
  EXPECT_EQ(model_.images.size(), 9u);
  ASSERT_EQ(model_.cameras.size(), 1u);
  EXPECT_EQ(model_.cameras.begin()->second.model, CameraModel::kPinhole);
  for (const auto& [id, im] : model_.images) {
    EXPECT_TRUE(fs::exists(dir_ / "photos" / im.name)) << im.name;
    EXPECT_TRUE(fs::exists(dir_ / "workspace/images" / im.name)) << im.name;
    EXPECT_TRUE(fs::exists(dir_ / "gt/depth" / (Stem(im) + ".exr"))) << im.name;
    EXPECT_TRUE(fs::exists(dir_ / "gt/radiance" / (Stem(im) + ".exr"))) << im.name;
  }
  const ColmapModel novel = ReadColmapModelText(dir_ / "gt/novel");
  EXPECT_EQ(novel.images.size(), 2u);
  for (const auto& [id, im] : novel.images) {
    const cv::Mat d = ReadExr(dir_ / "gt/novel/depth" / (Stem(im) + ".exr"));
    const cv::Mat r = ReadExr(dir_ / "gt/novel/radiance" / (Stem(im) + ".exr"));
    EXPECT_EQ(d.type(), CV_32FC1);
    EXPECT_EQ(r.type(), CV_32FC3);
    EXPECT_EQ(d.cols, 256);
  }
  EXPECT_TRUE(fs::exists(dir_ / "calib/response.json"));
  EXPECT_TRUE(fs::exists(dir_ / "gt/capture.json"));
  // No temporary folder (.capture.partial-PID) left beside the output.
  for (const auto& e : fs::directory_iterator(dir_.parent_path())) {
    EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
  }
}

TEST_F(Capture, PointsHaveNormalsRadiiAndReproduceGtDepth) {
  ASSERT_GT(points_.size(), 10000u);
  ASSERT_TRUE(points_.HasNormals());
  ASSERT_TRUE(points_.HasRadii());
  ASSERT_TRUE(points_.IsConsistent());
  const Camera& cam = model_.cameras.begin()->second;
  std::vector<double> rel;
  size_t behind = 0;
  for (const auto& [id, im] : model_.images) {
    const cv::Mat depth = ReadExr(dir_ / "gt/depth" / (Stem(im) + ".exr"));
    const Eigen::Vector3d centre = im.cam_from_world.Inverse().translation;
    for (size_t i = 0; i < points_.size(); i += 7) {
      const Eigen::Vector3d p = points_.positions[i].cast<double>();
      // Only surfaces facing the camera (back faces are hidden by construction).
      if (points_.normals[i].cast<double>().dot(centre - p) <= 0) continue;
      const Eigen::Vector3d pc = im.cam_from_world * p;
      if (pc.z() <= 0) continue;
      const Eigen::Vector2d px = cam.PixelFromCam(pc);
      const double d = SampleDepth(depth, px);
      if (d <= 0) continue;
      rel.push_back(std::abs(d - pc.z()) / pc.z());
      behind += d < 0.99 * pc.z();  // occluded from this view
    }
  }
  ASSERT_GT(rel.size(), 10000u);
  std::nth_element(rel.begin(), rel.begin() + rel.size() / 2, rel.end());
  const double median = rel[rel.size() / 2];
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", median);
  RecordProperty("median_relative_depth_error", text);
  EXPECT_LT(median, 1e-3) << "occluded share " << double(behind) / rel.size();
}

TEST_F(Capture, PointsSampledFromAViewLandOnItsPixelCentres) {
  // The points are exact ray hits through pixel centres of the photos: every point projects
  // (in some photo) onto a pixel centre, and that pixel's GT depth is the point's depth.
  const Camera& cam = model_.cameras.begin()->second;
  std::vector<char> found(points_.size(), 0);
  for (const auto& [id, im] : model_.images) {
    const cv::Mat depth = ReadExr(dir_ / "gt/depth" / (Stem(im) + ".exr"));
    for (size_t i = 0; i < points_.size(); ++i) {
      if (found[i]) continue;
      const Eigen::Vector3d pc = im.cam_from_world * points_.positions[i].cast<double>();
      if (pc.z() <= 0) continue;
      const Eigen::Vector2d px = cam.PixelFromCam(pc);
      const double fx = px.x() - 0.5 - std::round(px.x() - 0.5);
      const double fy = px.y() - 0.5 - std::round(px.y() - 0.5);
      if (std::abs(fx) > 2e-3 || std::abs(fy) > 2e-3) continue;  // float positions
      const int x = static_cast<int>(std::lround(px.x() - 0.5));
      const int y = static_cast<int>(std::lround(px.y() - 0.5));
      if (x < 0 || y < 0 || x >= depth.cols || y >= depth.rows) continue;
      found[i] = std::abs(depth.at<float>(y, x) - pc.z()) < 1e-5 * pc.z() ? 1 : 0;
    }
  }
  const double share = double(std::count(found.begin(), found.end(), 1)) / points_.size();
  EXPECT_GT(share, 0.999);
}

TEST_F(Capture, SplatsOverlapAndCoverEveryVisibleSurface) {
  // Splat every point visible in a photo as a disc of its projected radius: together they
  // cover the photo's non-sky pixels.
  const Camera& cam = model_.cameras.begin()->second;
  const ColmapImage& im = model_.images.begin()->second;
  const cv::Mat depth = ReadExr(dir_ / "gt/depth" / (Stem(im) + ".exr"));
  cv::Mat covered(depth.size(), CV_8UC1, cv::Scalar(0));
  for (size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d pc = im.cam_from_world * points_.positions[i].cast<double>();
    if (pc.z() <= 0) continue;
    const Eigen::Vector2d px = cam.PixelFromCam(pc);
    const double d = SampleDepth(depth, px);
    if (d <= 0 || std::abs(d - pc.z()) > 0.01 * pc.z()) continue;
    const double r = points_.radii[i] * cam.fx() / pc.z();
    cv::circle(covered, cv::Point(int(px.x()), int(px.y())), std::max(0, int(std::floor(r))),
               cv::Scalar(255), cv::FILLED);
  }
  const cv::Mat surface = depth > 0;
  const double surface_px = cv::countNonZero(surface);
  cv::Mat hit;
  cv::bitwise_and(surface, covered, hit);
  const double coverage = cv::countNonZero(hit) / surface_px;
  RecordProperty("splat_coverage", std::to_string(coverage));
  EXPECT_GT(coverage, 0.97);
}

TEST_F(Capture, PhotosDecodeWithTheWrittenExif) {
  const nlohmann::json j =
      nlohmann::json::parse(std::ifstream(dir_ / "gt/capture.json", std::ios::binary));
  const auto times = j["exposure_times_s"].get<std::vector<double>>();
  ASSERT_EQ(times.size(), 3u);
  EXPECT_NEAR(std::log2(times[1] / times[0]), 2.0, 1e-9);
  EXPECT_NEAR(std::log2(times[2] / times[1]), 2.0, 1e-9);
  for (const auto& [id, im] : model_.images) {
    const cv::Mat photo = ReadImage(dir_ / "photos" / im.name);
    EXPECT_EQ(photo.cols, 256);
    EXPECT_EQ(photo.rows, 192);
    const ExifInfo exif = ReadExif(dir_ / "photos" / im.name);
    const int series = im.name[1] - '0';
    ASSERT_TRUE(exif.exposure.time_s.has_value()) << im.name;
    EXPECT_NEAR(*exif.exposure.time_s, times[series], 1e-9 * times[series]) << im.name;
    ASSERT_TRUE(exif.exposure.iso && exif.exposure.f_number && exif.exposure.focal_mm);
    EXPECT_NEAR(*exif.exposure.iso, j["iso"].get<double>(), 1e-9);
    EXPECT_NEAR(*exif.exposure.f_number, j["f_number"].get<double>(), 1e-6);
    EXPECT_NEAR(*exif.exposure.focal_mm, j["focal_mm"].get<double>(), 1e-3);
  }
}

// Quantile of a copy of v.
double Quantile(std::vector<double> v, double q) {
  const size_t k = static_cast<size_t>(q * (v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

TEST_F(Capture, InverseResponseRecoversGtRadiance) {
  const ResponseCurve curve = ReadResponseCurve(dir_ / "calib/response.json");
  ASSERT_TRUE(curve.IsValid());
  const nlohmann::json j =
      nlohmann::json::parse(std::ifstream(dir_ / "gt/capture.json", std::ios::binary));
  const auto times = j["exposure_times_s"].get<std::vector<double>>();
  // Per unclipped channel value (10..245): the error in 8-bit levels between the photo and the
  // true response applied to the GT radiance, and the relative error of exp(g(z)) / t against
  // the GT radiance. "smooth": the GT radiance varies by less than 5% over the 9x9
  // neighbourhood, where JPEG (DCT blocks, 4:2:0 chroma) is nearly lossless, so that only the
  // 8-bit quantisation and the sensor noise remain.
  std::vector<double> level_all, level_smooth, rel_smooth;
  for (const auto& [id, im] : model_.images) {
    const cv::Mat photo = ReadImage(dir_ / "photos" / im.name);
    const cv::Mat radiance = ReadExr(dir_ / "gt/radiance" / (Stem(im) + ".exr"));
    std::vector<cv::Mat> ch;
    cv::split(radiance, ch);
    const cv::Mat kernel = cv::Mat::ones(9, 9, CV_8U);
    std::vector<cv::Mat> lo(3), hi(3);
    for (int c = 0; c < 3; ++c) {
      cv::erode(ch[c], lo[c], kernel);
      cv::dilate(ch[c], hi[c], kernel);
    }
    const double t = times[static_cast<size_t>(im.name[1] - '0')];
    for (int y = 0; y < photo.rows; ++y) {
      for (int x = 0; x < photo.cols; ++x) {
        const cv::Vec3b z = photo.at<cv::Vec3b>(y, x);
        const cv::Vec3f l = radiance.at<cv::Vec3f>(y, x);
        bool smooth = true;
        for (int c = 0; c < 3; ++c) {
          smooth &= hi[c].at<float>(y, x) <= 1.05f * lo[c].at<float>(y, x);
        }
        for (int c = 0; c < 3; ++c) {
          if (z[c] < 10 || z[c] > 245) continue;
          // Continuous level of the true exposure: g inverted by interpolation in the table.
          const auto& g = curve.log_inverse[c];
          const double lx = std::log(double(l[c]) * t);
          const auto it = std::upper_bound(g.begin(), g.end(), lx);
          if (it == g.begin() || it == g.end()) continue;
          const int k = static_cast<int>(it - g.begin()) - 1;
          const double zt = k + (lx - g[k]) / (g[k + 1] - g[k]);
          level_all.push_back(std::abs(zt - z[c]));
          if (!smooth) continue;
          level_smooth.push_back(std::abs(zt - z[c]));
          rel_smooth.push_back(std::abs(std::exp(g[z[c]]) / t - l[c]) / l[c]);
        }
      }
    }
  }
  ASSERT_GT(level_smooth.size(), 20000u);
  const double med_all = Quantile(level_all, 0.5), p90_all = Quantile(level_all, 0.9);
  const double med = Quantile(level_smooth, 0.5), p90 = Quantile(level_smooth, 0.9);
  const double med_rel = Quantile(rel_smooth, 0.5);
  RecordProperty("level_error_all_median", std::to_string(med_all));
  RecordProperty("level_error_all_p90", std::to_string(p90_all));
  RecordProperty("level_error_smooth_median", std::to_string(med));
  RecordProperty("level_error_smooth_p90", std::to_string(p90));
  RecordProperty("relative_radiance_error_smooth_median", std::to_string(med_rel));
  std::printf(
      "levels: all median %.3f p90 %.3f; smooth (%zu values) median %.3f p90 %.3f; "
      "radiance relative error median %.4f\n",
      med_all, p90_all, level_smooth.size(), med, p90, med_rel);
  // Rounding alone: uniform in [0, 0.5], median 0.25, p90 0.45; the noise adds under a level.
  EXPECT_LT(med, 0.75);
  EXPECT_LT(p90, 1.5);
  EXPECT_LT(med_rel, 0.015);
  // Everywhere, with JPEG's losses on the textures: still unbiased to a couple of levels.
  EXPECT_LT(med_all, 2.0);
}

TEST_F(Capture, RadianceSpansThreeOrdersOfMagnitude) {
  std::vector<float> lum;
  for (const auto& [id, im] : model_.images) {
    const cv::Mat r = ReadExr(dir_ / "gt/radiance" / (Stem(im) + ".exr"));
    for (int y = 0; y < r.rows; ++y) {
      for (int x = 0; x < r.cols; ++x) {
        const cv::Vec3f c = r.at<cv::Vec3f>(y, x);
        lum.push_back(0.2126f * c[2] + 0.7152f * c[1] + 0.0722f * c[0]);
      }
    }
  }
  std::sort(lum.begin(), lum.end());
  const double lo = lum[static_cast<size_t>(0.001 * (lum.size() - 1))];
  const double hi = lum[static_cast<size_t>(0.999 * (lum.size() - 1))];
  RecordProperty("radiance_ratio", std::to_string(hi / lo));
  EXPECT_GT(lo, 0.0);
  EXPECT_GE(hi / lo, 1000.0) << lo << " .. " << hi;
}

TEST_F(Capture, WorkspaceLoadsCleanly) {
  const Scene scene = LoadWorkspace(dir_ / "workspace");
  EXPECT_EQ(scene.photos.size(), 9u);
  ASSERT_EQ(scene.series.size(), 3u);
  for (const auto& s : scene.series) EXPECT_EQ(s.photo_indices.size(), 3u);
  EXPECT_LT(scene.series[0].relative_exposure, scene.series[1].relative_exposure);
  EXPECT_EQ(scene.points.size(), points_.size());
  EXPECT_TRUE(ValidateScene(scene).empty());
}

std::map<std::string, std::string> ReadTree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file()) continue;
    std::ifstream in(e.path(), std::ios::binary);
    files[fs::relative(e.path(), root).string()] =
        std::string(std::istreambuf_iterator<char>(in), {});
  }
  return files;
}

TEST(CaptureDeterminism, SameSeedSameBytesOtherSeedOtherPhotos) {
  const fs::path tmp = test::TempDir();
  CaptureOptions o = test::TestCaptureOptions({2, 2, 96, 72, 1, 11});
  WriteCapture(o, tmp / "a");
  o.threads = 1;
  WriteCapture(o, tmp / "b");
  o.seed = 12;
  WriteCapture(o, tmp / "c");
  const auto a = ReadTree(tmp / "a"), b = ReadTree(tmp / "b"), c = ReadTree(tmp / "c");
  ASSERT_EQ(a.size(), b.size());
  EXPECT_GT(a.size(), 20u);
  for (const auto& [name, bytes] : a) {
    ASSERT_TRUE(b.count(name)) << name;
    EXPECT_TRUE(bytes == b.at(name)) << name << " differs between runs with the same seed";
  }
  EXPECT_FALSE(a.at("photos/s0_v00.jpg") == c.at("photos/s0_v00.jpg"));
}

TEST(CaptureInput, RefusesANonEmptyOutputAndBadOptions) {
  const fs::path tmp = test::TempDir();
  fs::create_directories(tmp / "out");
  { std::ofstream(tmp / "out/keep.txt") << "mine"; }
  CaptureOptions o;
  o.series = 1;
  o.views = 1;
  o.width = 32;
  o.height = 24;
  EXPECT_THROW(WriteCapture(o, tmp / "out"), InputError);
  EXPECT_EQ(std::distance(fs::directory_iterator(tmp / "out"), fs::directory_iterator()), 1);
  o.scene = "nope";
  EXPECT_THROW(WriteCapture(o, tmp / "new"), UsageError);
  EXPECT_FALSE(fs::exists(tmp / "new"));
  o.scene = "default";
  o.views = 0;
  EXPECT_THROW(WriteCapture(o, tmp / "new"), UsageError);
  o.views = 1;
  for (double ev : {0.0, -2.0, std::nan(""), HUGE_VAL}) {
    o.ev_step = ev;  // equal or undefined exposure times: no HDR capture
    EXPECT_THROW(WriteCapture(o, tmp / "new"), UsageError) << ev;
  }
  o.ev_step = 2.0;
  o.threads = -1;
  EXPECT_THROW(WriteCapture(o, tmp / "new"), UsageError);
  o.threads = 0;
  o.exposure = "manual";
  EXPECT_THROW(WriteCapture(o, tmp / "new"), UsageError);
  o.exposure = "auto";
  for (double e : {-0.01, 0.6, std::nan("")}) {
    o.exif_error = e;
    EXPECT_THROW(WriteCapture(o, tmp / "new"), UsageError) << e;
  }
  // Only the pre-existing folder remains: no partial outputs.
  EXPECT_EQ(std::distance(fs::directory_iterator(tmp), fs::directory_iterator()), 1);
}

// Auto exposure: every photo metered on its own view, EXIF at a 1/n shutter speed on the
// 1/3-stop grid, the true time off by exif_error, everything recorded in capture.json.
TEST(AutoExposure, MetersEveryPhotoAndRecordsTheTruth) {
  CaptureOptions o = SmallOptions();
  o.width = 96;
  o.height = 72;
  o.novel_views = 0;
  o.exposure = "auto";
  o.exif_error = 0.05;
  const CapturePlan plan = PlanCapture(o);
  ASSERT_EQ(plan.photos.size(), 9u);
  double lo = HUGE_VAL, hi = 0, sum_sq = 0;
  for (const PlannedView& v : plan.photos) {
    const double n = 1.0 / v.exif_time_s;
    EXPECT_NEAR(n, std::round(n), 1e-9 * n) << v.name;  // 1/n s
    const double thirds = 3 * std::log2(v.exif_time_s);
    EXPECT_NEAR(thirds, std::round(thirds), 0.1) << v.name;  // 1/3 stop, up to the 1/n rounding
    const double err = std::log(v.exposure_time_s / v.exif_time_s);
    EXPECT_LT(std::abs(err), 4 * o.exif_error) << v.name;
    sum_sq += err * err;
    lo = std::min(lo, v.exif_time_s);
    hi = std::max(hi, v.exif_time_s);
  }
  EXPECT_GT(std::sqrt(sum_sq / plan.photos.size()), 0.3 * o.exif_error);
  EXPECT_NEAR(std::log2(hi / lo), 2 * o.ev_step, 1.0);  // bracketing offsets of +-1 series

  const fs::path dir = test::TempDir("synth_auto") / "capture";
  WriteCapture(o, dir);
  const nlohmann::json j =
      nlohmann::json::parse(std::ifstream(dir / "gt/capture.json", std::ios::binary));
  EXPECT_EQ(j["exposure"], "auto");
  EXPECT_FALSE(j.contains("exposure_times_s"));
  ASSERT_EQ(j["photos"].size(), plan.photos.size());
  for (size_t i = 0; i < plan.photos.size(); ++i) {
    const auto& p = j["photos"][i];
    ASSERT_EQ(p["name"], plan.photos[i].name);
    EXPECT_DOUBLE_EQ(p["exposure_time_s"].get<double>(), plan.photos[i].exposure_time_s);
    const ExifInfo exif = ReadExif(dir / "photos" / plan.photos[i].name);
    ASSERT_TRUE(exif.exposure.time_s.has_value());
    EXPECT_NEAR(*exif.exposure.time_s, plan.photos[i].exif_time_s, 1e-12);
  }
  // The workspace's series are the EXIF groups, darkest first.
  const Scene scene = LoadWorkspace(dir / "workspace");
  EXPECT_GE(scene.series.size(), 3u);
}

}  // namespace
}  // namespace hdribr::synth
