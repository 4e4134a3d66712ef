// The colour fill: pixels of a rendered view that no photo shows get a colour interpolated from
// those around them (pull-push, Gortler et al. 1996, sec. 3.3).
#pragma once

#include <vector>

#include "gl/objects.h"
#include "gl/shader_library.h"

namespace hdribr::render {

// Alpha of a filled pixel in the colour target (1 = blended from photos, 0 = empty).
inline constexpr float kFilledAlpha = 0.5f;

class FillPass {
 public:
  explicit FillPass(const gl::ShaderLibrary& shaders);
  // Fills in place the pixels of `color` (RGBA32F, alpha 1 = from photos, 0 = empty) with the
  // pull-push interpolation of the pixels from photos, alpha kFilledAlpha; nothing changes when
  // no pixel is from photos.
  void Process(const gl::Texture& color);

 private:
  gl::Program pull_;
  gl::Program push_;
  std::vector<gl::Texture> levels_;  // levels 1 (half size) to 1x1, kept while the size holds
  int width_ = 0;
  int height_ = 0;
};

}  // namespace hdribr::render
