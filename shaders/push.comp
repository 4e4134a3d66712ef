#version 450 core
// Push (Marroquim et al. 2007): an empty texel of level l takes the bilinear, depth-grouped
// average of the 4 nearest level l+1 texels whose splat ellipse covers it. With OCCLUDE, a
// valid texel lying entirely behind the pushed surface is replaced too (back-surface pixels
// seen through gaps of a front surface).
layout(local_size_x = 8, local_size_y = 8) in;
#include "pullpush.glsl"

#ifndef OCCLUDE
#define OCCLUDE 1
#endif

layout(binding = 0, rgba32f) uniform image2D u_fine_a;
layout(binding = 1, rgba32f) uniform image2D u_fine_b;
layout(binding = 2, rgba32f) readonly uniform image2D u_coarse_a;
layout(binding = 3, rgba32f) readonly uniform image2D u_coarse_b;
layout(location = 5) uniform float u_fine_scale;  // level-0 pixels per texel of level l

void main() {
  ivec2 f = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(f, imageSize(u_fine_a)))) return;
  Texel self;
  self.a = imageLoad(u_fine_a, f);
  self.b = imageLoad(u_fine_b, f);
#if !OCCLUDE
  if (Valid(self)) return;
#endif
  ivec2 base = PushBase(f);
  ivec2 coarse_size = imageSize(u_coarse_a);
  Texel t[4];
  for (int i = 0; i < 4; ++i) {
    ivec2 c = clamp(base + ivec2(i & 1, i >> 1), ivec2(0), coarse_size - 1);
    t[i].a = imageLoad(u_coarse_a, c);
    t[i].b = imageLoad(u_coarse_b, c);
  }
  Texel r = PushAverage(t, f, u_fine_scale);
  if (!Valid(r)) return;
  if (Valid(self)) {
#if OCCLUDE
    // Replace only when the whole depth interval of the texel lies behind the pushed one.
    if (self.a.z - DepthHalfWidth(self) <= r.a.z + DepthHalfWidth(r)) return;
#endif
  }
  imageStore(u_fine_a, f, r.a);
  imageStore(u_fine_b, f, vec4(r.b.xyz, 1e-3));
}
