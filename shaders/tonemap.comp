#version 450 core
// Reinhard et al. 2002 global operator (LEC19 eqs. 10-12): L_s = k / L_a * L (eq. 10),
// L_d = L_s / (1 + L_s) (eq. 11), display C_d = (exposure * C * L_d / L)^(1/gamma) (eq. 12),
// clamped to [0, 1]. Invalid pixels (alpha 0) and L <= 0 give 0 with alpha 0 / 1.
// Without u_reinhard: C_d = clamp(exposure * C)^(1/gamma). With u_camera: the camera's response
// instead, C_d = z / 255 with g(z) = ln(exposure * C) per channel (hdr/re_expose.h, the same
// interpolation and rounding), no gamma (the response holds the display encoding).
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap.glsl"

layout(binding = 0, rgba32f) readonly uniform image2D u_hdr;
layout(binding = 1) writeonly uniform image2D u_display;  // RGBA8 (or RGBA16F/32F for tests)
uniform float u_scale;  // k / L_a
uniform float u_exposure;
uniform float u_inv_gamma;
uniform bool u_reinhard;
uniform bool u_camera;
layout(binding = 2) uniform sampler2D u_response;  // 256 x 1: g(Z) per channel (RGB)

// The 8-bit code whose g matches ln(x), interpolated between codes and rounded; 0 for x <= 0.
float CameraCode(float x, int c) {
  if (!(x > 0.0) || isinf(x)) return x > 0.0 ? 255.0 : 0.0;
  float t = log(x);
  if (t < texelFetch(u_response, ivec2(0, 0), 0)[c]) return 0.0;
  if (t >= texelFetch(u_response, ivec2(255, 0), 0)[c]) return 255.0;
  int lo = 0, hi = 255;  // g(lo) <= t < g(hi)
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (texelFetch(u_response, ivec2(mid, 0), 0)[c] <= t) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  float g0 = texelFetch(u_response, ivec2(lo, 0), 0)[c];
  float g1 = texelFetch(u_response, ivec2(hi, 0), 0)[c];
  return floor(float(lo) + (g1 > g0 ? (t - g0) / (g1 - g0) : 0.0) + 0.5);
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(u_hdr)))) return;
  vec4 c = imageLoad(u_hdr, p);
  if (!(c.a > 0.0)) {
    imageStore(u_display, p, vec4(0.0));
    return;
  }
  vec3 rgb = max(c.rgb, vec3(0.0));
  if (u_camera) {
    vec3 code = vec3(CameraCode(u_exposure * rgb.r, 0), CameraCode(u_exposure * rgb.g, 1),
                     CameraCode(u_exposure * rgb.b, 2));
    imageStore(u_display, p, vec4(code / 255.0, 1.0));
    return;
  }
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
