#version 450 core
// Pull (Marroquim et al. 2007): level l+1 texel = depth-grouped average of its valid 2x2
// children in level l.
layout(local_size_x = 8, local_size_y = 8) in;
#include "pullpush.glsl"

layout(binding = 0, rgba32f) readonly uniform image2D u_fine_a;
layout(binding = 1, rgba32f) readonly uniform image2D u_fine_b;
layout(binding = 2, rgba32f) writeonly uniform image2D u_coarse_a;
layout(binding = 3, rgba32f) writeonly uniform image2D u_coarse_b;

void main() {
  ivec2 c = ivec2(gl_GlobalInvocationID.xy);
  ivec2 coarse_size = imageSize(u_coarse_a);
  if (any(greaterThanEqual(c, coarse_size))) return;
  ivec2 fine_size = imageSize(u_fine_a);
  Texel t[4];
  float wt[4];
  for (int i = 0; i < 4; ++i) {
    ivec2 f = 2 * c + ivec2(i & 1, i >> 1);
    bool inside = all(lessThan(f, fine_size));
    t[i].a = inside ? imageLoad(u_fine_a, f) : vec4(0.0);
    t[i].b = inside ? imageLoad(u_fine_b, f) : vec4(0.0);
    wt[i] = inside && Valid(t[i]) ? 1.0 : 0.0;
  }
  Texel r = Average(t, wt);
  imageStore(u_coarse_a, c, r.a);
  imageStore(u_coarse_b, c, r.b);
}
