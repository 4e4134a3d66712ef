// The colour fill (render/fill_pass.h) on colour targets with known holes: what photos show is
// never changed, holes get colours from their surroundings.
#include "render/fill_pass.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "gl_test_util.h"

namespace hdribr::render {
namespace {

class FillPassTest : public test::GlSuite {
 protected:
  // RGBA32F target of `rgba`'s size holding it (rows top to bottom).
  static gl::Texture Upload(const cv::Mat& rgba) {
    gl::Texture t = gl::Texture::Create2D(GL_RGBA32F, rgba.cols, rgba.rows);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(t.id(), 0, 0, 0, rgba.cols, rgba.rows, GL_RGBA, GL_FLOAT, rgba.data);
    return t;
  }
  static cv::Mat Download(const gl::Texture& t) {
    cv::Mat rgba(t.height(), t.width(), CV_32FC4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(rgba.total() * 16),
                      rgba.data);
    return rgba;
  }
  // A smooth colour field in [0.1, 0.9].
  static cv::Vec4f Field(int x, int y, int w, int h) {
    const float u = static_cast<float>(x) / w, v = static_cast<float>(y) / h;
    return {0.2f + 0.6f * u, 0.3f + 0.4f * v, 0.5f + 0.3f * std::sin(3.0f * u + 2.0f * v), 1.0f};
  }
};

// A band along the frame's left edge and a disc inside: every hole pixel is filled, within the
// range of the colours around it and far closer to the field than their mean colour.
TEST_F(FillPassTest, FillsHolesFromTheirSurroundings) {
  const int w = 97, h = 61;  // odd: levels rounded up
  cv::Mat truth(h, w, CV_32FC4), hole(h, w, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      truth.at<cv::Vec4f>(y, x) = Field(x, y, w, h);
      const bool band = x < 20;
      const bool disc = (x - 65) * (x - 65) + (y - 30) * (y - 30) < 36;
      if (band || disc || (x == 80 && y == 10)) hole.at<uint8_t>(y, x) = 255;
    }
  }
  cv::Mat input = truth.clone();
  input.setTo(cv::Scalar::all(0), hole);
  gl::Texture target = Upload(input);
  FillPass fill(*shaders_);
  fill.Process(target);
  const cv::Mat out = Download(target);
  const cv::Mat shown = hole == 0;
  EXPECT_EQ(cv::norm(out, input, cv::NORM_INF, shown), 0.0);  // what photos show is kept
  double lo[4], hi[4];
  for (int c = 0; c < 3; ++c) {
    cv::Mat channel;
    cv::extractChannel(input, channel, c);
    cv::minMaxLoc(channel, &lo[c], &hi[c], nullptr, nullptr, shown);
  }
  const cv::Scalar mean = cv::mean(input, shown);
  double fill_error[2] = {0, 0}, mean_error[2] = {0, 0};
  int count[2] = {0, 0};
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!hole.at<uint8_t>(y, x)) continue;
      const cv::Vec4f o = out.at<cv::Vec4f>(y, x), t = truth.at<cv::Vec4f>(y, x);
      ASSERT_EQ(o[3], kFilledAlpha) << x << "," << y;
      const int k = x < 20 ? 0 : 1;  // band, inner holes
      for (int c = 0; c < 3; ++c) {
        ASSERT_GE(o[c], lo[c] - 1e-6) << x << "," << y;
        ASSERT_LE(o[c], hi[c] + 1e-6) << x << "," << y;
        fill_error[k] += std::abs(o[c] - t[c]);
        mean_error[k] += std::abs(mean[c] - t[c]);
      }
      ++count[k];
    }
  }
  for (int k = 0; k < 2; ++k) {
    fill_error[k] /= 3.0 * count[k];
    mean_error[k] /= 3.0 * count[k];
    std::printf("%s: mean |error| %.4f filled, %.4f with the mean colour\n",
                k == 0 ? "band at the frame's edge" : "inner holes", fill_error[k], mean_error[k]);
  }
  EXPECT_LT(fill_error[0], 0.5 * mean_error[0]);
  EXPECT_LT(fill_error[1], 0.25 * mean_error[1]);
  EXPECT_LT(fill_error[1], 0.01);  // the field changes by 0.009 a pixel at most
  // Filled pixels never feed the fill: a second pass changes nothing.
  fill.Process(target);
  EXPECT_EQ(cv::norm(Download(target), out, cv::NORM_INF), 0.0);
}

// Nothing from photos: nothing to fill from, the target stays empty.
TEST_F(FillPassTest, AnEmptyTargetStaysEmpty) {
  const cv::Mat empty(24, 40, CV_32FC4, cv::Scalar::all(0));
  gl::Texture target = Upload(empty);
  FillPass(*shaders_).Process(target);
  EXPECT_EQ(cv::norm(Download(target), cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace hdribr::render
