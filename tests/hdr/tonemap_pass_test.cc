// The GPU tone-map pass (Reinhard 2002, LEC19 eqs. 8-12) against the CPU reference
// hdr/tonemap.h: log-average by GPU reduction and the mapped colours agree within 1e-3.
#include "render/tonemap_pass.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "gl_test_util.h"
#include "hdr/re_expose.h"
#include "hdr/tonemap.h"

namespace hdribr::render {
namespace {

class TonemapPassTest : public test::GlSuite {};

// RGBA32F texture from a BGR radiance map; alpha = validity.
gl::Texture Upload(const cv::Mat& bgr, const cv::Mat& valid) {
  cv::Mat rgba;
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  for (int y = 0; y < rgba.rows; ++y) {
    for (int x = 0; x < rgba.cols; ++x) {
      rgba.at<cv::Vec4f>(y, x)[3] = valid.at<uint8_t>(y, x) ? 1.0f : 0.0f;
    }
  }
  gl::Texture t = gl::Texture::Create2D(GL_RGBA32F, bgr.cols, bgr.rows);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(t.id(), 0, 0, 0, bgr.cols, bgr.rows, GL_RGBA, GL_FLOAT, rgba.data);
  return t;
}

// RGBA float read-back as BGR + alpha.
cv::Mat ReadBgra(const gl::Texture& t, cv::Mat* alpha) {
  cv::Mat rgba(t.height(), t.width(), CV_32FC4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(rgba.total() * 16),
                    rgba.data);
  cv::Mat bgr;
  cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
  if (alpha) cv::extractChannel(rgba, *alpha, 3);
  return bgr;
}

// A radiance map spanning ~6 decades (log-uniform), coloured, with invalid pixels, zeros and
// values that saturate. Odd size so that the reduction has partial tiles.
void MakeHdr(cv::Mat& hdr, cv::Mat& valid, int w = 157, int h = 93) {
  cv::RNG rng(7);
  hdr.create(h, w, CV_32FC3);
  valid.create(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double l = std::exp(rng.uniform(-7.0, 7.0));
      hdr.at<cv::Vec3f>(y, x) = cv::Vec3f(static_cast<float>(l * rng.uniform(0.2, 1.0)),
                                          static_cast<float>(l * rng.uniform(0.2, 1.0)),
                                          static_cast<float>(l * rng.uniform(0.2, 1.0)));
      valid.at<uint8_t>(y, x) = rng.uniform(0, 10) == 0 ? 0 : 255;
    }
  }
  hdr.at<cv::Vec3f>(3, 4) = cv::Vec3f(0, 0, 0);  // black valid pixel
  valid.at<uint8_t>(3, 4) = 255;
}

TEST_F(TonemapPassTest, LogAverageMatchesCpuReference) {
  cv::Mat hdr, valid;
  MakeHdr(hdr, valid);
  const gl::Texture tex = Upload(hdr, valid);
  TonemapPass pass(*shaders_);
  const double cpu = LogAverageLuminance(hdr, valid, 1e-6);
  const double gpu = pass.LogAverage(tex, 1e-6f);
  EXPECT_NEAR(gpu / cpu, 1.0, 1e-4) << "cpu " << cpu << " gpu " << gpu;
  // No valid pixel: 1, as on the CPU.
  const gl::Texture none = Upload(hdr, cv::Mat::zeros(hdr.size(), CV_8UC1));
  EXPECT_EQ(pass.LogAverage(none), 1.0f);
}

TEST_F(TonemapPassTest, ToneMapMatchesCpuReferenceWithin1e3) {
  cv::Mat hdr, valid;
  MakeHdr(hdr, valid);
  const gl::Texture tex = Upload(hdr, valid);
  TonemapPass pass(*shaders_);
  gl::Texture display = gl::Texture::Create2D(GL_RGBA32F, hdr.cols, hdr.rows);
  for (const auto& [key, exposure, gamma] :
       {std::tuple{0.18, 1.0, 2.2}, std::tuple{0.5, 4.0, 1.0}, std::tuple{0.09, 0.25, 2.4}}) {
    TonemapOptions gpu_opt;
    gpu_opt.key = static_cast<float>(key);
    gpu_opt.exposure = static_cast<float>(exposure);
    gpu_opt.gamma = static_cast<float>(gamma);
    const float l_a = pass.Apply(tex, gpu_opt, display);
    ReinhardOptions cpu_opt;
    cpu_opt.key = key;
    cpu_opt.exposure = exposure;
    cpu_opt.gamma = gamma;
    const cv::Mat want = ToneMapReinhard(hdr, cpu_opt, valid);
    EXPECT_NEAR(l_a / LogAverageLuminance(hdr, valid), 1.0, 1e-4);
    cv::Mat alpha;
    const cv::Mat got = ReadBgra(display, &alpha);
    double max_err = 0;
    for (int y = 0; y < hdr.rows; ++y) {
      for (int x = 0; x < hdr.cols; ++x) {
        EXPECT_EQ(alpha.at<float>(y, x), valid.at<uint8_t>(y, x) ? 1.0f : 0.0f);
        for (int c = 0; c < 3; ++c) {
          const float g = got.at<cv::Vec3f>(y, x)[c];
          ASSERT_TRUE(std::isfinite(g));
          max_err =
              std::max(max_err, std::abs(static_cast<double>(g) - want.at<cv::Vec3f>(y, x)[c]));
        }
      }
    }
    EXPECT_LE(max_err, 1e-3) << "key " << key << " exposure " << exposure << " gamma " << gamma;
    EXPECT_GT(cv::norm(want, cv::NORM_INF), 0.5);  // the comparison is not trivially on zeros
  }
}

TEST_F(TonemapPassTest, FixedLogAverageSmoothingAndRgba8) {
  cv::Mat hdr(8, 8, CV_32FC3, cv::Scalar(2, 2, 2)), valid(8, 8, CV_8UC1, cv::Scalar(255));
  const gl::Texture bright = Upload(hdr, valid);
  const gl::Texture dark = Upload(hdr * 0.01, valid);
  TonemapPass pass(*shaders_);
  gl::Texture display = gl::Texture::Create2D(GL_RGBA8, 8, 8);
  TonemapOptions opt;
  opt.fixed_log_average = 0.5f;
  const gl::TimestampQuery before = gl::TimestampQuery::Create();
  const gl::TimestampQuery after = gl::TimestampQuery::Create();
  before.Stamp();
  EXPECT_FLOAT_EQ(pass.Apply(bright, opt, display), 0.5f);
  after.Stamp();
  cv::Mat got = ReadBgra(display, nullptr);
  const double want = std::pow(0.72 / 1.72, 1 / 2.2);  // L_s = 0.18 / 0.5 * 2
  EXPECT_NEAR(got.at<cv::Vec3f>(4, 4)[1], want, 0.5 / 255 + 1e-6);
  // The pass's GPU time lies within the test's own stamps around Apply (timestamps taken in the
  // wrong order would wrap to about 1.8e13 ms); 1 us allowed for clock granularity.
  ASSERT_LE(before.ResultNs(), after.ResultNs());
  EXPECT_LE(pass.last_ms(),
            static_cast<double>(after.ResultNs() - before.ResultNs()) * 1e-6 + 1e-3);
  // Smoothing: L_a = 0.9 previous + 0.1 current.
  opt.fixed_log_average.reset();
  opt.smoothing = 0.9f;
  EXPECT_NEAR(pass.Apply(bright, opt, display), 2.0, 1e-4);  // first frame: no history
  EXPECT_NEAR(pass.Apply(dark, opt, display), 0.9 * 2.0 + 0.1 * 0.02, 1e-4);
  pass.ResetHistory();
  EXPECT_NEAR(pass.Apply(dark, opt, display), 0.02, 1e-5);
  // Without Reinhard: clamp(exposure * C)^(1/gamma).
  opt.enabled = false;
  opt.exposure = 0.25f;
  opt.gamma = 1.0f;
  pass.Apply(bright, opt, display);
  got = ReadBgra(display, nullptr);
  EXPECT_NEAR(got.at<cv::Vec3f>(0, 0)[2], 0.5, 0.5 / 255 + 1e-6);
  opt.gamma = 0.0f;
  EXPECT_THROW(pass.Apply(bright, opt, display), UsageError);
}

// Through the camera's response: the GPU codes are the CPU re-exposure's (hdr/re_expose.h),
// at most one code apart where float and double logarithms round differently.
TEST_F(TonemapPassTest, CameraCurveMatchesTheCpuReExposure) {
  cv::Mat hdr, valid;
  MakeHdr(hdr, valid);
  ResponseCurve curve;
  for (int c = 0; c < 3; ++c) {
    curve.log_inverse[c].resize(256);
    for (int z = 0; z < 256; ++z) {
      curve.log_inverse[c][z] = (2.0 + 0.2 * c) * std::log((z + 0.5) / 128.5) + 0.1 * c;
    }
  }
  const gl::Texture tex = Upload(hdr, valid);
  TonemapPass pass(*shaders_);
  gl::Texture display = gl::Texture::Create2D(GL_RGBA32F, hdr.cols, hdr.rows);
  TonemapOptions o;
  o.camera_curve = true;
  o.exposure = 0.5f;
  EXPECT_THROW(pass.Apply(tex, o, display), UsageError);  // no response yet
  pass.SetResponse(curve);
  pass.Apply(tex, o, display);
  const cv::Mat want = ExposeThroughResponse(hdr, curve, 0.5);
  cv::Mat alpha;
  const cv::Mat got = ReadBgra(display, &alpha);
  int differ = 0, worst = 0, mid = 0;
  for (int y = 0; y < hdr.rows; ++y) {
    for (int x = 0; x < hdr.cols; ++x) {
      if (!valid.at<uint8_t>(y, x)) continue;
      for (int c = 0; c < 3; ++c) {
        const int g = static_cast<int>(std::lround(got.at<cv::Vec3f>(y, x)[c] * 255.0f));
        const int w = want.at<cv::Vec3b>(y, x)[c];
        differ += g != w;
        worst = std::max(worst, std::abs(g - w));
        mid += w > 5 && w < 250;
      }
    }
  }
  EXPECT_LE(worst, 1);
  EXPECT_LE(differ, static_cast<int>(0.001 * hdr.total() * 3));
  EXPECT_GT(mid, static_cast<int>(0.2 * hdr.total()));  // not only clipped values compared
}

}  // namespace
}  // namespace hdribr::render
