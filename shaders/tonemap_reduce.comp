#version 450 core
// Log-average luminance for Reinhard et al. 2002 (LEC19 eqs. 8-9), step 1 of a GPU reduction:
// each 16x16 workgroup sums log(eps + L) and the valid-pixel count of its tile. The paper's
// eq. 9 puts 1/N outside the exp by mistake; the standard L_a = exp(sum / N) is finished on
// the host from the partial sums (tonemap_pass.cc), after tonemap_reduce_final.comp.
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap.glsl"

layout(binding = 0, rgba32f) readonly uniform image2D u_hdr;  // rgb linear, a > 0 = valid
layout(std430, binding = 0) writeonly buffer Partials { vec2 partials[]; };
uniform float u_epsilon;

shared vec2 s_sum[256];

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(u_hdr);
  vec2 v = vec2(0.0);
  if (all(lessThan(p, size))) {
    vec4 c = imageLoad(u_hdr, p);
    if (c.a > 0.0) v = vec2(log(u_epsilon + max(0.0, Luminance(c.rgb))), 1.0);
  }
  uint i = gl_LocalInvocationIndex;
  s_sum[i] = v;
  barrier();
  for (uint stride = 128u; stride > 0u; stride >>= 1u) {
    if (i < stride) s_sum[i] += s_sum[i + stride];
    barrier();
  }
  if (i == 0u) {
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    partials[group] = s_sum[0];
  }
}
