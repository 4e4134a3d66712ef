#include "viewer/false_colour_pass.h"

#include <cstdint>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace hdribr::viewer {
namespace {

constexpr int kTile = 16;  // workgroup size of both shaders
// viewer_false_colour.comp colours these class values.
static_assert(static_cast<int>(render::DepthClass::kFront) == 1 &&
              static_cast<int>(render::DepthClass::kBackground) == 2);
GLuint Groups(int n) { return static_cast<GLuint>((n + kTile - 1) / kTile); }

}  // namespace

FalseColourPass::FalseColourPass(const gl::ShaderLibrary& shaders)
    : range_(shaders.Build({"viewer_depth_range.comp"})),
      colour_(shaders.Build({"viewer_false_colour.comp"})),
      range_buffer_(2 * sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT) {
  // The LUT is OpenCV's own map, so the GPU picture equals FalseColour's.
  cv::Mat ramp(1, 256, CV_8UC1), bgr, rgba;
  for (int i = 0; i < 256; ++i) ramp.at<std::uint8_t>(0, i) = static_cast<std::uint8_t>(i);
  cv::applyColorMap(ramp, bgr, cv::COLORMAP_TURBO);
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  turbo_ = gl::Texture::Create2D(GL_RGBA8, 256, 1);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(turbo_.id(), 0, 0, 0, 256, 1, GL_RGBA, GL_UNSIGNED_BYTE, rgba.ptr());
}

void FalseColourPass::Apply(FalseColourMap map, const render::RenderTarget& target, int photos,
                            gl::Texture& display, const gl::Texture* classes) {
  HDRIBR_CHECK(display.format() == GL_RGBA8);
  HDRIBR_CHECK(map != FalseColourMap::kClasses ||
               (classes != nullptr && classes->format() == GL_R8UI &&
                classes->width() == target.width() && classes->height() == target.height()));
  HDRIBR_CHECK(display.width() == target.width() && display.height() == target.height());
  const int w = target.width(), h = target.height();
  glBindImageTexture(0, target.depth.depth.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, range_buffer_.id());
  if (map == FalseColourMap::kDepth) {
    const std::uint32_t init[2] = {0x7f800000u, 0u};  // +inf, 0
    glNamedBufferSubData(range_buffer_.id(), 0, sizeof(init), init);
    range_.Use();
    glDispatchCompute(Groups(w), Groups(h), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  colour_.Use();
  glUniform1i(colour_.Uniform("u_map"), static_cast<int>(map));
  glUniform1f(colour_.Uniform("u_count_hi"), static_cast<float>(photos));
  glBindImageTexture(1, target.depth.normal.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA16F);
  glBindImageTexture(2, target.aux.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(3, display.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
  if (classes != nullptr) {
    glBindImageTexture(4, classes->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8UI);
  }
  glBindTextureUnit(0, turbo_.id());
  glDispatchCompute(Groups(w), Groups(h), 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                  GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  glUseProgram(0);
}

}  // namespace hdribr::viewer
