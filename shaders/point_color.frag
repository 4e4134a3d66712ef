#version 450 core
// Colour-per-point splatting: fragments outside the projected ellipse are discarded (same test
// as step 1 of the depth pass); output = the point's colour, alpha 1 = covered.
#include "camera.glsl"

flat in vec3 v_p_cam;
flat in vec3 v_n_cam;
flat in float v_r_px;
flat in vec2 v_center_px;
flat in vec3 v_color;

layout(location = 0) out vec4 o_color;

void main() {
  vec2 d = gl_FragCoord.xy - v_center_px;
  bool centre_pixel = abs(d.x) <= 0.5 && abs(d.y) <= 0.5;
  if (!centre_pixel && !InsideEllipse(d, v_r_px, EllipseAxes(v_n_cam, v_p_cam))) discard;
  o_color = vec4(v_color, 1.0);
}
