#version 450 core
// Blend pass for the pixels without depth, listed by blend.comp (which blends those with a
// point; on a CPU rasteriser a pass over every pixel would pay for this code in all): each is
// placed on the plane of the surface around it (EnclosedDepth), or inside a hollow at the depth
// where the photos agree, or on the background (BACKGROUND: the scene's dominant plane, a
// sphere around the scene or a surface at infinity), seen by the photos whose depth maps hold
// no point there either; where no photo passes, on the surface that the photos' depth maps
// hold along the pixel's ray (HoleDepth), and where none does, at the depth along it where the
// photos agree (SweepDepth). Docs: docs/algorithms/blend.md.
layout(local_size_x = 64) in;

#include "blend_common.glsl"
#include "blend_visibility.glsl"
#include "blend_sampling.glsl"
#include "blend_refine.glsl"
#include "blend_pixel.glsl"
#include "blend_holes.glsl"

void main() {
  if (gl_GlobalInvocationID.x >= hole_count) return;
  uint xy = hole_pixels[gl_GlobalInvocationID.x];
  ivec2 p = ivec2(xy & 0xffffu, xy >> 16);
  vec4 color = vec4(0.0);
  vec4 aux = vec4(0.0);
  float z = 0.0;
  vec3 ray = vec3((vec2(p) + 0.5 - u_intrinsics.zw) / u_intrinsics.xy, 1.0);
  vec3 C = u_world_from_cam[3].xyz;
  Sample s;
  s.background = true;
  s.at_infinity = BACKGROUND == 1;
  vec3 ray_world = mat3(u_world_from_cam) * ray;
  float z_surface = BACKGROUND >= 2 ? SurfaceDepth(C, ray_world) : 0.0;
  vec2 span = vec2(0.0);  // inverse depths of the surface around a hole (EnclosedDepth)
  float z_plane = BACKGROUND != 0 ? EnclosedDepth(p, span) : 0.0;
  if (BACKGROUND >= 2) z = z_surface;
  if (z_plane > 0.0) {
    z = z_plane;
    s.at_infinity = false;
  }
#if BACKGROUND == 0
  // Without a background, a pixel without depth can still lie on a surface that the photos'
  // depth maps hold along its ray (a hole of the view's geometry; ranked as a direction).
  s.at_infinity = true;
  PlaceAtInfinity(s, ray_world);
  int hole_ids[kRankPhotos];
  RankByPenalty(s, hole_ids);
  z = HoleDepth(hole_ids, C, ray_world, 0.0);
  s.at_infinity = false;
  s.background = z <= 0.0;
#endif
  if (z > 0.0 || s.at_infinity) {
    if (s.at_infinity) {
      PlaceAtInfinity(s, ray_world);
    } else {
      PlaceAt(s, C, C + z * ray_world, z);
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
      // A marched sample (on a photo's surface) that no photo passes stays empty.
      if (BlendSample(s, C, ray_world, color, aux) || !s.background || fallback == 2) break;
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
