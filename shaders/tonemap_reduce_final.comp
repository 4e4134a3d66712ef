#version 450 core
// Log-average luminance (LEC19 eq. 9, standard form), step 2 of the GPU reduction: one
// workgroup sums the per-tile (sum of log(eps + L), count) pairs into partials[0].
layout(local_size_x = 256) in;

layout(std430, binding = 0) buffer Partials { vec2 partials[]; };
uniform int u_count;  // number of partial sums

shared vec2 s_sum[256];

void main() {
  uint i = gl_LocalInvocationIndex;
  vec2 v = vec2(0.0);
  for (int k = int(i); k < u_count; k += 256) v += partials[k];
  s_sum[i] = v;
  barrier();
  for (uint stride = 128u; stride > 0u; stride >>= 1u) {
    if (i < stride) s_sum[i] += s_sum[i + stride];
    barrier();
  }
  if (i == 0u) partials[0] = s_sum[0];
}
