#version 450 core
// Reinhard et al. 2002 global operator (LEC19 eqs. 10-12): L_s = k / L_a * L (eq. 10),
// L_d = L_s / (1 + L_s) (eq. 11), display C_d = (exposure * C * L_d / L)^(1/gamma) (eq. 12),
// clamped to [0, 1]. Invalid pixels (alpha 0) and L <= 0 give 0 with alpha 0 / 1.
// Without u_reinhard: C_d = clamp(exposure * C)^(1/gamma).
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap.glsl"

layout(binding = 0, rgba32f) readonly uniform image2D u_hdr;
layout(binding = 1) writeonly uniform image2D u_display;  // RGBA8 (or RGBA16F/32F for tests)
uniform float u_scale;  // k / L_a
uniform float u_exposure;
uniform float u_inv_gamma;
uniform bool u_reinhard;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(u_hdr)))) return;
  vec4 c = imageLoad(u_hdr, p);
  if (!(c.a > 0.0)) {
    imageStore(u_display, p, vec4(0.0));
    return;
  }
  vec3 rgb = max(c.rgb, vec3(0.0));
  vec3 mapped;
  if (u_reinhard) {
    float l = Luminance(c.rgb);
    if (!(l > 0.0) || isinf(l) || isnan(l)) {
      mapped = vec3(0.0);
    } else {
      float l_s = u_scale * l;
      float ratio = u_exposure * (l_s / (1.0 + l_s)) / l;
      mapped = ratio * rgb;
    }
  } else {
    mapped = u_exposure * rgb;
  }
  mapped = min(pow(max(mapped, vec3(0.0)), vec3(u_inv_gamma)), vec3(1.0));
  imageStore(u_display, p, vec4(mapped, 1.0));
}
