// The point cloud as a shader storage buffer for the compute rasterisation of the depth pass
// (render/point_buffer.h: 8 floats per point: world position, world normal (zero when
// absent), splat radius in world units, padding).
layout(std430, binding = 0) readonly buffer Points { float b_points[]; };
layout(location = 8) uniform uint u_point_count;

// Index of this invocation's point (2D dispatch: more than 65535 groups of points), or -1.
int PointIndex() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x +
           gl_GlobalInvocationID.x;
  return i < u_point_count ? int(i) : -1;
}

vec3 PointPosition(int i) {
  return vec3(b_points[8 * i], b_points[8 * i + 1], b_points[8 * i + 2]);
}
vec3 PointNormal(int i) {
  return vec3(b_points[8 * i + 3], b_points[8 * i + 4], b_points[8 * i + 5]);
}
float PointRadius(int i) { return b_points[8 * i + 6]; }

// Camera z at or below which a point is dropped (the graphics pipeline's near plane).
layout(location = 9) uniform float u_near;
