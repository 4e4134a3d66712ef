// Shared camera uniforms and splat geometry for the depth pass (Lechelek et al. 2019, sec. 4).
// Camera space is COLMAP's: x right, y down, z forward; pixel positions are COLMAP's (the
// centre of the top-left pixel is (0.5, 0.5)), equal to gl_FragCoord.xy under the render
// layer's glClipControl(GL_UPPER_LEFT, ...).
layout(location = 0) uniform mat4 u_cam_from_world;
layout(location = 1) uniform mat4 u_clip_from_cam;  // ClipFromCam() in core/projection.h
layout(location = 2) uniform vec4 u_intrinsics;     // fx, fy, cx, cy in pixels of the target
layout(location = 3) uniform vec2 u_size;           // target size in pixels
layout(location = 4) uniform float u_max_point_size;

// Smallest ratio of the ellipse's minor to major axis (|N_z| at grazing views would make the
// splat vanish).
const float kMinAxisRatio = 0.2;

// Pixel position of a camera-space point.
vec2 PixelFromCam(vec3 p) { return u_intrinsics.xy * p.xy / p.z + u_intrinsics.zw; }

// Camera-space ray with z = 1 through a pixel position.
vec3 RayThroughPixel(vec2 px) { return vec3((px - u_intrinsics.zw) / u_intrinsics.xy, 1.0); }

// Normal facing the camera; points without a normal (zero vector) become view-facing discs.
vec3 FacingNormal(vec3 n, vec3 p) {
  if (dot(n, n) < 0.25) return -normalize(p);
  n = normalize(n);
  return dot(n, p) > 0.0 ? -n : n;
}

// Ellipse axes of a splat at camera position p with normal n, for InsideEllipse: xy = the
// normal's component across the view ray (the direction of the minor axis on screen), z =
// cosine between normal and view ray. The paper uses the eye-space N_z, which equals this on
// the optical axis; measuring along the view ray keeps view-facing splats round off-axis.
vec3 EllipseAxes(vec3 n, vec3 p) {
  vec3 v = normalize(p);
  float c = dot(n, v);
  return vec3((n - c * v).xy, c);
}

// True when offset d (pixels) from the splat centre lies inside the projected ellipse of a
// disc with axes n (EllipseAxes): semi-major axis r_px, semi-minor r_px |N_z| along the
// projected normal (paper sec. 4, step 1).
bool InsideEllipse(vec2 d, float r_px, vec3 n) {
  float la = length(n.xy);
  if (la < 1e-4) return dot(d, d) <= r_px * r_px;
  vec2 a = n.xy / la;
  float along = dot(d, a);
  float across = dot(d, vec2(-a.y, a.x));
  float minor = r_px * max(abs(n.z), kMinAxisRatio);
  return (across * across) / (r_px * r_px) + (along * along) / (minor * minor) <= 1.0;
}

// Depth (camera z) where the ray through pixel px meets the plane through p with normal n;
// p.z when the plane is seen at a grazing angle or the hit strays beyond max_dz.
float PlaneDepth(vec3 p, vec3 n, vec2 px, float max_dz) {
  vec3 ray = RayThroughPixel(px);
  float denom = dot(n, ray);
  if (abs(denom) < 0.25 * length(ray)) return p.z;
  float z = dot(n, p) / denom;
  return abs(z - p.z) <= max_dz ? z : p.z;
}
