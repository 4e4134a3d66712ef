#version 450 core
// Level 0 of pull-push (Marroquim et al. 2007) rasterised in a compute shader, one invocation
// per point: every point projected to the pixel holding its centre, the nearest per pixel
// kept. STAGE 1 keeps the nearest depth by an image atomicMin; STAGE 2 lets the point holding
// it write the texel (camera position, radius in pixels; facing normal, weight 1); points at
// exactly equal depth on one pixel may both write. With CLASSIFY (step 2 of Lechelek et al.
// 2019) front points go to layer 0 and back points to layer 1, a point being front when its
// depth is within a tolerance of the step-1 depth at its centre pixel (as project.vert);
// without, every point goes to layer 0.
layout(local_size_x = 64) in;
#include "camera.glsl"
#include "points_buffer.glsl"
#include "splat_depth.glsl"

#if CLASSIFY
#include "classify.glsl"
layout(binding = 0) uniform usampler2D u_splat_depth;
#endif
#if STAGE == 1
layout(binding = 0, r32ui) uniform uimage2DArray u_nearest;
#else
layout(binding = 0, r32ui) readonly uniform uimage2DArray u_nearest;
layout(binding = 1, rgba32f) writeonly uniform image2DArray u_a;
layout(binding = 2, rgba32f) writeonly uniform image2DArray u_b;
#endif

void main() {
  int i = PointIndex();
  if (i < 0) return;
  Point point = LoadPoint(i);
  vec3 p = (u_cam_from_world * vec4(point.position, 1.0)).xyz;
  if (p.z <= u_near) return;
  vec2 c = PixelFromCam(p);
  if (!(all(greaterThanEqual(c, vec2(0.0))) && all(lessThan(c, u_size)))) return;
  ivec2 texel = ivec2(floor(c));
  int layer = 0;
#if CLASSIFY
  float z1 = DecodeSplatDepth(texelFetch(u_splat_depth, texel, 0).r);
  layer = IsFront(p.z, point.radius, z1) ? 0 : 1;
#endif
  ivec3 t = ivec3(texel, layer);
  uint bits = EncodeSplatDepth(p.z);
#if STAGE == 1
  imageAtomicMin(u_nearest, t, bits);
#else
  if (imageLoad(u_nearest, t).r != bits) return;
  vec3 n = FacingNormal(mat3(u_cam_from_world) * point.normal, p);
  imageStore(u_a, t, vec4(p, point.radius * u_intrinsics.y / p.z));
  imageStore(u_b, t, vec4(n, 1.0));
#endif
}
