#version 450 core
// Level 0 of pull-push (Marroquim et al. 2007): every point projected as one pixel, the
// nearest winning through the depth test. With CLASSIFY (step 2 of Lechelek et al. 2019), a
// point is front when its depth is within a tolerance of the step-1 depth at its centre pixel:
// CLASSIFY == 1 keeps front points, 2 back points, 3 sends front points to layer 0 and back
// points to layer 1 of a layered target in one draw (gl_Layer from the vertex shader).
#extension GL_ARB_shader_viewport_layer_array : enable
#include "camera.glsl"
#include "points.glsl"
#include "splat_depth.glsl"

#ifndef CLASSIFY
#define CLASSIFY 0
#endif

#if CLASSIFY != 0
#include "classify.glsl"
layout(binding = 0) uniform usampler2D u_splat_depth;  // step-1 depth (splat_depth.glsl)
#endif

flat out vec3 v_p_cam;
flat out vec3 v_n_cam;
flat out float v_r_px;

void main() {
  vec3 p = (u_cam_from_world * vec4(a_position, 1.0)).xyz;
  v_p_cam = p;
  v_n_cam = FacingNormal(mat3(u_cam_from_world) * a_normal, p);
  float z = max(p.z, 1e-6);
  v_r_px = a_radius * u_intrinsics.y / z;
  gl_Position = PointClipPosition(p);
  gl_PointSize = 1.0;
#if CLASSIFY != 0
  if (p.z > 0.0) {
    ivec2 texel = ivec2(floor(PixelFromCam(p)));
    bool inside = all(greaterThanEqual(texel, ivec2(0))) && all(lessThan(texel, ivec2(u_size)));
    float z1 = inside ? DecodeSplatDepth(texelFetch(u_splat_depth, texel, 0).r) : 0.0;
    bool front = IsFront(p.z, a_radius, z1);
#if CLASSIFY == 3
    gl_Layer = front ? 0 : 1;
#else
    if (front != (CLASSIFY == 1)) gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // clipped away
#endif
  }
#endif
}
