#version 450 core
// Blend pass (Lechelek et al. 2019, sec. 4 "Blending pixels from photographs", eqs. 1-5): for
// each pixel with a valid depth, back-project the surface point P, and blend the photos that
// see it with weight max(0, V . V_k) / (delta_k + 1) (eq. 5), where delta_k (eq. 4) is the
// difference of the distances |C - P| and |C_k - P| in units of the scene scale. A photo sees
// P when P projects inside it, passes the shadow-map test against the photo's own depth map
// and N_p . V_k > lambda (sec. 4, "Occlusion and visibility"). Docs: docs/algorithms.md.
layout(local_size_x = 8, local_size_y = 8) in;

// One per scene photo (std430, matches PhotoGpu in blend_pass.cc).
struct PhotoGpu {
  mat4 cam_from_world;
  vec4 intrinsics;  // fx, fy, cx, cy in pixels of the photo's camera
  vec4 center;      // xyz: centre in world, w: 1 / relative exposure
  vec4 size;        // xy: camera size in pixels, z: photo-texture texels per camera pixel
  vec4 tex;         // xy: texture coordinate per camera pixel, zw: largest texture coordinate
  vec4 dmap;        // xy: depth-map texels per camera pixel, zw: depth-map layer size
};
layout(std430, binding = 0) readonly buffer Photos { PhotoGpu photos[]; };
layout(std430, binding = 1) readonly buffer Active { int active_photos[]; };

layout(binding = 0) uniform sampler2D u_depth;           // new view: camera z, 0 = none
layout(binding = 1) uniform sampler2D u_normal;          // new view: camera-space normal
layout(binding = 2) uniform sampler2DArray u_photos;     // layer i = photo i, mipmapped
layout(binding = 3) uniform sampler2DArray u_photo_depth; // layer i = photo i's camera z
layout(binding = 4) uniform sampler2D u_response;        // 256 x 1: g(Z) per channel (RGB)

layout(binding = 0, rgba32f) writeonly uniform image2D u_out_color;
layout(binding = 1, rgba32f) writeonly uniform image2D u_out_aux;

layout(location = 0) uniform mat4 u_world_from_cam;
layout(location = 1) uniform vec4 u_intrinsics;  // new view, pixels of the target
layout(location = 2) uniform ivec2 u_size;
layout(location = 3) uniform int u_active_count;
layout(location = 4) uniform int u_k_best;  // 0 = all photos
layout(location = 5) uniform float u_lambda;
layout(location = 6) uniform float u_tolerance;
layout(location = 7) uniform float u_inv_scene_scale;
layout(location = 8) uniform int u_debug_photo;
layout(location = 9) uniform int u_encoding;  // 0 display, 1 radiance
layout(location = 10) uniform int u_nearest;  // 1: projective texturing, weight 1
layout(location = 11) uniform int u_weights;  // 0 paper eq. 5, 1 Unstructured Lumigraph

#ifndef MAX_K
#define MAX_K 32
#endif

const float kHalfPi = 1.5707963;

// Geometric weight of photo i for the point P (0 when photo i does not see it); uvl receives
// the texture coordinate and the level of detail of P in the photo, penalty the Unstructured
// Lumigraph penalty angle(V, V_k) (radians) + delta_k.
float PhotoWeight(int i, vec3 P, vec3 N, vec3 V, float dist_c, float z_new, out vec3 uvl,
                  out float penalty) {
  uvl = vec3(0.0);
  penalty = 0.0;
  vec3 pk = (photos[i].cam_from_world * vec4(P, 1.0)).xyz;
  if (pk.z <= 0.0) return 0.0;
  vec4 intr = photos[i].intrinsics;
  vec2 px = intr.xy * pk.xy / pk.z + intr.zw;
  vec2 size = photos[i].size.xy;
  if (any(lessThan(px, vec2(0.0))) || any(greaterThanEqual(px, size))) return 0.0;
  // Shadow-map test: consistent with one of the 2x2 depth-map texels around the projection
  // (a single texel rejects half the pixels along the photo's silhouettes).
  vec4 dmap = photos[i].dmap;
  ivec2 d0 = ivec2(floor(px * dmap.xy - 0.5));
  ivec2 dmax = ivec2(dmap.zw) - 1;
  bool visible = false;
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      ivec2 t = clamp(d0 + ivec2(dx, dy), ivec2(0), dmax);
      float dk = texelFetch(u_photo_depth, ivec3(t, i), 0).r;
      if (dk > 0.0 && abs(pk.z - dk) <= u_tolerance * dk) visible = true;
    }
  }
  if (!visible) return 0.0;
  vec3 vk = photos[i].center.xyz - P;
  float dist_k = length(vk);
  vk /= dist_k;
  if (dot(N, vk) <= u_lambda) return 0.0;  // grazing or back-facing (paper: N_p . V_k > lambda)
  float w = 1.0;
  if (u_nearest == 0) {
    float cos_k = max(0.0, dot(V, vk));                      // eq. 2
    float delta = abs(dist_c - dist_k) * u_inv_scene_scale;  // eq. 4, scene-scale units
    w = cos_k / (delta + 1.0);                               // eq. 5
    penalty = acos(min(cos_k, 1.0)) + delta;
  }
  // Level of detail: a target pixel covers z_new / f_new world units at P, which photo i sees
  // over that times f_i / z_i camera pixels, times its texels per camera pixel.
  float footprint = z_new / u_intrinsics.x * intr.x / pk.z * photos[i].size.z;
  vec4 tex = photos[i].tex;
  uvl = vec3(clamp(px * tex.xy, vec2(0.0), tex.zw), log2(max(footprint, 1e-6)));
  return w;
}

// The blended quantity of photo i at uvl; hat receives Debevec's hat weight (radiance
// encoding; 1 otherwise).
vec3 PhotoValue(int i, vec3 uvl, out vec3 hat) {
  vec3 c = textureLod(u_photos, vec3(uvl.xy, float(i)), uvl.z).rgb;
  hat = vec3(1.0);
  if (u_encoding == 1) {
    vec3 z = clamp(c * 255.0, 0.0, 255.0);
    // min(Z, 255 - Z) per channel, floored so that a value saturated in every photo keeps its
    // (clipped) radiance instead of going invalid.
    hat = max(min(z, 255.0 - z), vec3(1e-3));
    vec3 t = (z + 0.5) / 256.0;
    vec3 g = vec3(texture(u_response, vec2(t.r, 0.5)).r, texture(u_response, vec2(t.g, 0.5)).g,
                  texture(u_response, vec2(t.b, 0.5)).b);
    c = exp(g) * photos[i].center.w;
  }
  return c;
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, u_size))) return;
  vec4 color = vec4(0.0);
  vec4 aux = vec4(0.0);
  float z = texelFetch(u_depth, p, 0).r;
  if (z > 0.0) {
    vec2 px = vec2(p) + 0.5;
    vec3 pc = vec3((px - u_intrinsics.zw) / u_intrinsics.xy, 1.0) * z;
    vec3 P = (u_world_from_cam * vec4(pc, 1.0)).xyz;
    vec3 C = u_world_from_cam[3].xyz;
    float dist_c = length(C - P);
    vec3 V = (C - P) / dist_c;
    vec3 n = texelFetch(u_normal, p, 0).xyz;
    vec3 N = dot(n, n) > 1e-8 ? normalize(mat3(u_world_from_cam) * n) : V;
    vec3 sum = vec3(0.0);
    vec3 wsum = vec3(0.0);
    float geo_sum = 0.0;
    float debug_w = 0.0;
    float count = 0.0;
    // Candidates: every photo (paper, u_k_best = 0), or the K best by weight, or the K + 1
    // smallest penalties (Unstructured Lumigraph), kept sorted by insertion.
    bool ulr = u_weights == 1 && u_nearest == 0;
    int k = u_k_best <= 0 ? MAX_K : min(u_k_best, MAX_K);
    int keep = ulr ? k + 1 : k;
    float best_key[MAX_K + 1];
    float best_w[MAX_K + 1];
    int best_i[MAX_K + 1];
    vec3 best_uvl[MAX_K + 1];
    int n_best = 0;
    for (int a = 0; a < u_active_count; ++a) {
      int i = active_photos[a];
      vec3 uvl;
      float penalty;
      float w = PhotoWeight(i, P, N, V, dist_c, z, uvl, penalty);
      if (w <= 0.0) continue;
      if (u_k_best <= 0 && !ulr) {  // all photos: accumulate directly
        vec3 hat;
        vec3 c = PhotoValue(i, uvl, hat);
        sum += w * hat * c;
        wsum += w * hat;
        geo_sum += w;
        count += 1.0;
        if (i == u_debug_photo) debug_w = w;
        continue;
      }
      float key = ulr ? -penalty : w;  // larger is better
      if (n_best == keep && key <= best_key[keep - 1]) continue;
      int j = min(n_best, keep - 1);
      while (j > 0 && best_key[j - 1] < key) {
        best_key[j] = best_key[j - 1];
        best_w[j] = best_w[j - 1];
        best_i[j] = best_i[j - 1];
        best_uvl[j] = best_uvl[j - 1];
        --j;
      }
      best_key[j] = key;
      best_w[j] = w;
      best_i[j] = i;
      best_uvl[j] = uvl;
      n_best = min(n_best + 1, keep);
    }
    if (ulr && n_best > 0) {
      // Threshold: the (K+1)-th penalty, or the paper's cosine horizon when fewer photos see P.
      // (floored: K + 1 photos from exactly the view's direction would give 0 / 0).
      float t = max(n_best > k ? -best_key[k] : kHalfPi, 1e-4);
      n_best = min(n_best, k);
      for (int j = 0; j < n_best; ++j) {
        float p = -best_key[j];
        best_w[j] = max(0.0, 1.0 - p / t) / max(p, 1e-4);
      }
      if (best_w[0] <= 0.0) best_w[0] = 1.0;  // every penalty beyond the horizon: the best
    }
    for (int j = 0; j < n_best; ++j) {
      if (best_w[j] <= 0.0) continue;
      vec3 hat;
      vec3 c = PhotoValue(best_i[j], best_uvl[j], hat);
      sum += best_w[j] * hat * c;
      wsum += best_w[j] * hat;
      geo_sum += best_w[j];
      count += 1.0;
      if (best_i[j] == u_debug_photo) debug_w = best_w[j];
    }
    if (count > 0.0 && all(greaterThan(wsum, vec3(0.0)))) {
      color = vec4(sum / wsum, 1.0);
      aux = vec4(count, debug_w / geo_sum, 0.0, 0.0);
    } else {
      aux = vec4(0.0);
    }
  }
  imageStore(u_out_color, p, color);
  imageStore(u_out_aux, p, aux);
}
