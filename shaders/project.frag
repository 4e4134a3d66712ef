#version 450 core
// Writes the pull-push level-0 texel of a projected point: (camera position, radius in
// pixels) and (facing normal, weight 1).
flat in vec3 v_p_cam;
flat in vec3 v_n_cam;
flat in float v_r_px;

layout(location = 0) out vec4 o_a;
layout(location = 1) out vec4 o_b;

void main() {
  o_a = vec4(v_p_cam, v_r_px);
  o_b = vec4(v_n_cam, 1.0);
}
