#version 450 core
// Step 1 of the depth pass (Lechelek et al. 2019, sec. 4) rasterised in a compute shader, one
// invocation per point, the nearest depth kept by an image atomicMin (compute rasterisation
// of points, as Schuetz et al. 2021 do): the same sprite of size 2 r_proj, r_proj = r fy / z,
// and ellipse as splat.vert/splat.frag (InsideEllipse in camera.glsl), so both paths cover
// the same pixels up to rounding on the ellipse's border. With
// WRITE_NORMAL (plain mode, a second dispatch once the depths are final) the splat holding a
// pixel's nearest depth writes its normal and coverage there.
layout(local_size_x = 64) in;
#include "camera.glsl"
#include "points_buffer.glsl"
#include "splat_depth.glsl"

#ifndef WRITE_NORMAL
#define WRITE_NORMAL 0
#endif

#if WRITE_NORMAL
layout(binding = 0, r32ui) readonly uniform uimage2D u_depth;
layout(binding = 1, rgba16f) writeonly uniform image2D u_normal;
#else
layout(binding = 0, r32ui) uniform uimage2D u_depth;
#endif

void main() {
  int i = PointIndex();
  if (i < 0) return;
  Point point = LoadPoint(i);
  vec3 p = (u_cam_from_world * vec4(point.position, 1.0)).xyz;
  if (p.z <= u_near) return;
  vec3 n = FacingNormal(mat3(u_cam_from_world) * point.normal, p);
  float r_px = point.radius * u_intrinsics.y / p.z;
  vec2 c = PixelFromCam(p);
  float half_size = 0.5 * clamp(2.0 * r_px, 1.0, u_max_point_size);
  // The ellipse of InsideEllipse as a quadratic form d^T Q d <= 1 (Q = a a^T / minor^2 +
  // (I - a a^T) / r^2, a the unit minor-axis direction), evaluated once per point; its
  // bounding box (half extents sqrt of the diagonal of Q^-1) bounds the pixel loop.
  vec3 axes = EllipseAxes(n, p);
  float la = length(axes.xy);
  vec2 a = la < 1e-4 ? vec2(1.0, 0.0) : axes.xy / la;
  float minor = la < 1e-4 ? r_px : r_px * max(abs(axes.z), kMinAxisRatio);
  float inv_r2 = 1.0 / (r_px * r_px), inv_m2 = 1.0 / (minor * minor);
  mat2 q = mat2(inv_r2) + (inv_m2 - inv_r2) * outerProduct(a, a);
  vec2 extent = sqrt(r_px * r_px + (minor * minor - r_px * r_px) * a * a);
  // Pixels whose centre lies in the sprite's square and the ellipse's box, plus the centre
  // pixel (clamped before the conversion to int).
  vec2 box = max(min(vec2(half_size), extent), vec2(0.5));
  vec2 lo = clamp(ceil(c - box - 0.5), vec2(0.0), u_size);
  vec2 hi = clamp(floor(c + box - 0.5), vec2(-1.0), u_size - 1.0);
  if (any(isnan(lo)) || any(isnan(hi))) return;
  uint bits = EncodeSplatDepth(p.z);
  for (int y = int(lo.y); y <= int(hi.y); ++y) {
    for (int x = int(lo.x); x <= int(hi.x); ++x) {
      vec2 d = vec2(x, y) + 0.5 - c;
      // The pixel holding the centre is always covered, so tiny splats never vanish.
      bool centre_pixel = abs(d.x) <= 0.5 && abs(d.y) <= 0.5;
      if (!centre_pixel && (any(greaterThan(abs(d), vec2(half_size))) || dot(d, q * d) > 1.0)) {
        continue;
      }
#if WRITE_NORMAL
      if (imageLoad(u_depth, ivec2(x, y)).r == bits) {
        imageStore(u_normal, ivec2(x, y), vec4(n, 1.0));
      }
#else
      // A plain load first: most covered pixels already hold a nearer splat, and an atomic
      // costs more than a load.
      if (bits < imageLoad(u_depth, ivec2(x, y)).r) imageAtomicMin(u_depth, ivec2(x, y), bits);
#endif
    }
  }
}
