#version 450 core
// Viewer debug displays of the renderer's per-pixel outputs (the same pictures as
// render::FalseColour on the CPU, `hdribr render --debug`): depth with the turbo map over the
// valid range (near = red end), camera-space normals as n / 2 + 1/2, the contributing-photo
// count with the turbo map over [0, photos], and the front/back classes of the depth pass
// (Lechelek et al. 2019 sec. 4 step 2: front points, back pixels filled by pull-push) in two
// colours. Pixels without depth are 0 with alpha 0.
layout(local_size_x = 16, local_size_y = 16) in;

layout(binding = 0, r32f) readonly uniform image2D u_depth;     // camera z, 0 = invalid
layout(binding = 1, rgba16f) readonly uniform image2D u_normal;  // camera-space unit normal
layout(binding = 2, rgba32f) readonly uniform image2D u_aux;     // r = contributing count
layout(binding = 3) writeonly uniform image2D u_display;          // RGBA8
layout(binding = 4, r8ui) readonly uniform uimage2D u_classes;  // 0 invalid, 1 front, 2 filled
layout(std430, binding = 0) readonly buffer Range { uint range_lo; uint range_hi; };
layout(binding = 0) uniform sampler2D u_turbo;  // 256 x 1 RGBA8: OpenCV's COLORMAP_TURBO, RGB
uniform int u_map;         // 0 depth, 1 normals, 2 count, 3 classes
uniform float u_count_hi;  // photos in the scene

// The LUT entry of t in [0, 1], rounded like render::FalseColour (t * 255 + 0.5).
vec3 Turbo(float t) {
  int i = int(clamp(t, 0.0, 1.0) * 255.0 + 0.5);
  return texelFetch(u_turbo, ivec2(i, 0), 0).rgb;
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(u_depth)))) return;
  float z = imageLoad(u_depth, p).r;
  if (!(z > 0.0)) {
    imageStore(u_display, p, vec4(0.0));
    return;
  }
  vec3 rgb;
  if (u_map == 0) {
    float lo = uintBitsToFloat(range_lo), hi = uintBitsToFloat(range_hi);
    float span = hi > lo ? hi - lo : 1.0;
    rgb = Turbo((hi - z) / span);
  } else if (u_map == 1) {
    rgb = clamp(imageLoad(u_normal, p).xyz * 0.5 + 0.5, 0.0, 1.0);
  } else if (u_map == 2) {
    rgb = Turbo(imageLoad(u_aux, p).r / max(1.0, u_count_hi));
  } else {
    // The legend in the viewer's panel uses the same colours (app.cc, kClassColours).
    uint c = imageLoad(u_classes, p).r;
    rgb = c == 1u ? vec3(1.0, 0.55, 0.1) : c == 2u ? vec3(0.2, 0.45, 1.0) : vec3(0.5);
  }
  imageStore(u_display, p, vec4(rgb, 1.0));
}
