#version 450 core
// Blend pass (Lechelek et al. 2019, sec. 4 "Blending pixels from photographs", eqs. 1-5): for
// each pixel with a valid depth, back-project the surface point P, and blend the photos that
// see it with weight max(0, V . V_k) / (delta_k + 1) (eq. 5), where delta_k (eq. 4) is the
// difference of the distances |C - P| and |C_k - P| in units of the scene scale. A photo sees
// P when P projects inside it, passes the shadow-map test against the photo's own depth map
// and N_p . V_k > lambda (sec. 4, "Occlusion and visibility"). Beyond the paper, pixels
// without depth can show a background (BACKGROUND): the scene's dominant plane, a sphere
// around the scene or a surface at infinity, seen by the photos whose depth maps hold no point
// there either, or the surface that the photos' depth maps hold along the pixel's ray
// (HoleDepth), or the depth along it where the photos agree (SweepDepth).
// Docs: docs/algorithms/blend.md.
layout(local_size_x = 8, local_size_y = 8) in;

// One per scene photo (std430, matches PhotoGpu in blend_pass.cc).
struct PhotoGpu {
  mat4 cam_from_world;
  vec4 intrinsics;  // fx, fy, cx, cy in pixels of the photo's camera
  vec4 center;      // xyz: centre in world, w: 1 / relative exposure
  vec4 size;        // xy: camera size in pixels, z: photo-texture texels per camera pixel,
                    // w: level of detail added in the coarse copy (CACHED)
  vec4 tex;         // xy: texture coordinate per camera pixel, zw: largest texture coordinate
  vec4 dmap;        // xy: depth-map texels per camera pixel, zw: depth-map layer size
  vec4 coarse;      // CACHED: xy coarse-copy coordinate per u_photos one, zw its largest
};
layout(std430, binding = 0) readonly buffer Photos { PhotoGpu photos[]; };
layout(std430, binding = 1) readonly buffer Active { int active_photos[]; };
// CACHED: photo i's slot, t << 24 | layer (layer of u_photos for t = 0, of u_tier1 / u_tier2
// for t = 1 / 2), -1 when only its coarse copy is resident.
layout(std430, binding = 2) readonly buffer SlotMap { int slot_of[]; };
// CACHED_DEPTH: photo i's layer in u_photo_depth, -1 when its depth map is not resident.
layout(std430, binding = 3) readonly buffer DepthSlotMap { int depth_slot_of[]; };

layout(binding = 0) uniform sampler2D u_depth;           // new view: camera z, 0 = none
layout(binding = 1) uniform sampler2D u_normal;          // new view: camera-space normal
layout(binding = 2) uniform sampler2DArray u_photos;     // layer i = photo i, mipmapped
                                                          // (CACHED: layer slot_of[i])
layout(binding = 3) uniform sampler2DArray u_photo_depth; // layer i = photo i's camera z
                                                          // (CACHED_DEPTH: depth_slot_of[i])
layout(binding = 4) uniform sampler2D u_response;        // 256 x 1: g(Z) per channel (RGB)
layout(binding = 5) uniform sampler2DArray u_coarse;     // CACHED: layer i = photo i, coarse
layout(binding = 6) uniform sampler2DArray u_tier1;      // CACHED: slots of mip levels 1...
layout(binding = 7) uniform sampler2DArray u_tier2;      // CACHED: slots of mip levels 2...

layout(binding = 0, rgba32f) writeonly uniform image2D u_out_color;
layout(binding = 1, rgba32f) writeonly uniform image2D u_out_aux;

layout(location = 0) uniform mat4 u_world_from_cam;
layout(location = 1) uniform vec4 u_intrinsics;  // new view, pixels of the target
layout(location = 2) uniform ivec2 u_size;
layout(location = 3) uniform int u_active_count;
layout(location = 5) uniform float u_lambda;
layout(location = 6) uniform float u_tolerance;
layout(location = 7) uniform float u_inv_scene_scale;
layout(location = 8) uniform int u_debug_photo;
layout(location = 13) uniform vec4 u_sphere;  // background sphere: centre (world), radius
// Background plane (BACKGROUND 3, world): n . X + offset = 0 with the cameras on the side n
// points to; its in-plane axes u, v; its extent (u min, u max, v min, v max).
layout(location = 21) uniform vec4 u_plane;
layout(location = 22) uniform vec3 u_plane_u;
layout(location = 23) uniform vec3 u_plane_v;
layout(location = 24) uniform vec4 u_plane_extent;

// Modes, fixed per program (BlendPass::ProgramFor): llvmpipe pays for both sides of a branch on
// a uniform, so they are constants here (docs/decisions/0013).
#ifndef ENCODING
#define ENCODING 0  // 0 display, 1 radiance
#endif
#ifndef NEAREST
#define NEAREST 0  // 1: projective texturing, weight 1
#endif
#ifndef ULR
#define ULR 1  // 0 paper eq. 5, 1 Unstructured Lumigraph (ignored with NEAREST)
#endif
#ifndef SUM_ALL
#define SUM_ALL 0  // 1: paper eq. 5 summed over every photo (no list of best photos)
#endif
// Pixels without depth: 0 left empty, 1 at infinity, 2 on the sphere u_sphere, 3 on the plane
// u_plane within its extent, else on the sphere (render::Background).
#ifndef BACKGROUND
#define BACKGROUND 3
#endif
// 1: a point's visibility in a photo is the share of the 2x2 depth texels about its projection
// that agree with it (soft at the photo's depth discontinuities); 0: visible when one agrees.
#ifndef SOFT_VISIBILITY
#define SOFT_VISIBILITY 0
#endif
// 1: the photos are in a cache (render/photo_cache.h): u_photos holds the resident ones in
// slots, u_coarse a coarse copy of every photo; 0: u_photos holds every photo.
#ifndef CACHED
#define CACHED 0
#endif
// CACHED: the slot sizes in use, 1 (full size) to 3 (also 1/2 and 1/4 of it).
#ifndef TIERS
#define TIERS 1
#endif
#if CACHED == 1
// Per photo, the finest mip level sampled (atomicMin; the cache clears it before the frame
// and places photos from it: PhotoCache::Request).
layout(std430, binding = 4) coherent buffer Feedback { int sampled_level[]; };
#endif
// 1: u_photo_depth holds the depth maps of the cache's depth slots (depth_slot_of).
#ifndef CACHED_DEPTH
#define CACHED_DEPTH 0
#endif
// 1: each photo is sampled with a Catmull-Rom bicubic filter (9 bilinear taps at level 0) where
// its level of detail is at most kCubicMaxLod; 0: trilinear.
#ifndef CUBIC
#define CUBIC 0
#endif
#if CUBIC == 1
// The full-size photo array's size in texels (with a cache, its slots of every size share its
// texture coordinates, and a cache may have no full-size slot to ask textureSize of).
layout(location = 19) uniform vec2 u_photo_texels;
#else
const vec2 u_photo_texels = vec2(1.0);
#endif
// 1: one reweighting step of the per-pixel list: each photo's weight is divided by
// 1 + (|c_k - m| / u_outlier_scale)^2, m the weighted mean of the photos' stored values.
#ifndef OUTLIER
#define OUTLIER 0
#endif
#if OUTLIER == 1
layout(location = 18) uniform float u_outlier_scale;
#endif
// 1: photo-consistent depth (RefineDepth): each point moves along the view's ray, within
// +-u_refine of its view depth, to where its ranked photos agree best.
#ifndef REFINE
#define REFINE 0
#endif
#if REFINE == 1
layout(location = 20) uniform float u_refine;
#endif
#ifdef FILTERED
// Filtered blending (Eisemann et al. 2007, sec. 4): relative depth uncertainty along the view's
// ray; each blended photo is low-passed along its line of disparity. A program of its own (the
// unused taps would slow the others on llvmpipe).
layout(location = 17) uniform float u_filter;
#else
const float u_filter = 0.0;
#endif

// Entries of the per-pixel list of best photos: K (the K best weights) or K + 1 (Unstructured
// Lumigraph: the K smallest penalties and the threshold); each K compiles its own program, so
// that the list stays in registers (constant indices only).
#ifndef KEEP
#define KEEP 5
#endif
// Weight of delta_k against the angle in the Unstructured Lumigraph penalty: set by BlendPass
// from kUlrDistanceWeight (core/photo_candidates.h), its one home.
#ifndef DELTA_WEIGHT
#error "DELTA_WEIGHT must be defined (render/blend_pass.cc, ProgramModes)"
#endif

const float kHalfPi = 1.5707963;
const float kFeather = 0.05;  // feathered band at a photo's frame, share of its longer side
const int kMarchSteps = 64;   // MarchDepth: steps along the ray before the bisection
const int kRankPhotos = 4;   // RankByPenalty: photos ranked
const int kMarchPhotos = 2;  // HoleDepth: photos marched, smallest penalty first
const float kMarchNear = 0.01;  // MarchDepth: nearest view depth searched, in scene scales
const float kMarchTolerance = 0.05;  // MarchDepth: relative depth gap of a continuous surface
const int kSweepSteps = 64;     // SweepDepth: depths, uniform in inverse depth, before refining
const int kHollowSteps = 16;    // SweepDepth inside a non-planar surface: depths before refining
const float kHollowFar = 2.0;   // ... searched to this multiple of the surface's farthest depth
const float kSweepNear = 0.5;   // SweepDepth: nearest view depth searched, in scene scales
const float kSweepPatch = 2.0;  // SweepDepth: offset of the patch's 4 diagonal rays, view pixels
const float kSweepMaxCost = 0.02;  // SweepDepth: largest SweepCost accepted (ln units^2)
const float kEnclosedReach = 1.0 / 8.0;  // EnclosedDepth: search reach, share of the longer side
const int kEnclosedSteps = 32;  // EnclosedDepth: steps to the reach past the first 8 pixels
const float kEnclosedPlanar = 0.05;  // EnclosedDepth: spread of the lines' inverse depths
const float kCubicMaxLod = 0.5;  // CUBIC: coarser levels of detail are sampled trilinearly
const int kRefineSteps = 1;     // REFINE: depths tested on each side of the depth pass's z
const float kRefinePatch = 1.0;  // REFINE: offset of the patch's 4 diagonal rays, view pixels

// What a pixel shows: a point P with normal N (world) on a surface or on the background
// sphere, or, at infinity, the world direction d (stored in P) of the pixel's ray.
struct Sample {
  vec3 P;
  vec3 N;
  vec3 V;        // unit vector from the point towards the view's centre C (-d at infinity)
  float dist_c;  // |C - P|; 0 at infinity
  float z_new;   // camera z of P in the view; 0 at infinity
  bool background;   // no point: on the background sphere or at infinity
  bool at_infinity;  // P holds a direction
};

// Places the sample at the world point P of view depth z (view centre C), facing the view.
void PlaceAt(inout Sample s, vec3 C, vec3 P, float z) {
  s.P = P;
  s.dist_c = length(C - P);
  s.V = (C - P) / s.dist_c;
  s.N = s.V;
  s.z_new = z;
}

// Places the sample at infinity in the world direction d, facing the view.
void PlaceAtInfinity(inout Sample s, vec3 d) {
  s.P = normalize(d);
  s.V = -s.P;
  s.N = s.V;
  s.dist_c = 0.0;
  s.z_new = 0.0;
}

// Camera z of the background sphere (centre u_sphere.xyz, radius u_sphere.w, around every
// camera) along the world ray C + u d (d with camera z 1); 0 when the ray does not leave it.
float SphereDepth(vec3 C, vec3 d) {
  vec3 o = C - u_sphere.xyz;
  float a = dot(d, d);
  float b = dot(o, d);
  float c = dot(o, o) - u_sphere.w * u_sphere.w;
  float disc = b * b - a * c;
  if (disc < 0.0) return 0.0;
  return max((-b + sqrt(disc)) / a, 0.0);
}

// Camera z of the background surface along the world ray C + u d (d with camera z 1): the plane
// (BACKGROUND 3) where the ray meets it inside its extent before it leaves the sphere, else the
// sphere; 0 when there is none.
float SurfaceDepth(vec3 C, vec3 d) {
  float t = SphereDepth(C, d);
#if BACKGROUND == 3
  // The cameras lie on the side the normal points to: only a ray going against it meets the
  // plane's face.
  float along = dot(u_plane.xyz, d);
  if (along < 0.0) {
    float t_plane = -(dot(u_plane.xyz, C) + u_plane.w) / along;
    vec3 X = C + t_plane * d;
    vec2 uv = vec2(dot(u_plane_u, X), dot(u_plane_v, X));
    bool inside = all(greaterThanEqual(uv, u_plane_extent.xz)) &&
                  all(lessThanEqual(uv, u_plane_extent.yw));
    if (t_plane > 0.0 && t_plane < t && inside) t = t_plane;
  }
#endif
  return t;
}

// Places the sample on the background: at infinity (BACKGROUND 1), else on the surface at the
// view depth z_surface of the world ray C + t d; false where there is none (z_surface 0).
bool PlaceOnBackground(inout Sample s, vec3 C, vec3 d, float z_surface) {
  s.at_infinity = BACKGROUND == 1;
  if (s.at_infinity) {
    PlaceAtInfinity(s, d);
  } else if (z_surface > 0.0) {
    PlaceAt(s, C, C + z_surface * d, z_surface);
  } else {
    return false;
  }
  return true;
}

// Photo i's camera pixel of the point pk of its camera space; false when pk is behind the photo
// or outside its frame.
bool PixelIn(int i, vec3 pk, out vec2 px) {
  px = vec2(0.0);
  if (pk.z <= 0.0) return false;
  vec4 intr = photos[i].intrinsics;
  px = intr.xy * pk.xy / pk.z + intr.zw;
  return all(greaterThanEqual(px, vec2(0.0))) && all(lessThan(px, photos[i].size.xy));
}

// Unit direction V_k from the sample toward photo i's centre (V at infinity) and delta_k, the
// difference of the distances |C - P| and |C_k - P| in scene scales (eq. 4); at infinity the
// distance |C_k - C| between the centres (see Weight).
vec3 TowardPhoto(int i, Sample s, out float delta) {
  vec3 ck = photos[i].center.xyz;
  if (s.at_infinity) {
    delta = length(ck - u_world_from_cam[3].xyz) * u_inv_scene_scale;
    return s.V;
  }
  vec3 vk = ck - s.P;
  float dist_k = length(vk);
  delta = abs(s.dist_c - dist_k) * u_inv_scene_scale;
  return vk / dist_k;
}

// Where a sample projects in photo i, in the photo's camera pixels; false when it is behind
// the photo or outside its frame. pk receives the point (or direction) in photo i's camera.
bool ProjectInto(int i, Sample s, out vec2 px, out vec3 pk) {
  pk = s.at_infinity ? mat3(photos[i].cam_from_world) * s.P
                     : (photos[i].cam_from_world * vec4(s.P, 1.0)).xyz;
  return PixelIn(i, pk, px);
}

// Shadow-map test against photo i's depth map around px, on the 2x2 texels about the
// projection (a single texel rejects half the pixels along the photo's silhouettes): a point
// passes when it agrees with one of them, a background sample (which lies beyond every point,
// or on the plane around a hole of the view's depth) when one of them holds no point or agrees.
float VisibleIn(int i, Sample s, vec2 px, float z_k) {
  int layer = CACHED_DEPTH == 1 ? depth_slot_of[i] : i;
  if (layer < 0) return 0.0;  // no depth map resident: nothing to test against
  vec4 dmap = photos[i].dmap;
  ivec2 d0 = ivec2(floor(px * dmap.xy - 0.5));
  ivec2 dmax = ivec2(dmap.zw) - 1;
  int agree = 0;
  bool any_empty = false;
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      ivec2 t = clamp(d0 + ivec2(dx, dy), ivec2(0), dmax);
      float dk = texelFetch(u_photo_depth, ivec3(t, layer), 0).r;
      if (dk <= 0.0) any_empty = true;
      if (dk > 0.0 && abs(z_k - dk) <= u_tolerance * dk) ++agree;
    }
  }
  if (s.background) return any_empty || agree > 0 ? 1.0 : 0.0;
  if (SOFT_VISIBILITY == 1) return float(agree) / 4.0;
  return agree > 0 ? 1.0 : 0.0;
}

// Photo i's depth map and its camera z at the view's ray point C + t d: in front (true) when the
// map holds no point there or a farther one. False in `inside` when the point is behind photo i
// or outside its frame.
bool InFrontOf(int i, int layer, vec3 P, out bool inside, out float z_k, out float d_k) {
  vec3 pk = (photos[i].cam_from_world * vec4(P, 1.0)).xyz;
  z_k = pk.z;
  d_k = 0.0;
  vec2 px;
  inside = PixelIn(i, pk, px);
  if (!inside) return false;
  ivec2 t = clamp(ivec2(px * photos[i].dmap.xy), ivec2(0), ivec2(photos[i].dmap.zw) - 1);
  d_k = texelFetch(u_photo_depth, ivec3(t, layer), 0).r;
  return d_k <= 0.0 || pk.z < d_k;
}

// The view depths [t.x, t.y] over which the ray C + t d lies in front of photo i and inside its
// frame, within [t0, t1] (t1 <= 0: unbounded); t.x >= t.y when it never does. Each frame edge
// and the photo's image plane are a linear condition a + b t >= 0 on t.
vec2 FrustumSpan(int i, vec3 C, vec3 d, float t0, float t1) {
  vec3 o = (photos[i].cam_from_world * vec4(C, 1.0)).xyz;
  vec3 e = mat3(photos[i].cam_from_world) * d;
  vec4 f = photos[i].intrinsics;
  vec2 size = photos[i].size.xy;
  vec2 span = vec2(t0, t1 > 0.0 ? t1 : 3.0e38);
  vec2 conds[5];
  conds[0] = vec2(o.z - 1e-3 * t0, e.z);
  conds[1] = vec2(f.x * o.x + f.z * o.z, f.x * e.x + f.z * e.z);
  conds[2] = vec2(size.x * o.z, size.x * e.z) - conds[1];
  conds[3] = vec2(f.y * o.y + f.w * o.z, f.y * e.y + f.w * e.z);
  conds[4] = vec2(size.y * o.z, size.y * e.z) - conds[3];
  for (int c = 0; c < 5; ++c) {
    float a = conds[c].x, b = conds[c].y;
    if (b > 0.0) {
      span.x = max(span.x, -a / b);
    } else if (b < 0.0) {
      span.y = min(span.y, -a / b);
    } else if (a < 0.0) {
      span.y = span.x;
    }
  }
  return span;
}

// View depth (camera z) where the view's ray C + t d (d: camera z 1) first passes behind the
// surface of photo i's depth map, searched where the ray is in photo i's frame between t0 and
// t1 (t1 <= 0: infinity) in kMarchSteps steps uniform in inverse depth (uniform along the
// epipolar line in the photo), then bisected; 0 when the ray meets no continuous surface there
// (only silhouettes it passes behind, where the map's depth jumps away from the ray's).
float MarchDepth(int i, vec3 C, vec3 d, float t0, float t1) {
  int layer = CACHED_DEPTH == 1 ? depth_slot_of[i] : i;
  if (layer < 0) return 0.0;
  vec2 span = FrustumSpan(i, C, d, t0, t1);
  if (span.x >= span.y) return 0.0;
  float inv0 = 1.0 / span.x;
  float inv1 = span.y < 3.0e38 ? 1.0 / span.y : 0.0;
  bool prev_front = false;
  float prev_inv = inv0;
  for (int j = 0; j <= kMarchSteps; ++j) {
    float inv = max(mix(inv0, inv1, float(j) / float(kMarchSteps)), 1e-3 * inv0);
    bool inside;
    float z_k, d_k;
    bool front = InFrontOf(i, layer, C + d / inv, inside, z_k, d_k);
    if (inside && !front && prev_front) {
      float lo = prev_inv, hi = inv;  // in front at lo, behind at hi (inside, z_k, d_k at hi)
      for (int b = 0; b < 8; ++b) {
        float mid = 0.5 * (lo + hi);
        bool mid_inside;
        float mid_z, mid_d;
        if (InFrontOf(i, layer, C + d / mid, mid_inside, mid_z, mid_d)) {
          lo = mid;
        } else {
          hi = mid;
          inside = mid_inside;
          z_k = mid_z;
          d_k = mid_d;
        }
      }
      if (inside && d_k > 0.0 && z_k - d_k <= kMarchTolerance * d_k) return 1.0 / hi;
    }
    prev_front = inside && front;
    prev_inv = inv;
  }
  return 0.0;
}

// The kRankPhotos photos that frame sample s with the smallest Unstructured Lumigraph penalty
// (angle + distance, as in Weight), smallest first; -1 past the photos that frame it.
void RankByPenalty(Sample s, out int ids[kRankPhotos]) {
  float best_p[kRankPhotos];
  for (int j = 0; j < kRankPhotos; ++j) {
    best_p[j] = 3.0e38;
    ids[j] = -1;
  }
  for (int a = 0; a < u_active_count; ++a) {
    int i = active_photos[a];
    vec2 px;
    vec3 pk;
    if (!ProjectInto(i, s, px, pk)) continue;
    float delta;
    float p =
        acos(clamp(dot(s.V, TowardPhoto(i, s, delta)), -1.0, 1.0)) + DELTA_WEIGHT * delta;
    for (int j = 0; j < kRankPhotos; ++j) {  // insertion with constant indices
      if (p < best_p[j]) {
        float t_p = best_p[j];
        int t_i = ids[j];
        best_p[j] = p;
        ids[j] = i;
        p = t_p;
        i = t_i;
      }
    }
  }
}

// Where a background sample that no photo passes (each photo's depth map holds a point where
// the sample projects: a hole in the view's geometry), or without a background a pixel without
// depth (ranked as its ray's direction), lies on the photos' surfaces: the view depth at which
// its ray meets the depth map of the first of the kMarchPhotos photos of ids (RankByPenalty of
// the sample) that holds a continuous surface along the ray; 0 when none does.
float HoleDepth(int ids[kRankPhotos], vec3 C, vec3 d, float t_far) {
  float t0 = kMarchNear / u_inv_scene_scale;
  for (int j = 0; j < kMarchPhotos; ++j) {
    float t = ids[j] >= 0 ? MarchDepth(ids[j], C, d, t0, t_far) : 0.0;
    if (t > 0.0) return t;
  }
  return 0.0;
}

// True when photo i with ranking key `key` ranks before photo i2 with key2: a larger key, or
// an equal key and a smaller index.
bool Beats(float key, int i, float key2, int i2) { return key > key2 || (key == key2 && i < i2); }

// Geometric weight of photo i for the sample (0 when photo i does not see it, or when its
// ranking key, -penalty for the Unstructured Lumigraph or an upper bound of the weight
// otherwise, is < min_key: it could not enter the list of best photos, and the shadow-map test
// is skipped); uvl receives the texture coordinate and the level of detail in the photo,
// feather a factor in (0, 1] of the final weight (for the background: falling to 0 at the
// photo's frame, so that no seam shows where a photo's frame crosses the sky; for points, the
// soft visibility or 1), penalty the Unstructured Lumigraph penalty angle(V, V_k) (radians) +
// DELTA_WEIGHT delta_k. At infinity V_k = V (angle 0, cos 1), and delta_k is the distance
// |C_k - C| between the centres: what lies beyond the points is far but not infinitely far, and
// its parallax grows with that distance (the limit of eq. 4, (C_k - C) . d, would ignore
// sideways offsets).
float Weight(int i, Sample s, bool ulr, float min_key, out vec3 uvl, out float feather,
             out float penalty) {
  uvl = vec3(0.0);
  feather = 1.0;
  penalty = 0.0;
  vec2 px;
  vec3 pk;
  if (!ProjectInto(i, s, px, pk)) return 0.0;
  float cos_k = 1.0;
  float delta;
  vec3 vk = TowardPhoto(i, s, delta);  // eq. 4
  float footprint;  // photo texels per target pixel
  vec4 intr = photos[i].intrinsics;
  if (s.at_infinity) {
    // Angular size of a pixel: 1 / f_new in the view, 1 / f_i in the photo.
    footprint = intr.x / u_intrinsics.x * photos[i].size.z;
  } else {
    // Grazing or back-facing (paper: N_p . V_k > lambda).
    if (dot(s.N, vk) <= u_lambda) return 0.0;
    cos_k = max(0.0, dot(s.V, vk));  // eq. 2
    // A target pixel covers z_new / f_new world units at P, which photo i sees over that
    // times f_i / z_i camera pixels, times its texels per camera pixel.
    footprint = s.z_new / u_intrinsics.x * intr.x / pk.z * photos[i].size.z;
  }
  if (s.background) {
    vec2 size = photos[i].size.xy;
    vec2 border = min(px, size - px);
    feather = max(clamp(min(border.x, border.y) / (kFeather * max(size.x, size.y)), 0.0, 1.0),
                  1e-3);
  }
  if (NEAREST == 0) penalty = acos(min(cos_k, 1.0)) + DELTA_WEIGHT * delta;
  // The weight with full visibility bounds the weight (eq. 5).
  if ((ulr ? -penalty : NEAREST == 0 ? feather * cos_k / (delta + 1.0) : feather) < min_key) {
    return 0.0;
  }
  float visibility = VisibleIn(i, s, px, pk.z);
  if (visibility <= 0.0) return 0.0;
  feather *= visibility;
  vec4 tex = photos[i].tex;
  uvl = vec3(clamp(px * tex.xy, vec2(0.0), tex.zw), log2(max(footprint, 1e-6)));
  return NEAREST == 0 ? feather * cos_k / (delta + 1.0) : feather;  // eq. 5
}

// Photo i's stored value at uvl (texture coordinate, level of detail).
// A slot of 1 / 2^t of the full size holds levels t and coarser at the same texture
// coordinates: sampled at level of detail lod - t, it returns the full array's texels.
vec3 FetchPhoto(int i, vec3 uvl) {
  if (CACHED == 0) return textureLod(u_photos, vec3(uvl.xy, float(i)), uvl.z).rgb;
#if CACHED == 1
  int level = int(max(uvl.z, 0.0));  // trilinear reads this level and the next
  if (sampled_level[i] > level) atomicMin(sampled_level[i], level);
#endif
  int slot = slot_of[i];
  if (slot >= 0) {
    int tier = slot >> 24;
    vec3 at = vec3(uvl.xy, float(slot & 0xffffff));
    if (TIERS == 1 || tier == 0) return textureLod(u_photos, at, uvl.z).rgb;
    if (TIERS == 2 || tier == 1) return textureLod(u_tier1, at, uvl.z - 1.0).rgb;
    return textureLod(u_tier2, at, uvl.z - 2.0).rgb;
  }
  vec4 co = photos[i].coarse;
  return textureLod(u_coarse, vec3(min(uvl.xy * co.xy, co.zw), float(i)), uvl.z + photos[i].size.w)
      .rgb;
}

// Keys' cubic convolution weights (a = -0.5: Catmull-Rom) of the 4 texels at distances 1 + f,
// f, 1 - f and 2 - f from the sample.
vec4 CatmullRomWeights(float f) {
  float f2 = f * f;
  return vec4(f * (-0.5 + f * (1.0 - 0.5 * f)), 1.0 + f2 * (-2.5 + 1.5 * f),
              f * (0.5 + f * (2.0 - 1.5 * f)), f2 * (-0.5 + 0.5 * f));
}

// Photo i's stored value at uvl, sampled with CUBIC's filter: Catmull-Rom from 9 bilinear taps
// at level 0 (the two middle texels of each axis share one tap; the negative lobes' undershoot
// clamped at 0); trilinear (FetchPhoto) beyond kCubicMaxLod.
vec3 FetchCubic(int i, vec3 uvl) {
  if (CUBIC == 0 || uvl.z > kCubicMaxLod) return FetchPhoto(i, uvl);
  vec2 texels = u_photo_texels;
  vec2 sp = uvl.xy * texels;
  vec2 t1 = floor(sp - 0.5) + 0.5;  // centre of the texel left of / above the sample
  vec2 f = sp - t1;
  vec4 wx = CatmullRomWeights(f.x);
  vec4 wy = CatmullRomWeights(f.y);
  vec3 xs = vec3(t1.x - 1.0, t1.x + wx[2] / (wx[1] + wx[2]), t1.x + 2.0) / texels.x;
  vec3 ys = vec3(t1.y - 1.0, t1.y + wy[2] / (wy[1] + wy[2]), t1.y + 2.0) / texels.y;
  vec3 cx = vec3(wx[0], wx[1] + wx[2], wx[3]);
  vec3 cy = vec3(wy[0], wy[1] + wy[2], wy[3]);
  vec3 sum = vec3(0.0);
  for (int b = 0; b < 3; ++b) {
    for (int a = 0; a < 3; ++a) sum += cx[a] * cy[b] * FetchPhoto(i, vec3(xs[a], ys[b], 0.0));
  }
  return max(sum, vec3(0.0));
}

// Photo i's stored value low-passed along its line of disparity (Eisemann et al. 2007, sec. 4):
// the segment between the projections of the points at relative depths 1 - u and 1 + u along
// the view's ray through s.P, sampled with 5 binomial taps at the level of detail of their
// spacing (a single tap where the segment is under a texel).
vec3 FetchFiltered(int i, Sample s, vec3 uvl, float u) {
#ifndef FILTERED
  return FetchCubic(i, uvl);
#else
  if (u <= 0.0 || s.background) return FetchCubic(i, uvl);
  vec3 C = u_world_from_cam[3].xyz;
  vec3 a = (photos[i].cam_from_world * vec4(C + (s.P - C) * (1.0 - u), 1.0)).xyz;
  vec3 b = (photos[i].cam_from_world * vec4(C + (s.P - C) * (1.0 + u), 1.0)).xyz;
  if (a.z <= 0.0 || b.z <= 0.0) return FetchCubic(i, uvl);
  vec4 intr = photos[i].intrinsics;
  vec2 pa = intr.xy * a.xy / a.z + intr.zw;
  vec2 pb = intr.xy * b.xy / b.z + intr.zw;
  float texels = length(pb - pa) * photos[i].size.z;
  if (texels <= 1.0) return FetchCubic(i, uvl);
  vec4 tex = photos[i].tex;
  float lod = max(uvl.z, log2(texels * 0.25));
  const float kTap[5] = float[5](1.0, 4.0, 6.0, 4.0, 1.0);
  vec3 sum = vec3(0.0);
  for (int t = 0; t < 5; ++t) {
    vec2 px = mix(pa, pb, float(t) * 0.25);
    sum += kTap[t] * FetchPhoto(i, vec3(clamp(px * tex.xy, vec2(0.0), tex.zw), lod));
  }
  return sum / 16.0;
#endif
}

// Debevec's g(Z) per channel of a stored photo value c (radiance encoding): ln of the exposure
// that gives the value, before the photo's own exposure.
vec3 ResponseLog(vec3 c) {
  vec3 t = (clamp(c * 255.0, 0.0, 255.0) + 0.5) / 256.0;
  return vec3(texture(u_response, vec2(t.r, 0.5)).r, texture(u_response, vec2(t.g, 0.5)).g,
              texture(u_response, vec2(t.b, 0.5)).b);
}

// The blended quantity of photo i from its stored value c; hat receives Debevec's hat weight
// (radiance encoding; 1 otherwise).
vec3 Blended(int i, vec3 c, out vec3 hat) {
  hat = vec3(1.0);
  if (ENCODING == 1) {
    vec3 z = clamp(c * 255.0, 0.0, 255.0);
    // min(Z, 255 - Z) per channel, floored so that a value saturated in every photo keeps its
    // (clipped) radiance instead of going invalid.
    hat = max(min(z, 255.0 - z), vec3(1e-3));
    c = exp(ResponseLog(c)) * photos[i].center.w;
  }
  return c;
}

// World offsets dx, dy of the view's ray direction (camera z 1) that move it `pixels` view
// pixels along the view's x and y axes: a patch's diagonal rays are d +- dx +- dy.
void PatchOffsets(float pixels, out vec3 dx, out vec3 dy) {
  dx = mat3(u_world_from_cam) * vec3(pixels / u_intrinsics.x, 0.0, 0.0);
  dy = mat3(u_world_from_cam) * vec3(0.0, pixels / u_intrinsics.y, 0.0);
}

// ln of photo i's blended quantity (radiance: g(Z) + ln of the exposure) at its camera pixel
// px and level of detail lod, at least ln 1e-4: a gain between photos adds the same to every
// pixel.
vec3 LogValue(int i, vec2 px, float lod) {
  vec4 tex = photos[i].tex;
  vec3 c = FetchPhoto(i, vec3(clamp(px * tex.xy, vec2(0.0), tex.zw), lod));
  return ENCODING == 1 ? max(ResponseLog(c) + log(photos[i].center.w), vec3(log(1e-4)))
                       : log(max(c, vec3(1e-4)));
}

// Disagreement of the ranked photos ids at view depth z on the view's ray C + z d, and when
// rays_used is 5 on 4 diagonal rays d +- dx +- dy beside it at the same depth: the variance of
// their log values (LogValue), summed over RGB and averaged over the rays, among the photos
// that see the centre ray's point (their depth map holds no surface there) and frame each
// ray's. False in ok when fewer than two photos see it, or when one holds a surface beyond it:
// it saw through the point, which lies in free space.
float SweepCost(vec3 C, vec3 d, vec3 dx, vec3 dy, float z, int ids[kRankPhotos], int rays_used,
                out bool ok) {
  float cost = 0.0;
  ok = false;
  vec3 rays[5] = vec3[5](d, d + dx + dy, d + dx - dy, d - dx + dy, d - dx - dy);
  bool sees[kRankPhotos];
  for (int r = 0; r < rays_used; ++r) {
    vec3 P = C + rays[r] * z;
    vec3 m = vec3(0.0), m2 = vec3(0.0);
    float n = 0.0;
    for (int j = 0; j < kRankPhotos; ++j) {
      int i = ids[j];
      if (r == 0) {
        int layer = i < 0 ? -1 : CACHED_DEPTH == 1 ? depth_slot_of[i] : i;
        bool inside = false;
        float z_k = 0.0, d_k = 0.0;
        sees[j] = layer >= 0 && InFrontOf(i, layer, P, inside, z_k, d_k) && d_k <= 0.0;
        if (inside && d_k > (1.0 + u_tolerance) * z_k) return 0.0;
      }
      if (!sees[j]) continue;
      vec3 pk = (photos[i].cam_from_world * vec4(P, 1.0)).xyz;
      vec2 px;
      if (!PixelIn(i, pk, px)) continue;
      // Photo texels per view pixel at this depth (as in Weight).
      float footprint = z / u_intrinsics.x * photos[i].intrinsics.x / pk.z * photos[i].size.z;
      vec3 v = LogValue(i, px, max(log2(max(footprint, 1e-6)), 0.0));
      m += v;
      m2 += v * v;
      n += 1.0;
    }
    if (n < 2.0) {
      if (r == 0) return 0.0;
      continue;
    }
    m /= n;
    vec3 var = max(m2 / n - m * m, vec3(0.0));
    cost += var.r + var.g + var.b;
  }
  ok = true;
  return cost / float(rays_used);
}

// View depth of the plane that encloses pixel p's hole in the view's depth map: along each of
// the 4 lines through p (horizontal, vertical, the diagonals), the first depth on both sides
// within kEnclosedReach of the frame, interpolated linearly in inverse depth (exact across a
// plane, whose inverse depth is affine in the image); 0 unless at least 3 lines find both sides
// and their estimates agree within kEnclosedPlanar (a silhouette, where the sides are different
// surfaces, gives no depth). What multi-view stereo leaves without points inside a surface (an
// untextured wall or door) is drawn on the surface around it. span receives the smallest and
// largest of the lines' inverse depths when at least 3 lines find both sides (the hole is
// enclosed, planar or not), else 0.
float EnclosedDepth(ivec2 p, out vec2 span) {
  span = vec2(0.0);
  const ivec2 kDirs[4] = ivec2[4](ivec2(1, 0), ivec2(0, 1), ivec2(1, 1), ivec2(1, -1));
  int reach = int(kEnclosedReach * float(max(u_size.x, u_size.y)));
  int stride = max(1, reach / kEnclosedSteps);
  float lo = 3.0e38, hi = 0.0, sum = 0.0;
  int lines = 0;
  for (int l = 0; l < 4; ++l) {
    if (l - lines >= 2) return 0.0;  // 3 lines can no longer be found
    float inv[2] = float[2](0.0, 0.0);
    float dist[2] = float[2](0.0, 0.0);
    for (int side = 0; side < 2; ++side) {
      if (side == 1 && dist[0] <= 0.0) break;
      ivec2 dir = side == 0 ? kDirs[l] : -kDirs[l];
      for (int k = 1; k <= reach; k += k < 8 ? 1 : stride) {
        ivec2 q = p + k * dir;
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, u_size))) break;
        float zq = texelFetch(u_depth, q, 0).r;
        if (zq > 0.0) {
          inv[side] = 1.0 / zq;
          dist[side] = float(k);
          break;
        }
      }
    }
    if (dist[0] <= 0.0 || dist[1] <= 0.0) continue;
    float e = (inv[0] * dist[1] + inv[1] * dist[0]) / (dist[0] + dist[1]);
    lo = min(lo, e);
    hi = max(hi, e);
    sum += e;
    ++lines;
  }
  if (lines >= 3) span = vec2(lo, hi);
  if (lines < 3 || hi > (1.0 + kEnclosedPlanar) * lo) return 0.0;
  return float(lines) / sum;
}

// Depth of a background sample that no photo passes and whose ray meets no surface of the
// photos' depth maps (HoleDepth), or that a non-planar surface encloses, from a plane sweep
// along the view's ray C + t d (d: camera z 1) over the photos ids (RankByPenalty of the
// sample): `steps` depths uniform in inverse depth over inv_range (view inverse depths,
// farthest first) scored on the ray alone (SweepCost), then every eighth of a step within one
// step of the best scored over the patch; the depth where the photos agree best (on ties the
// farthest, as befits what lies beyond the points), 0 when no depth is seen by two photos or
// the best disagrees more than kSweepMaxCost. What multi-view stereo left without points
// (untextured walls, far buildings seen through gaps) is drawn at the depth where its photos
// agree: a plane sweep (Collins 1996) for the view's holes alone.
float SweepDepth(int ids[kRankPhotos], vec3 C, vec3 d, vec2 inv_range, int steps) {
  if (ids[1] < 0) return 0.0;
  vec3 dx, dy;
  PatchOffsets(kSweepPatch, dx, dy);
  float step = (inv_range.y - inv_range.x) / float(steps);
  float best_cost = 3.0e38;
  float best_inv = 0.0;
  for (int k = 0; k < steps; ++k) {  // far to near, from half a step short of the far end
    float inv = inv_range.x + step * (float(k) + 0.5);
    bool ok;
    float cost = SweepCost(C, d, dx, dy, 1.0 / inv, ids, 1, ok);
    if (ok && cost < best_cost) {
      best_cost = cost;
      best_inv = inv;
    }
  }
  if (best_inv <= 0.0) return 0.0;
  float center = best_inv;
  best_cost = 3.0e38;
  for (int k = -8; k <= 8; ++k) {
    float inv = center + step * float(k) / 8.0;
    if (inv <= 0.0) continue;
    bool ok;
    float cost = SweepCost(C, d, dx, dy, 1.0 / inv, ids, 5, ok);
    if (ok && cost < best_cost) {
      best_cost = cost;
      best_inv = inv;
    }
  }
  return best_cost <= kSweepMaxCost ? 1.0 / best_inv : 0.0;
}

#if REFINE == 1
// Disagreement of the listed photos (weights w, levels of detail uvl.z) at the point of view
// depth z on the ray C + z d (d: camera z 1): the weighted variance, summed over RGB, of the
// logs of their blended values (a gain between photos adds the same to every depth); false in
// ok when a listed photo does not frame the point.
float Disagreement(vec3 C, vec3 d, float z, int ids[KEEP], float w[KEEP], vec3 uvl[KEEP],
                   out bool ok) {
  vec3 P = C + d * z;
  vec3 m = vec3(0.0), m2 = vec3(0.0);
  float ws = 0.0;
  ok = true;
  for (int j = 0; j < KEEP; ++j) {
    if (w[j] <= 0.0) continue;
    int i = ids[j];
    vec2 px;
    if (!PixelIn(i, (photos[i].cam_from_world * vec4(P, 1.0)).xyz, px)) {
      ok = false;
      return 0.0;
    }
    vec3 v = LogValue(i, px, max(uvl[j].z, 0.0));
    m += w[j] * v;
    m2 += w[j] * v * v;
    ws += w[j];
  }
  m /= ws;
  vec3 var = max(m2 / ws - m * m, vec3(0.0));
  return var.r + var.g + var.b;
}

// Photo-consistent depth: the view depth, among the depth pass's z (sample s) and kRefineSteps
// steps on each side of it within +-u_refine * z, where the listed photos disagree least over
// a patch: the pixel's ray at that depth and 4 diagonal rays kRefinePatch pixels away where
// they meet the plane through that point with the sample's normal (PatchMatch stereo's slanted
// windows, Bleyer et al. 2011; a depth ratio beyond 1.25 counts as fronto-parallel). Winner
// takes all; z itself on ties or where a photo does not frame a depth; a patch ray that leaves
// a photo's frame adds nothing. The photos' texture coordinates move with it; their list,
// weights and visibility stay those of z (a depth within the occlusion tolerance of it, of the
// same surface). Point clouds from multi-view stereo are off by a fraction of a pixel's
// parallax, which blurs the blend of several photos; the search realigns them: per-view depth
// from photo-consistency, as in Soft 3D (Penner & Zhang 2017), within a small range about the
// cloud's depth.
void RefineDepth(inout Sample s, vec3 C, vec3 d, int ids[KEEP], float w[KEEP],
                 inout vec3 uvl[KEEP]) {
  int used = 0;
  for (int j = 0; j < KEEP; ++j) used += w[j] > 0.0 ? 1 : 0;
  if (used < 2) return;
  vec3 dx, dy;
  PatchOffsets(kRefinePatch, dx, dy);
  float z0 = s.z_new;
  // Ratios of the patch rays' depths to the centre's on the sample's plane (normal s.N).
  float nd = dot(s.N, d);
  vec4 tilt = nd / vec4(dot(s.N, d + dx + dy), dot(s.N, d + dx - dy), dot(s.N, d - dx + dy),
                        dot(s.N, d - dx - dy));
  tilt = mix(vec4(1.0), tilt, equal(clamp(tilt, 0.8, 1.25), tilt));
  float best_cost = 3.0e38;
  float best_z = z0;
  for (int r = 0; r <= 2 * kRefineSteps; ++r) {
    // z first, then outwards (-1, +1, -2, +2, ... steps), so a tie keeps the nearest to z.
    int step = (r + 1) / 2 * ((r & 1) == 1 ? -1 : 1);
    float z = z0 * (1.0 + u_refine * float(step) / float(kRefineSteps));
    bool ok, ok_patch;
    float cost = Disagreement(C, d, z, ids, w, uvl, ok);
    if (!ok) continue;
    cost += Disagreement(C, d + dx + dy, z * tilt.x, ids, w, uvl, ok_patch);
    cost += Disagreement(C, d + dx - dy, z * tilt.y, ids, w, uvl, ok_patch);
    cost += Disagreement(C, d - dx + dy, z * tilt.z, ids, w, uvl, ok_patch);
    cost += Disagreement(C, d - dx - dy, z * tilt.w, ids, w, uvl, ok_patch);
    if (cost < best_cost) {
      best_cost = cost;
      best_z = z;
    }
  }
  if (best_z == z0) return;
  vec3 n = s.N;
  PlaceAt(s, C, C + d * best_z, best_z);
  s.N = n;
  for (int j = 0; j < KEEP; ++j) {
    if (w[j] <= 0.0) continue;
    vec2 px;
    vec3 pk;
    if (ProjectInto(ids[j], s, px, pk)) {
      vec4 tex = photos[ids[j]].tex;
      uvl[j].xy = clamp(px * tex.xy, vec2(0.0), tex.zw);
    }
  }
}
#endif

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, u_size))) return;
  vec4 color = vec4(0.0);
  vec4 aux = vec4(0.0);
  float z = texelFetch(u_depth, p, 0).r;
  vec3 ray = vec3((vec2(p) + 0.5 - u_intrinsics.zw) / u_intrinsics.xy, 1.0);
  vec3 C = u_world_from_cam[3].xyz;
  const bool has_point = z > 0.0;
  Sample s;
  s.background = !has_point;
  s.at_infinity = s.background && BACKGROUND == 1;
  vec3 ray_world = mat3(u_world_from_cam) * ray;
  float z_surface = s.background && BACKGROUND >= 2 ? SurfaceDepth(C, ray_world) : 0.0;
  vec2 span = vec2(0.0);  // inverse depths of the surface around a hole (EnclosedDepth)
  float z_plane = s.background && BACKGROUND != 0 ? EnclosedDepth(p, span) : 0.0;
  if (s.background && BACKGROUND >= 2) z = z_surface;
  if (z_plane > 0.0) {
    z = z_plane;
    s.at_infinity = false;
  }
#if BACKGROUND == 0
  // Without a background, a pixel without depth can still lie on a surface that the photos'
  // depth maps hold along its ray (a hole of the view's geometry; ranked as a direction).
  if (s.background) {
    s.at_infinity = true;
    PlaceAtInfinity(s, ray_world);
    int ids[kRankPhotos];
    RankByPenalty(s, ids);
    z = HoleDepth(ids, C, ray_world, 0.0);
    s.at_infinity = false;
    s.background = z <= 0.0;
  }
#endif
  if (z > 0.0 || s.at_infinity) {
    if (s.at_infinity) {
      PlaceAtInfinity(s, ray_world);
    } else {
      PlaceAt(s, C, C + z * ray_world, z);
      vec3 n = has_point ? texelFetch(u_normal, p, 0).xyz : vec3(0.0);
      if (dot(n, n) > 1e-8) s.N = normalize(mat3(u_world_from_cam) * n);
    }
    // A pixel without a point is tried first on the plane of the surface around it
    // (EnclosedDepth), or, where that surface is not planar, at the depth where the photos
    // agree between the surface's nearest depth and twice its farthest (the inside of a
    // hollow, which holds no point: the sphere would show what the photos see past the rim);
    // then on the background surface; where no photo passes, on the surface that the photos'
    // depth maps hold along its ray (HoleDepth), and where none does, at the depth where the
    // photos agree (SweepDepth), rather than staying empty: a loop, so that the blend below is
    // compiled once. `fallback` is the next depth to try: 0 the background surface, 1 the march
    // or the sweep, 2 none.
    int fallback = z_plane > 0.0 ? 0 : 1;
    // The photos ranked for the sample on the background surface, where the march and the
    // sweeps need them (the same for the hollow's sweep, which runs before the sample moves).
    int ids[kRankPhotos];
    bool ranked = false;
    if (s.background && z_plane <= 0.0 && span.y > 0.0) {
      RankByPenalty(s, ids);
      ranked = true;
      float t = SweepDepth(ids, C, ray_world, vec2(span.x / kHollowFar, span.y), kHollowSteps);
      if (t > 0.0) {
        s.at_infinity = false;
        PlaceAt(s, C, C + t * ray_world, t);
        fallback = 0;
      }
    }
    for (int pass = 0; pass < 3; ++pass) {
      vec3 sum = vec3(0.0);
      vec3 wsum = vec3(0.0);
      float geo_sum = 0.0;
      float debug_w = 0.0;
      float count = 0.0;
      // Candidates: every photo (paper, SUM_ALL), or the K best by weight, or the K + 1
      // smallest penalties (Unstructured Lumigraph), kept sorted (Beats), so the list does not
      // depend on the order the photos are visited in.
      bool ulr = ULR == 1 && NEAREST == 0;
      int k = ulr ? KEEP - 1 : KEEP;
      float best_key[KEEP];
      float best_w[KEEP];
      float best_f[KEEP];
      int best_i[KEEP];
      vec3 best_uvl[KEEP];
      for (int j = 0; j < KEEP; ++j) {
        best_key[j] = -3.0e38;
        best_w[j] = 0.0;
        best_f[j] = 0.0;
        best_i[j] = 0x7fffffff;
        best_uvl[j] = vec3(0.0);
      }
      int n_best = 0;
      for (int a = 0; a < u_active_count; ++a) {
        int i = active_photos[a];
        vec3 uvl;
        float feather;
        float penalty;
        float w = Weight(i, s, ulr, best_key[KEEP - 1], uvl, feather, penalty);
        if (w <= 0.0) continue;
        if (SUM_ALL == 1) {  // all photos: accumulate directly
          vec3 hat;
          vec3 c = Blended(i, FetchFiltered(i, s, uvl, u_filter), hat);
          sum += w * hat * c;
          wsum += w * hat;
          geo_sum += w;
          count += 1.0;
          if (i == u_debug_photo) debug_w = w;
          continue;
        }
        float key = ulr ? -penalty : w;  // larger is better
        if (!Beats(key, i, best_key[KEEP - 1], best_i[KEEP - 1])) continue;
        // Carried down the list, swapping with every entry it beats: an insertion with constant
        // indices; the entry carried past the end is dropped.
        for (int j = 0; j < KEEP; ++j) {
          if (Beats(key, i, best_key[j], best_i[j])) {
            float t_key = best_key[j], t_w = best_w[j], t_f = best_f[j];
            int t_i = best_i[j];
            vec3 t_uvl = best_uvl[j];
            best_key[j] = key;
            best_w[j] = w;
            best_f[j] = feather;
            best_i[j] = i;
            best_uvl[j] = uvl;
            key = t_key;
            w = t_w;
            feather = t_f;
            i = t_i;
            uvl = t_uvl;
          }
        }
        n_best = min(n_best + 1, KEEP);
      }
      if (ulr && n_best > 0) {
        // Threshold: the (K+1)-th penalty, or the paper's cosine horizon when fewer photos see P.
        // (floored: K + 1 photos from exactly the view's direction would give 0 / 0).
        float t = max(n_best > k ? -best_key[KEEP - 1] : kHalfPi, 1e-4);
        n_best = min(n_best, k);
        for (int j = 0; j < KEEP; ++j) {
          float p = -best_key[j];
          best_w[j] = j < n_best ? best_f[j] * max(0.0, 1.0 - p / t) / max(p, 1e-4) : 0.0;
        }
        if (best_w[0] <= 0.0) best_w[0] = 1.0;  // every penalty beyond the horizon: the best
      }
      for (int j = 0; j < KEEP; ++j) {  // entries past the list carry no weight
        if (j >= n_best) best_w[j] = 0.0;
      }
#if REFINE == 1
      if (!s.background) RefineDepth(s, C, ray_world, best_i, best_w, best_uvl);
#endif
      vec3 stored[KEEP];
      for (int j = 0; j < KEEP; ++j) {
        bool used = j < n_best && best_w[j] > 0.0;
        stored[j] = used ? FetchFiltered(best_i[j], s, best_uvl[j], u_filter) : vec3(0.0);
        if (!used) best_w[j] = 0.0;
      }
#if OUTLIER == 1
      // One reweighting step (Cauchy's): photos whose value departs from the weighted mean by
      // more than the scale (ghosts of wrong depth or occlusion, highlights) lose their weight.
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
#endif
      for (int j = 0; j < KEEP; ++j) {
        if (best_w[j] <= 0.0) continue;
        vec3 hat;
        vec3 c = Blended(best_i[j], stored[j], hat);
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
      // A point, or a marched sample (on a photo's surface), that no photo passes stays empty.
      if (color.a > 0.0 || !s.background || fallback == 2) break;
      if (fallback == 0) {
        if (!PlaceOnBackground(s, C, ray_world, z_surface)) break;
        fallback = 1;
        continue;
      }
      if (!ranked) RankByPenalty(s, ids);
      float t = HoleDepth(ids, C, ray_world, s.at_infinity ? 0.0 : z_surface);
      fallback = 2;
      if (t > 0.0) {
        s.background = false;
      } else {
        // Still a background sample: seen by the photos whose depth map holds no point there.
        t = SweepDepth(ids, C, ray_world, vec2(0.0, u_inv_scene_scale / kSweepNear), kSweepSteps);
        if (t <= 0.0) break;
      }
      s.at_infinity = false;
      PlaceAt(s, C, C + t * ray_world, t);
    }
  }
  imageStore(u_out_color, p, color);
  imageStore(u_out_aux, p, aux);
}
