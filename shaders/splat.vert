#version 450 core
// Step 1 of the depth pass (Lechelek et al. 2019, sec. 4): each point as a sprite of size
// 2 r_proj, r_proj = r fy / z (pinhole).
#include "camera.glsl"
#include "points.glsl"

flat out vec3 v_p_cam;
flat out vec3 v_n_cam;
flat out float v_r_px;
flat out vec2 v_center_px;

void main() {
  vec3 p = (u_cam_from_world * vec4(a_position, 1.0)).xyz;
  v_p_cam = p;
  v_n_cam = FacingNormal(mat3(u_cam_from_world) * a_normal, p);
  gl_Position = PointClipPosition(p);
  float z = max(p.z, 1e-6);
  v_r_px = a_radius * u_intrinsics.y / z;
  v_center_px = PixelFromCam(vec3(p.xy, z));
  gl_PointSize = clamp(2.0 * v_r_px, 1.0, u_max_point_size);
}
