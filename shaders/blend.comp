#version 450 core
// Blend pass (Lechelek et al. 2019, sec. 4 "Blending pixels from photographs", eqs. 1-5), for
// the pixels with a valid depth: back-project the surface point P, and blend the photos that
// see it with weight max(0, V . V_k) / (delta_k + 1) (eq. 5), where delta_k (eq. 4) is the
// difference of the distances |C - P| and |C_k - P| in units of the scene scale, or with the
// Unstructured Lumigraph's weights (ULR). A photo sees P when P projects inside it, passes the
// shadow-map test against the photo's own depth map and N_p . V_k > lambda (sec. 4, "Occlusion
// and visibility"). The pixels without depth are listed for blend_background.comp.
// Docs: docs/algorithms/blend.md.
layout(local_size_x = 8, local_size_y = 8) in;

#include "blend_common.glsl"
#include "blend_visibility.glsl"
#include "blend_sampling.glsl"
#include "blend_refine.glsl"
#include "blend_pixel.glsl"

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, u_size))) return;
  float z = texelFetch(u_depth, p, 0).r;
  if (z <= 0.0) {
    uint k = atomicAdd(hole_count, 1u);
    if (k % 64u == 0u) atomicAdd(groups_x, 1u);
    hole_pixels[k] = uint(p.x) | uint(p.y) << 16;
    return;
  }
  vec3 ray = vec3((vec2(p) + 0.5 - u_intrinsics.zw) / u_intrinsics.xy, 1.0);
  vec3 C = u_world_from_cam[3].xyz;
  vec3 ray_world = mat3(u_world_from_cam) * ray;
  Sample s;
  s.background = false;
  s.at_infinity = false;
  PlaceAt(s, C, C + z * ray_world, z);
  vec3 n = texelFetch(u_normal, p, 0).xyz;
  if (dot(n, n) > 1e-8) s.N = normalize(mat3(u_world_from_cam) * n);
  vec4 color, aux;
  BlendSample(s, C, ray_world, color, aux);  // a point that no photo passes stays empty
  imageStore(u_out_color, p, color);
  imageStore(u_out_aux, p, aux);
}
