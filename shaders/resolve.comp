#version 450 core
// Final depth, normal and validity of the depth pass.
//  MODE 0 (plain):     the step-1 splats as they are.
//  MODE 1 (marroquim): pull-push of all points; depth on the tangent plane of the texel.
//  MODE 2 (lechelek):  steps 4-5 of Lechelek et al. 2019 sec. 4: only pixels covered by
//                      step-1 splats; foreground pull-push where valid, background filling
//                      the foreground's holes, the step-1 splat depth (and a view-facing
//                      normal: step 1 writes no normal in this mode) as a last resort. MODE 2
//                      writes the foreground, or the last resort at the foreground's holes,
//                      which it appends to a list for MODE 3. With u_trim_radius > 0 it
//                      first trims the front splats' overhang past silhouettes (TrimOverhang).
//  MODE 3 (lechelek holes): one invocation per listed pixel (an indirect dispatch sized by
//                      MODE 2): the background's level-0 texel, else its last push (level 1
//                      to 0, u_push_back; the pyramid is pushed only down to level 1); where
//                      that gives a texel, it replaces the last resort. A separate pass
//                      because a CPU rasteriser (llvmpipe) runs both sides of a branch for a
//                      whole SIMD vector: inline, the rarely needed background reads and push
//                      cost every pixel.
#if MODE == 3
layout(local_size_x = 64) in;  // kHoleGroupSize
#else
layout(local_size_x = 8, local_size_y = 8) in;
#endif
#include "pullpush.glsl"
#include "splat_depth.glsl"

#ifndef MODE
#define MODE 2
#endif
#if MODE == 2
#include "classify.glsl"
#endif

layout(binding = 0) uniform usampler2D u_splat_depth;  // splat_depth.glsl
layout(binding = 1) uniform sampler2D u_splat_normal;  // w = coverage (plain only)
layout(binding = 2) uniform sampler2D u_front_a;
layout(binding = 3) uniform sampler2D u_front_b;
layout(binding = 4) uniform sampler2D u_back_a;
layout(binding = 5) uniform sampler2D u_back_b;
layout(binding = 6) uniform sampler2D u_back1_a;  // level 1 of the background pyramid
layout(binding = 7) uniform sampler2D u_back1_b;
layout(location = 7) uniform int u_push_back;     // 1: level 0 of u_back_* is not pushed yet
layout(location = 8) uniform int u_trim_radius;   // MODE 2: silhouette trim window, 0 = off

layout(binding = 0, r32f) writeonly uniform image2D u_out_depth;
layout(binding = 1, rgba16f) writeonly uniform image2D u_out_normal;
layout(binding = 2, r8) writeonly uniform image2D u_out_valid;
// Pixel class (render::DepthClass): 0 invalid, 1 front, 2 background filling a foreground hole.
layout(binding = 3, r8ui) writeonly uniform uimage2D u_out_class;

#if MODE >= 2
// Pixels of foreground holes (x | y << 16) and the indirect dispatch arguments of MODE 3
// (render/depth_pass.cc resets them to (0, 1, 1) and count 0 every frame).
layout(std430, binding = 0) buffer Holes {
  uint h_groups_x;
  uint h_groups_y;
  uint h_groups_z;
  uint h_count;
  uint h_pixels[];
};
const uint kHoleGroupSize = 64u;  // local_size_x of MODE 3
const uint kMaxGroups = 65535u;
#endif

// Depth of a pull-push texel at pixel px: its tangent plane, within its depth interval.
float TexelDepth(Texel t, vec2 px) { return PlaneDepth(t.a.xyz, t.b.xyz, px, DepthHalfWidth(t)); }

#if MODE == 3
void main() {
  // Grid-stride loop: the dispatch is capped at kMaxGroups groups.
  uint stride = gl_NumWorkGroups.x * kHoleGroupSize;
  for (uint k = gl_GlobalInvocationID.x; k < h_count; k += stride) {
    ivec2 p = ivec2(h_pixels[k] & 0xFFFFu, h_pixels[k] >> 16);
    Texel back;
    back.a = texelFetch(u_back_a, p, 0);
    back.b = texelFetch(u_back_b, p, 0);
    if (!Valid(back) && u_push_back != 0) {
      ivec2 base = PushBase(p);
      ivec2 coarse_size = textureSize(u_back1_a, 0);
      Texel t[4];
      for (int i = 0; i < 4; ++i) {
        ivec2 c = clamp(base + ivec2(i & 1, i >> 1), ivec2(0), coarse_size - 1);
        t[i].a = texelFetch(u_back1_a, c, 0);
        t[i].b = texelFetch(u_back1_b, c, 0);
      }
      back = PushAverage(t, p, 1.0);
    }
    if (!Valid(back)) continue;
    imageStore(u_out_depth, p, vec4(TexelDepth(back, vec2(p) + 0.5)));
    imageStore(u_out_normal, p, vec4(normalize(back.b.xyz), 0.0));
    imageStore(u_out_class, p, uvec4(2u));
  }
}
#else
#if MODE == 2
// Depth of a step-1 pinhole: a pixel that no splat covers but whose 8 neighbours all are, but
// for at most one, lies in a gap between the splats of one surface (their radii, from the
// mean spacing of the nearest points, leave rare gaps where the points are sparsest), not
// between two surfaces; it counts as covered, with the nearest neighbouring splat depth as
// its last resort. 0 for any other pixel.
float PinholeDepth(ivec2 p) {
  int missing = 0;
  float nearest = 0.0;
  for (int i = 0; i < 9; ++i) {
    if (i == 4) continue;  // p itself
    ivec2 q = p + ivec2(i % 3 - 1, i / 3 - 1);
    float d = all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, ivec2(u_size)))
                  ? DecodeSplatDepth(texelFetch(u_splat_depth, q, 0).r)
                  : 0.0;
    if (d > 0.0) {
      nearest = nearest > 0.0 ? min(nearest, d) : d;
    } else {
      ++missing;
    }
  }
  return missing <= 1 ? nearest : 0.0;
}

// Silhouette trim. A foreground pixel that no front point centre holds (its texel was pushed)
// may lie in the overhang of the front splats past a silhouette: the step-1 splats and the
// pushed foreground reach a splat radius past the last sample, and the points of the farther
// surface under that band were classified back. The true silhouette lies between the last
// samples of the two visible surfaces: the pixel is given to the farther surface when, among
// the front point centres within u_trim_radius pixels, the nearest lies on a farther surface
// (deeper than the pixel's foreground depth z by the tolerance of step 2) rather than on the
// pixel's own, step 1 shows that farther surface at its centre, and step 1 does not show the
// pixel's own surface again u_trim_radius pixels past it (which marks a gap between the
// splats of one surface, not its edge). Returns that farther centre's texel (whose tangent
// plane gives the pixel's depth), or an invalid texel.
Texel TrimOverhang(ivec2 p, float z) {
  vec2 px = vec2(p) + 0.5;
  float own = 1e30, other = 1e30;
  vec2 towards = vec2(0.0);
  Texel far_texel;
  far_texel.a = vec4(0.0);
  far_texel.b = vec4(0.0);
  ivec2 lo = max(p - u_trim_radius, ivec2(0));
  ivec2 hi = min(p + u_trim_radius, ivec2(u_size) - 1);
  for (int y = lo.y; y <= hi.y; ++y) {
    for (int x = lo.x; x <= hi.x; ++x) {
      Texel t;
      t.b = texelFetch(u_front_b, ivec2(x, y), 0);
      if (t.b.w < 0.5) continue;  // empty or pushed: no point centre here
      t.a = texelFetch(u_front_a, ivec2(x, y), 0);
      vec2 d = PixelFromCam(t.a.xyz) - px;
      float d2 = dot(d, d);
      if (!IsFront(t.a.z, DepthHalfWidth(t), z)) {
        if (d2 < other) {
          other = d2;
          towards = d;
          far_texel = t;
        }
      } else if (t.a.z >= z - u_front_radii * DepthHalfWidth(t) - u_front_rel * z) {
        own = min(own, d2);
      }
    }
  }
  bool trim = other < own;
  if (trim) {
    vec2 c = px + towards;
    float z_c = DecodeSplatDepth(texelFetch(u_splat_depth, ivec2(c), 0).r);
    ivec2 q = ivec2(floor(c + normalize(towards) * float(u_trim_radius)));
    float z_q = all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, ivec2(u_size)))
                    ? DecodeSplatDepth(texelFetch(u_splat_depth, q, 0).r)
                    : 0.0;
    float r = DepthHalfWidth(far_texel);
    trim = z_c > 0.0 && !IsFront(z_c, r, z) && (z_q <= 0.0 || !IsFront(z_q, r, z));
  }
  if (!trim) far_texel.b = vec4(0.0);
  return far_texel;
}
#endif

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, ivec2(u_size)))) return;
  vec2 px = vec2(p) + 0.5;
  float depth = 0.0;
  vec3 normal = vec3(0.0);
  uint cls = 1u;  // front unless the background fills the pixel (step 5)
  float splat_depth = DecodeSplatDepth(texelFetch(u_splat_depth, p, 0).r);
#if MODE == 0
  vec4 splat_normal = texelFetch(u_splat_normal, p, 0);
  if (splat_normal.w > 0.0) {
    depth = splat_depth;
    normal = splat_normal.xyz;
  }
#else
  Texel front;
  front.a = texelFetch(u_front_a, p, 0);
  front.b = texelFetch(u_front_b, p, 0);
#if MODE == 1
  if (Valid(front)) {
    depth = TexelDepth(front, px);
    normal = front.b.xyz;
  }
#else
  if (splat_depth <= 0.0) splat_depth = PinholeDepth(p);
  if (splat_depth > 0.0) {
    if (Valid(front)) {
      depth = TexelDepth(front, px);
      normal = front.b.xyz;
      if (u_trim_radius > 0 && front.b.w < 0.5) {
        Texel far_texel = TrimOverhang(p, depth);
        if (Valid(far_texel)) {
          depth = TexelDepth(far_texel, px);
          normal = far_texel.b.xyz;
        }
      }
    } else {
      uint k = atomicAdd(h_count, 1u);
      if (k % kHoleGroupSize == 0u && k / kHoleGroupSize < kMaxGroups) {
        atomicAdd(h_groups_x, 1u);
      }
      h_pixels[k] = uint(p.x) | uint(p.y) << 16;
      depth = splat_depth;
      normal = -normalize(RayThroughPixel(px));
    }
  }
#endif
#endif
  bool valid = depth > 0.0;
  imageStore(u_out_depth, p, vec4(valid ? depth : 0.0));
  imageStore(u_out_normal, p, vec4(valid ? normalize(normal) : vec3(0.0), 0.0));
  imageStore(u_out_valid, p, vec4(valid ? 1.0 : 0.0));
  imageStore(u_out_class, p, uvec4(valid ? cls : 0u));
}
#endif
