#version 450 core
// Step 1: discard fragments outside the projected ellipse; depth is constant over a splat
// (the centre's), as in the paper. Outputs camera z (encoded, splat_depth.glsl) and
// (normal, coverage = 1).
#include "camera.glsl"
#include "splat_depth.glsl"

flat in vec3 v_p_cam;
flat in vec3 v_n_cam;
flat in float v_r_px;
flat in vec2 v_center_px;

layout(location = 0) out uint o_depth;
layout(location = 1) out vec4 o_normal;

void main() {
  vec2 d = gl_FragCoord.xy - v_center_px;
  // The pixel holding the centre is always covered, so tiny splats never vanish.
  bool centre_pixel = abs(d.x) <= 0.5 && abs(d.y) <= 0.5;
  if (!centre_pixel && !InsideEllipse(d, v_r_px, EllipseAxes(v_n_cam, v_p_cam))) discard;
  o_depth = EncodeSplatDepth(v_p_cam.z);
  o_normal = vec4(v_n_cam, 1.0);
}
