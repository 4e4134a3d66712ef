#version 450 core
// Colour-per-point splatting, the baseline of Lechelek et al. 2019, Fig. 8: each point drawn as
// the depth pass's elliptical splat (sprite of size 2 r_proj, r_proj = r fy / z), carrying one
// colour. No pull-push and no blending: the nearest splat wins the depth test.
#include "camera.glsl"
#include "points.glsl"
layout(location = 3) in vec3 a_color;

flat out vec3 v_p_cam;
flat out vec3 v_n_cam;
flat out float v_r_px;
flat out vec2 v_center_px;
flat out vec3 v_color;

void main() {
  vec3 p = (u_cam_from_world * vec4(a_position, 1.0)).xyz;
  v_p_cam = p;
  v_n_cam = FacingNormal(mat3(u_cam_from_world) * a_normal, p);
  v_color = a_color;
  gl_Position = PointClipPosition(p);
  float z = max(p.z, 1e-6);
  v_r_px = a_radius * u_intrinsics.y / z;
  v_center_px = PixelFromCam(vec3(p.xy, z));
  gl_PointSize = clamp(2.0 * v_r_px, 1.0, u_max_point_size);
}
