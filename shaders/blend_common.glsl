// Blend pass, shared by its two programs (blend.comp for the pixels with a point,
// blend_background.comp for the others): the modes compiled into a program, the photos'
// buffers and textures, the parameters' uniform block, and the sample a pixel shows.
// Docs: docs/algorithms/blend.md.

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
// The pixels without depth, listed by blend.comp (x | y << 16 each) for blend_background.comp,
// which is dispatched on the buffer's first three words (a group per 64 pixels listed); the
// pass sets them to 0, 1, 1, 0 before the frame.
layout(std430, binding = 5) buffer Holes {
  uint groups_x;
  uint groups_y;
  uint groups_z;
  uint hole_count;
  uint hole_pixels[];
};

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

// Every parameter of a frame (std140; render::BlendParamsGpu in render/blend_params.h mirrors
// it, member for member). A parameter that a program's modes do not use is ignored.
layout(std140, binding = 0) uniform BlendParams {
  mat4 u_world_from_cam;
  vec4 u_intrinsics;  // new view: fx, fy, cx, cy in pixels of the target
  vec4 u_sphere;      // background sphere: centre (world), radius
  // Background plane (BACKGROUND 3, world): n . X + offset = 0 with the cameras on the side n
  // points to; its in-plane axes u, v (xyz); its extent (u min, u max, v min, v max).
  vec4 u_plane;
  vec4 u_plane_u;
  vec4 u_plane_v;
  vec4 u_plane_extent;
  ivec2 u_size;  // target size in pixels
  // CUBIC: the full-size photo array's size in texels (with a cache, its slots of every size
  // share its texture coordinates, and a cache may have no full-size slot to ask
  // textureSize of).
  vec2 u_photo_texels;
  int u_active_count;
  float u_lambda;           // a photo counts when N . V_k > lambda (paper eq. 3)
  float u_tolerance;        // shadow-map test: relative depth tolerance
  float u_inv_scene_scale;  // 1 / the scene's scale (eq. 4's unit)
  int u_debug_photo;        // photo whose normalised weight goes to aux.g, -1 none
  float u_filter;           // FILTERED: relative depth uncertainty along the view's ray
  float u_outlier_scale;    // OUTLIER: colour distance at which a weight halves
  float u_refine;           // REFINE: half-range of the depth search, share of the view depth
};

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
// 1: one reweighting step of the per-pixel list: each photo's weight is divided by
// 1 + (|c_k - m| / u_outlier_scale)^2, m the weighted mean of the photos' stored values.
#ifndef OUTLIER
#define OUTLIER 0
#endif
// 1: photo-consistent depth (RefineDepth): each point moves along the view's ray, within
// +-u_refine of its view depth, to where its ranked photos agree best.
#ifndef REFINE
#define REFINE 0
#endif
// Filtered blending (Eisemann et al. 2007, sec. 4), defined or not: a program of its own (the
// unused taps would slow the others on llvmpipe).

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
