// Pull-push interpolation (Marroquim et al. 2007) on a pyramid of splat texels.
#pragma once

#include <vector>

#include "gl/objects.h"
#include "gl/shader_library.h"

namespace hdribr::render {

// Pyramid of texel pairs: a = (camera position, radius px), b = (normal, weight); level 0 is
// the full resolution (render target of the projection step), each level half the previous
// (rounded up) down to 1x1.
struct PullPushPyramid {
  std::vector<gl::Texture> a;
  std::vector<gl::Texture> b;
  int width = 0;
  int height = 0;

  static PullPushPyramid Create(int width, int height);
  // Same, with level 0 given (e.g. layer views of a layered projection target).
  static PullPushPyramid Create(gl::Texture level0_a, gl::Texture level0_b);
  int levels() const { return static_cast<int>(a.size()); }
};

class PullPushPass {
 public:
  // occlude: in the push, replace valid texels lying behind the pushed surface.
  PullPushPass(const gl::ShaderLibrary& shaders, bool occlude = false);
  // Fills the holes of level 0 of `pyramid` in place. The camera uniforms (intrinsics of the
  // target) are set on both programs from `intrinsics` (fx, fy, cx, cy) and the size. The
  // push stops at level `last_push_level` (> 0: the caller pushes the finer levels itself).
  void Process(PullPushPyramid& pyramid, const float intrinsics[4], int last_push_level = 0);

 private:
  gl::Program pull_;
  gl::Program push_;
};

}  // namespace hdribr::render
