// GLSL ES 3.00 sources of the viewer's passes. Each mirrors a pass of the native renderer
// (docs/architecture.md, "Web viewer"): WebGL2 has no compute shaders, so every pass is a
// fragment pass into a float target. Pixel positions are COLMAP's: in every offscreen target
// row v holds image row v, so gl_FragCoord.xy is the pixel position (centre of the top-left
// pixel at (0.5, 0.5)), as under the native renderer's glClipControl(GL_UPPER_LEFT).

// Splat depth pass, step 1 (Lechelek et al. 2019, sec. 4; shaders/splat.vert, splat.frag,
// camera.glsl): every point a sprite of side 2 r_proj, r_proj = r fy / z, fragments outside the
// projected ellipse discarded, depth constant over the splat (the centre's camera z).
export const SPLAT_VS = `#version 300 es
precision highp float;
layout(location = 0) in vec3 a_q;       // position in the bounds, normalised uint16
layout(location = 1) in vec2 a_oct;     // octahedral normal, normalised int8
layout(location = 2) in float a_r;      // radius / max radius, normalised uint16
uniform vec3 u_lo;
uniform vec3 u_extent;
uniform float u_max_radius;
uniform bool u_has_normals;
uniform mat4 u_cam_from_world;
uniform vec4 u_intrinsics;  // fx, fy, cx, cy of the target
uniform vec2 u_size;
uniform vec2 u_near_far;
uniform float u_max_point_size;
flat out vec3 v_p;
flat out vec3 v_n;
flat out float v_r_px;
flat out vec2 v_center_px;

vec3 OctDecode(vec2 e) {
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return normalize(n);
}

// Normal facing the camera; points without a normal become view-facing discs.
vec3 FacingNormal(vec3 n, vec3 p) {
  if (dot(n, n) < 0.25) return -normalize(p);
  n = normalize(n);
  return dot(n, p) > 0.0 ? -n : n;
}

void main() {
  vec3 world = u_lo + a_q * u_extent;
  vec3 p = (u_cam_from_world * vec4(world, 1.0)).xyz;
  vec3 n = u_has_normals ? OctDecode(a_oct) : vec3(0.0);
  v_p = p;
  v_n = FacingNormal(mat3(u_cam_from_world) * n, p);
  float z = max(p.z, 1e-6);
  v_r_px = a_r * u_max_radius * u_intrinsics.y / z;
  v_center_px = u_intrinsics.xy * p.xy / z + u_intrinsics.zw;
  vec2 ndc = 2.0 * v_center_px / u_size - 1.0;
  float zn = 2.0 * (p.z - u_near_far.x) / (u_near_far.y - u_near_far.x) - 1.0;
  gl_Position = p.z > 0.0 ? vec4(ndc * p.z, zn * p.z, p.z) : vec4(0.0, 0.0, -2.0, 1.0);
  gl_PointSize = clamp(2.0 * v_r_px, 1.0, u_max_point_size);
}`;

export const SPLAT_FS = `#version 300 es
precision highp float;
flat in vec3 v_p;
flat in vec3 v_n;
flat in float v_r_px;
flat in vec2 v_center_px;
layout(location = 0) out vec4 o_depth;   // R32F: camera z
layout(location = 1) out vec4 o_normal;  // camera-space normal, coverage 1
const float kMinAxisRatio = 0.2;

bool InsideEllipse(vec2 d, float r_px, vec3 n) {
  float la = length(n.xy);
  if (la < 1e-4) return dot(d, d) <= r_px * r_px;
  vec2 a = n.xy / la;
  float along = dot(d, a);
  float across = dot(d, vec2(-a.y, a.x));
  float minor = r_px * max(abs(n.z), kMinAxisRatio);
  return (across * across) / (r_px * r_px) + (along * along) / (minor * minor) <= 1.0;
}

void main() {
  vec2 d = gl_FragCoord.xy - v_center_px;
  bool centre_pixel = abs(d.x) <= 0.5 && abs(d.y) <= 0.5;
  vec3 v = normalize(v_p);
  float c = dot(v_n, v);
  if (!centre_pixel && !InsideEllipse(d, v_r_px, vec3((v_n - c * v).xy, c))) discard;
  o_depth = vec4(v_p.z, 0.0, 0.0, 1.0);
  o_normal = vec4(v_n, 1.0);
}`;

// A triangle covering the target.
export const FULLSCREEN_VS = `#version 300 es
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}`;

// Blend pass (LEC19 sec. 4, eqs. 1-5; shaders/blend.comp): back-project the pixel, rank the
// photos that see it by the Unstructured Lumigraph penalty (Buehler et al. 2001), keep the K
// best, one Cauchy reweighting step (outlier rejection), and blend radiance (Debevec's g, hat
// weights per channel) or display values. Pixels without a point take the background: the
// dominant plane within its extent, else the sphere around points and cameras.
export const BLEND_FS = (photoCount) => `#version 300 es
precision highp float;
#define PHOTO_COUNT ${photoCount}
precision highp sampler2DArray;
uniform sampler2D u_depth;
uniform sampler2D u_normal;
uniform highp sampler2DArray u_photos;     // RGBA8, mipmapped
uniform highp sampler2DArray u_photo_depth;  // R32F camera z
// 8 vec4 per photo (uploadPhotoData in renderer.js).
layout(std140) uniform PhotoData { vec4 u_photo_data[PHOTO_COUNT * 8]; };
uniform sampler2D u_response;     // 256 x 1: g(Z) per channel
uniform int u_photo_count;
// The order the photos are visited in: smallest penalty at the view's centre first, so that
// most later photos fail the list's bound before their depth-map test (the list, kept sorted
// with ties to the smaller index, does not depend on the order).
uniform int u_order[PHOTO_COUNT];
uniform mat4 u_world_from_cam;
uniform vec4 u_intrinsics;
uniform float u_lambda;
uniform float u_tolerance;
uniform float u_inv_scene_scale;
uniform float u_delta_weight;
uniform float u_outlier_scale;
uniform bool u_radiance;
uniform vec4 u_sphere;
uniform bool u_has_plane;
uniform vec4 u_plane;
uniform vec3 u_plane_u;
uniform vec3 u_plane_v;
uniform vec4 u_plane_extent;
layout(location = 0) out vec4 o_color;

#define KEEP 5
const float kHalfPi = 1.5707963;
const float kFeather = 0.05;

vec4 Data(int i, int k) { return u_photo_data[i * 8 + k]; }

float SphereDepth(vec3 C, vec3 d) {
  vec3 o = C - u_sphere.xyz;
  float a = dot(d, d);
  float b = dot(o, d);
  float c = dot(o, o) - u_sphere.w * u_sphere.w;
  float disc = b * b - a * c;
  if (disc < 0.0) return 0.0;
  return max((-b + sqrt(disc)) / a, 0.0);
}

float SurfaceDepth(vec3 C, vec3 d) {
  float t = SphereDepth(C, d);
  if (u_has_plane) {
    float along = dot(u_plane.xyz, d);
    if (along < 0.0) {
      float t_plane = -(dot(u_plane.xyz, C) + u_plane.w) / along;
      vec3 X = C + t_plane * d;
      vec2 uv = vec2(dot(u_plane_u, X), dot(u_plane_v, X));
      bool inside = all(greaterThanEqual(uv, u_plane_extent.xz)) &&
                    all(lessThanEqual(uv, u_plane_extent.yw));
      if (t_plane > 0.0 && t_plane < t && inside) t = t_plane;
    }
  }
  return t;
}

// Photo i's depth-map test on the 2x2 texels about px (blend.comp VisibleIn).
bool VisibleIn(int i, bool background, vec2 px, float z_k) {
  vec4 dmap = Data(i, 7);
  ivec2 d0 = ivec2(floor(px * dmap.xy - 0.5));
  ivec2 dmax = ivec2(dmap.zw) - 1;
  int agree = 0;
  bool any_empty = false;
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      ivec2 t = clamp(d0 + ivec2(dx, dy), ivec2(0), dmax);
      float dk = texelFetch(u_photo_depth, ivec3(t, i), 0).r;
      if (dk <= 0.0) any_empty = true;
      if (dk > 0.0 && abs(z_k - dk) <= u_tolerance * dk) ++agree;
    }
  }
  if (background) return any_empty || agree > 0;
  return agree > 0;
}

vec3 ResponseLog(vec3 c) {
  vec3 z = clamp(c * 255.0, 0.0, 255.0);
  vec3 g;
  for (int ch = 0; ch < 3; ++ch) {
    int lo = int(floor(z[ch]));
    int hi = min(lo + 1, 255);
    float f = z[ch] - float(lo);
    g[ch] = mix(texelFetch(u_response, ivec2(lo, 0), 0)[ch], texelFetch(u_response, ivec2(hi, 0), 0)[ch], f);
  }
  return g;
}

vec3 Blended(int i, vec3 c, out vec3 hat) {
  hat = vec3(1.0);
  if (u_radiance) {
    vec3 z = clamp(c * 255.0, 0.0, 255.0);
    hat = max(min(z, 255.0 - z), vec3(1e-3));
    c = exp(ResponseLog(c)) * Data(i, 4).w;
  }
  return c;
}

bool Beats(float key, int i, float key2, int i2) { return key > key2 || (key == key2 && i < i2); }

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float z = texelFetch(u_depth, p, 0).r;
  vec3 ray = vec3((gl_FragCoord.xy - u_intrinsics.zw) / u_intrinsics.xy, 1.0);
  vec3 C = u_world_from_cam[3].xyz;
  vec3 ray_world = mat3(u_world_from_cam) * ray;
  bool background = !(z > 0.0);
  if (background) z = SurfaceDepth(C, ray_world);
  o_color = vec4(0.0);
  if (!(z > 0.0)) return;
  vec3 P = C + z * ray_world;
  float dist_c = length(C - P);
  vec3 V = (C - P) / dist_c;
  vec3 N = V;
  if (!background) {
    vec3 n = texelFetch(u_normal, p, 0).xyz;
    if (dot(n, n) > 1e-8) N = normalize(mat3(u_world_from_cam) * n);
  }
  float best_key[KEEP];
  float best_f[KEEP];
  int best_i[KEEP];
  vec3 best_uvl[KEEP];
  for (int j = 0; j < KEEP; ++j) {
    best_key[j] = -3.0e38;
    best_f[j] = 0.0;
    best_i[j] = 0x7fffffff;
    best_uvl[j] = vec3(0.0);
  }
  int n_best = 0;
  for (int a = 0; a < u_photo_count; ++a) {
    int i = u_order[a];
    vec4 size = Data(i, 5);
    if (size.w <= 0.0) continue;  // not loaded yet
    vec4 r0 = Data(i, 0), r1 = Data(i, 1), r2 = Data(i, 2);
    vec3 pk = vec3(dot(r0.xyz, P) + r0.w, dot(r1.xyz, P) + r1.w, dot(r2.xyz, P) + r2.w);
    if (pk.z <= 0.0) continue;
    vec4 intr = Data(i, 3);
    vec2 px = intr.xy * pk.xy / pk.z + intr.zw;
    if (any(lessThan(px, vec2(0.0))) || any(greaterThanEqual(px, size.xy))) continue;
    vec3 ck = Data(i, 4).xyz;
    vec3 vk = ck - P;
    float dist_k = length(vk);
    float delta = abs(dist_c - dist_k) * u_inv_scene_scale;
    vk /= dist_k;
    if (dot(N, vk) <= u_lambda) continue;
    float cos_k = max(0.0, dot(V, vk));
    float footprint = z / u_intrinsics.x * intr.x / pk.z * size.z;
    float feather = 1.0;
    if (background) {
      vec2 border = min(px, size.xy - px);
      feather = max(clamp(min(border.x, border.y) / (kFeather * max(size.x, size.y)), 0.0, 1.0), 1e-3);
    }
    float penalty = acos(min(cos_k, 1.0)) + u_delta_weight * delta;
    float key = -penalty;
    if (key < best_key[KEEP - 1]) continue;
    if (!VisibleIn(i, background, px, pk.z)) continue;
    vec4 tex = Data(i, 6);
    vec3 uvl = vec3(clamp(px * tex.xy, vec2(0.0), tex.zw), log2(max(footprint, 1e-6)));
    if (!Beats(key, i, best_key[KEEP - 1], best_i[KEEP - 1])) continue;
    int id = i;
    for (int j = 0; j < KEEP; ++j) {
      if (Beats(key, id, best_key[j], best_i[j])) {
        float t_key = best_key[j], t_f = best_f[j];
        int t_i = best_i[j];
        vec3 t_uvl = best_uvl[j];
        best_key[j] = key;
        best_f[j] = feather;
        best_i[j] = id;
        best_uvl[j] = uvl;
        key = t_key;
        feather = t_f;
        id = t_i;
        uvl = t_uvl;
      }
    }
    n_best = min(n_best + 1, KEEP);
  }
  if (n_best == 0) return;
  float best_w[KEEP];
  int k = KEEP - 1;
  float t = max(n_best > k ? -best_key[KEEP - 1] : kHalfPi, 1e-4);
  n_best = min(n_best, k);
  for (int j = 0; j < KEEP; ++j) {
    float pen = -best_key[j];
    best_w[j] = j < n_best ? best_f[j] * max(0.0, 1.0 - pen / t) / max(pen, 1e-4) : 0.0;
  }
  if (best_w[0] <= 0.0) best_w[0] = 1.0;
  vec3 stored[KEEP];
  for (int j = 0; j < KEEP; ++j) {
    bool used = j < n_best && best_w[j] > 0.0;
    stored[j] = used ? textureLod(u_photos, vec3(best_uvl[j].xy, float(best_i[j])), best_uvl[j].z).rgb
                     : vec3(0.0);
    if (!used) best_w[j] = 0.0;
  }
  if (u_outlier_scale > 0.0 && u_radiance) {
    vec3 mean = vec3(0.0);
    float mean_w = 0.0;
    for (int j = 0; j < KEEP; ++j) {
      mean += best_w[j] * stored[j];
      mean_w += best_w[j];
    }
    mean /= max(mean_w, 1e-30);
    for (int j = 0; j < KEEP; ++j) {
      vec3 r = (stored[j] - mean) / u_outlier_scale;
      best_w[j] /= 1.0 + dot(r, r);
    }
  }
  vec3 sum = vec3(0.0);
  vec3 wsum = vec3(0.0);
  float count = 0.0;
  for (int j = 0; j < KEEP; ++j) {
    if (best_w[j] <= 0.0) continue;
    vec3 hat;
    vec3 c = Blended(best_i[j], stored[j], hat);
    sum += best_w[j] * hat * c;
    wsum += best_w[j] * hat;
    count += 1.0;
  }
  if (count > 0.0 && all(greaterThan(wsum, vec3(0.0)))) o_color = vec4(sum / wsum, 1.0);
}`;

// Log-average luminance, step 1 (tonemap_reduce.comp): each texel sums (ln(eps + L), 1) over
// a 16 x 16 block of the valid radiance pixels.
export const REDUCE_FS = `#version 300 es
precision highp float;
uniform sampler2D u_src;
uniform bool u_first;  // the radiance (else partial sums)
uniform float u_epsilon;
uniform int u_block;
layout(location = 0) out vec4 o_sum;
void main() {
  ivec2 size = textureSize(u_src, 0);
  ivec2 base = ivec2(gl_FragCoord.xy) * u_block;
  vec2 s = vec2(0.0);
  for (int y = 0; y < 64; ++y) {
    if (y >= u_block) break;
    for (int x = 0; x < 64; ++x) {
      if (x >= u_block) break;
      ivec2 q = base + ivec2(x, y);
      if (q.x >= size.x || q.y >= size.y) continue;
      vec4 c = texelFetch(u_src, q, 0);
      if (u_first) {
        if (c.a > 0.0) s += vec2(log(u_epsilon + max(0.0, dot(c.rgb, vec3(0.2126, 0.7152, 0.0722)))), 1.0);
      } else {
        s += c.xy;
      }
    }
  }
  o_sum = vec4(s, 0.0, 1.0);
}`;

// Reinhard 2002 global operator (eqs. 8-12; tonemap.comp): L_s = k / L_a L,
// display = (exposure C L_s / (1 + L_s) / L)^(1 / gamma); display values are scaled by the
// exposure alone.
export const TONEMAP_FS = `#version 300 es
precision highp float;
uniform sampler2D u_hdr;
uniform sampler2D u_sum;  // 1 x 1: (sum of ln(eps + L), count)
uniform float u_key;
uniform float u_fixed_la;  // > 0: this L_a
uniform float u_exposure;  // 2^EV
uniform float u_inv_gamma;
uniform bool u_reinhard;
uniform bool u_flip;       // drawing to the canvas (row 0 at the bottom)
uniform float u_height;     // of the output
uniform float u_scale;      // render pixels per output pixel (reduced frames)
layout(location = 0) out vec4 o_color;
void main() {
  vec2 q = gl_FragCoord.xy;
  if (u_flip) q.y = u_height - q.y;
  ivec2 p = ivec2(q * u_scale);
  vec4 c = texelFetch(u_hdr, p, 0);
  if (!(c.a > 0.0)) {
    o_color = vec4(0.0);
    return;
  }
  vec3 rgb = max(c.rgb, vec3(0.0));
  vec3 mapped;
  if (u_reinhard) {
    vec2 s = texelFetch(u_sum, ivec2(0), 0).xy;
    float l_a = u_fixed_la > 0.0 ? u_fixed_la : exp(s.x / max(s.y, 1.0));
    float l = dot(c.rgb, vec3(0.2126, 0.7152, 0.0722));
    if (!(l > 0.0) || isinf(l) || isnan(l)) {
      mapped = vec3(0.0);
    } else {
      float l_s = u_key / l_a * l;
      mapped = u_exposure * (l_s / (1.0 + l_s)) / l * rgb;
    }
  } else {
    mapped = u_exposure * rgb;
  }
  o_color = vec4(min(pow(max(mapped, vec3(0.0)), vec3(u_inv_gamma)), vec3(1.0)), 1.0);
}`;
