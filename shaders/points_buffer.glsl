// The point cloud as a shader storage buffer for the compute rasterisation of the depth pass
// (render/point_buffer.h: 8 floats per point: world position, world normal (zero when
// absent), splat radius in world units, padding).
layout(std430, binding = 0) readonly buffer Points { vec4 b_points[]; };
layout(location = 8) uniform uint u_point_count;

// Index of this invocation's point (2D dispatch: more than 65535 groups of points), or -1.
int PointIndex() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x +
           gl_GlobalInvocationID.x;
  return i < u_point_count ? int(i) : -1;
}

// A point's two vec4 (fewer, wider loads than eight floats): (position, normal.x) and
// (normal.yz, radius, padding).
struct Point {
  vec3 position;
  vec3 normal;
  float radius;
};

Point LoadPoint(int i) {
  vec4 u = b_points[2 * i], v = b_points[2 * i + 1];
  return Point(u.xyz, vec3(u.w, v.xy), v.z);
}

// Camera z at or below which a point is dropped (the graphics pipeline's near plane).
layout(location = 9) uniform float u_near;
