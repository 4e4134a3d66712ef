#include "render/pull_push.h"

#include <algorithm>

namespace hdribr::render {

PullPushPyramid PullPushPyramid::Create(int width, int height) {
  PullPushPyramid p;
  p.width = width;
  p.height = height;
  int w = width, h = height;
  while (true) {
    p.a.push_back(gl::Texture::Create2D(GL_RGBA32F, w, h));
    p.b.push_back(gl::Texture::Create2D(GL_RGBA32F, w, h));
    if (w == 1 && h == 1) break;
    w = std::max(1, (w + 1) / 2);
    h = std::max(1, (h + 1) / 2);
  }
  return p;
}

PullPushPyramid PullPushPyramid::Create(gl::Texture level0_a, gl::Texture level0_b) {
  const int width = level0_a.width(), height = level0_a.height();
  PullPushPyramid p = Create(std::max(1, (width + 1) / 2), std::max(1, (height + 1) / 2));
  if (width == 1 && height == 1) p = {};
  p.a.insert(p.a.begin(), std::move(level0_a));
  p.b.insert(p.b.begin(), std::move(level0_b));
  p.width = width;
  p.height = height;
  return p;
}

PullPushPass::PullPushPass(const gl::ShaderLibrary& shaders, bool occlude)
    : pull_(shaders.Build({"pull.comp"})),
      push_(shaders.Build({"push.comp"}, {{"OCCLUDE", occlude ? "1" : "0"}})) {}

void PullPushPass::Process(PullPushPyramid& pyramid, const float intrinsics[4],
                           int last_push_level) {
  const float size[2] = {static_cast<float>(pyramid.width), static_cast<float>(pyramid.height)};
  for (const gl::Program* prog : {&pull_, &push_}) {
    glProgramUniform4fv(prog->id(), 2, 1, intrinsics);
    glProgramUniform2fv(prog->id(), 3, 1, size);
  }
  auto groups = [](int n) { return static_cast<GLuint>((n + 7) / 8); };
  const int levels = pyramid.levels();
  pull_.Use();
  for (int l = 0; l + 1 < levels; ++l) {
    glBindImageTexture(0, pyramid.a[l].id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, pyramid.b[l].id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(2, pyramid.a[l + 1].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(3, pyramid.b[l + 1].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(groups(pyramid.a[l + 1].width()), groups(pyramid.a[l + 1].height()), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
  push_.Use();
  for (int l = levels - 2; l >= last_push_level; --l) {
    glProgramUniform1f(push_.id(), 5, static_cast<float>(1 << l));
    glBindImageTexture(0, pyramid.a[l].id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(1, pyramid.b[l].id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(2, pyramid.a[l + 1].id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(3, pyramid.b[l + 1].id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glDispatchCompute(groups(pyramid.a[l].width()), groups(pyramid.a[l].height()), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_FRAMEBUFFER_BARRIER_BIT);
  }
}

}  // namespace hdribr::render
