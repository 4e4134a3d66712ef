// Point attributes of the depth pass (render/point_buffer.h): world position, world normal
// (zero when absent) and splat radius in world units.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_radius;

// Camera z range (near, far) of the draw: the clip range given to ClipFromCam().
layout(location = 9) uniform vec2 u_depth_range;

// Clip position of a camera-space point drawn as a GL_POINTS sprite: x, y and w as
// u_clip_from_cam, z linear in camera z over u_depth_range. The perspective depth with
// near = far * 1e-5 resolves only about 0.6% of far in a float depth buffer; the linear one
// about 1e-7. Exact for points: every fragment of a sprite takes its vertex's depth.
vec4 PointClipPosition(vec3 p) {
  vec4 c = u_clip_from_cam * vec4(p, 1.0);
  c.z = (2.0 * (p.z - u_depth_range.x) / (u_depth_range.y - u_depth_range.x) - 1.0) * c.w;
  return c;
}
