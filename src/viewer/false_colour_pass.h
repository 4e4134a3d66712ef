// The viewer's debug displays (depth, normals, contributing-photo count) coloured on the GPU
// from the renderer's outputs: no read-back, the same pictures as FalseColour.
#pragma once

#include "gl/objects.h"
#include "gl/shader_library.h"
#include "render/renderer.h"

namespace hdribr::viewer {

enum class FalseColourMap {
  kDepth,    // turbo over the valid depth range, near = red
  kNormals,  // camera-space normal n / 2 + 1/2 as RGB
  kCount,    // turbo over [0, photos] contributing photos
  kClasses,  // depth pass classes: front orange, background-filled blue, other grey
};

// RGB display colours of the classes 1 (front) and 2 (background-filled), as in the shader.
inline constexpr float kFrontColour[3] = {1.0f, 0.55f, 0.1f};
inline constexpr float kFilledColour[3] = {0.2f, 0.45f, 1.0f};

class FalseColourPass {
 public:
  // Needs a current GL 4.5 context.
  explicit FalseColourPass(const gl::ShaderLibrary& shaders);

  // Colours `map` of `target` into `display` (RGBA8, the target's size): alpha 1 where the
  // depth is valid, else all 0. `photos` is the top of the count scale; `classes` (R8UI, the
  // target's size) is needed by kClasses.
  void Apply(FalseColourMap map, const render::RenderTarget& target, int photos,
             gl::Texture& display, const gl::Texture* classes = nullptr);

 private:
  gl::Program range_, colour_;
  gl::Buffer range_buffer_;
  gl::Texture turbo_;  // 256 x 1 RGBA8, OpenCV's COLORMAP_TURBO
};

}  // namespace hdribr::viewer
