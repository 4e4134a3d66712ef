#version 450 core
// Viewer depth display, step 1: the range [min, max] of the valid camera depths (z > 0) of the
// depth pass output, by atomics on the float bits (for positive floats the bit patterns order
// like the values). The host clears the range to (+inf bits, 0) before the dispatch.
layout(local_size_x = 16, local_size_y = 16) in;

layout(binding = 0, r32f) readonly uniform image2D u_depth;  // camera z, 0 = invalid
layout(std430, binding = 0) buffer Range { uint range_lo; uint range_hi; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(u_depth)))) return;
  float z = imageLoad(u_depth, p).r;
  if (!(z > 0.0) || isinf(z)) return;
  atomicMin(range_lo, floatBitsToUint(z));
  atomicMax(range_hi, floatBitsToUint(z));
}
