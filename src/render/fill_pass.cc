#include "render/fill_pass.h"

#include <algorithm>
#include <string>

namespace hdribr::render {

FillPass::FillPass(const gl::ShaderLibrary& shaders)
    : pull_(shaders.Build({"fill_pull.comp"})),
      push_(shaders.Build({"fill_push.comp"}, {{"FILLED_ALPHA", std::to_string(kFilledAlpha)}})) {}

void FillPass::Process(const gl::Texture& color) {
  if (color.width() != width_ || color.height() != height_) {
    width_ = color.width();
    height_ = color.height();
    levels_.clear();
    int w = width_, h = height_;
    while (w > 1 || h > 1) {
      w = std::max(1, (w + 1) / 2);
      h = std::max(1, (h + 1) / 2);
      levels_.push_back(gl::Texture::Create2D(GL_RGBA32F, w, h));
    }
  }
  if (levels_.empty()) return;
  auto groups = [](int n) { return static_cast<GLuint>((n + 7) / 8); };
  auto level = [&](size_t l) -> const gl::Texture& { return l == 0 ? color : levels_[l - 1]; };
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  pull_.Use();
  for (size_t l = 0; l < levels_.size(); ++l) {
    glProgramUniform1i(pull_.id(), 0, l == 0 ? 1 : 0);
    glBindImageTexture(0, level(l).id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, level(l + 1).id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(groups(level(l + 1).width()), groups(level(l + 1).height()), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
  push_.Use();
  for (size_t l = levels_.size(); l-- > 0;) {
    glProgramUniform1i(push_.id(), 0, l == 0 ? 1 : 0);
    glBindImageTexture(0, level(l).id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(1, level(l + 1).id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glDispatchCompute(groups(level(l).width()), groups(level(l).height()), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  }
}

}  // namespace hdribr::render
