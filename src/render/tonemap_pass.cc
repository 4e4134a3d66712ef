#include "render/tonemap_pass.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.h"
#include "render/response_lut.h"

namespace hdribr::render {

namespace {
constexpr int kTile = 16;  // workgroup size of tonemap_reduce.comp and tonemap.comp
int Groups(int n) { return (n + kTile - 1) / kTile; }
}  // namespace

struct TonemapPass::Impl {
  gl::Program reduce, reduce_final, map;
  gl::Buffer partials;
  size_t partial_capacity = 0;
  std::optional<double> history;  // smoothed L_a of the previous frame
  gl::Texture response;           // SetResponse's LUT, empty before
  gl::TimestampQuery start, end;
  bool timed = false;
  double last_ms = 0;

  // Sum of log(eps + L) and the valid count over `hdr`, by the two-step GPU reduction.
  std::pair<double, double> Reduce(const gl::Texture& hdr, float epsilon) {
    const int gx = Groups(hdr.width()), gy = Groups(hdr.height());
    const size_t count = static_cast<size_t>(gx) * static_cast<size_t>(gy);
    if (count > partial_capacity) {
      partials = gl::Buffer(count * 2 * sizeof(float), nullptr, GL_DYNAMIC_STORAGE_BIT);
      partial_capacity = count;
    }
    reduce.Use();
    glUniform1f(reduce.Uniform("u_epsilon"), epsilon);
    glBindImageTexture(0, hdr.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, partials.id());
    glDispatchCompute(static_cast<GLuint>(gx), static_cast<GLuint>(gy), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    reduce_final.Use();
    glUniform1i(reduce_final.Uniform("u_count"), static_cast<GLint>(count));
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    float result[2] = {0, 0};
    glGetNamedBufferSubData(partials.id(), 0, sizeof(result), result);
    return {result[0], result[1]};
  }
};

TonemapPass::TonemapPass(const gl::ShaderLibrary& shaders) : impl_(std::make_unique<Impl>()) {
  impl_->reduce = shaders.Build({"tonemap_reduce.comp"});
  impl_->reduce_final = shaders.Build({"tonemap_reduce_final.comp"});
  impl_->map = shaders.Build({"tonemap.comp"});
  impl_->start = gl::TimestampQuery::Create();
  impl_->end = gl::TimestampQuery::Create();
}

TonemapPass::~TonemapPass() = default;

float TonemapPass::LogAverage(const gl::Texture& hdr, float epsilon) {
  HDRIBR_CHECK(hdr.format() == GL_RGBA32F);
  const auto [sum, count] = impl_->Reduce(hdr, epsilon);
  if (!(count > 0)) return 1.0f;
  const double l_a = std::exp(sum / count);
  return std::isfinite(l_a) && l_a > 0 ? static_cast<float>(l_a) : 1.0f;
}

float TonemapPass::Apply(const gl::Texture& hdr, const TonemapOptions& options,
                         gl::Texture& display) {
  HDRIBR_CHECK(hdr.format() == GL_RGBA32F);
  HDRIBR_CHECK(display.format() == GL_RGBA8 || display.format() == GL_RGBA16F ||
               display.format() == GL_RGBA32F);
  HDRIBR_CHECK(hdr.width() == display.width() && hdr.height() == display.height());
  if (!(options.key > 0) || !(options.gamma > 0) || !(options.exposure >= 0) ||
      !std::isfinite(options.key) || !std::isfinite(options.gamma) ||
      !std::isfinite(options.exposure)) {
    throw UsageError("tone mapping needs key > 0, gamma > 0 and exposure >= 0");
  }
  if (options.fixed_log_average &&
      !(*options.fixed_log_average > 0 && std::isfinite(*options.fixed_log_average))) {
    throw UsageError("a fixed log-average luminance must be positive");
  }
  impl_->start.Stamp();
  double l_a = 1.0;
  if (options.camera_curve && !impl_->response) {
    throw UsageError("tone mapping through the camera's response needs a response curve");
  }
  if (options.fixed_log_average) {
    l_a = *options.fixed_log_average;
  } else if (options.enabled && !options.camera_curve) {
    l_a = LogAverage(hdr, options.epsilon);
    if (options.smoothing > 0 && impl_->history) {
      const double s = std::clamp(static_cast<double>(options.smoothing), 0.0, 1.0);
      l_a = s * *impl_->history + (1.0 - s) * l_a;
    }
    impl_->history = l_a;
  }
  impl_->map.Use();
  glUniform1f(impl_->map.Uniform("u_scale"), static_cast<float>(options.key / l_a));
  glUniform1f(impl_->map.Uniform("u_exposure"), options.exposure);
  glUniform1f(impl_->map.Uniform("u_inv_gamma"), 1.0f / options.gamma);
  glUniform1i(impl_->map.Uniform("u_reinhard"), options.enabled ? 1 : 0);
  glUniform1i(impl_->map.Uniform("u_camera"), options.camera_curve ? 1 : 0);
  if (options.camera_curve) glBindTextureUnit(2, impl_->response.id());
  glBindImageTexture(0, hdr.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(1, display.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, display.format());
  glDispatchCompute(static_cast<GLuint>(Groups(hdr.width())),
                    static_cast<GLuint>(Groups(hdr.height())), 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                  GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
  impl_->end.Stamp();
  impl_->timed = true;
  return static_cast<float>(l_a);
}

void TonemapPass::SetResponse(const ResponseCurve& response) {
  impl_->response = MakeResponseLut(response);
}

bool TonemapPass::has_response() const { return static_cast<bool>(impl_->response); }

void TonemapPass::ResetHistory() { impl_->history.reset(); }

double TonemapPass::last_ms() const {
  if (impl_->timed) {
    impl_->last_ms = static_cast<double>(impl_->end.ResultNs() - impl_->start.ResultNs()) * 1e-6;
    impl_->timed = false;
  }
  return impl_->last_ms;
}

}  // namespace hdribr::render
