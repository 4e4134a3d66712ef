#version 450 core
// Frustum lines hidden by the scene: a fragment farther than the depth pass's camera z at its
// pixel (beyond a relative tolerance) is discarded; pixels without scene depth show the line.
// The current photo gets the highlight colour, the renderer's candidate photos their own.
layout(binding = 0) uniform sampler2D u_scene_depth;  // R32F camera z, 0 = none; rows top first
layout(location = 2) uniform float u_tolerance;       // relative depth
layout(location = 3) uniform int u_highlight;         // photo drawn in the highlight colour
layout(location = 4) uniform vec4 u_colour;
layout(location = 5) uniform vec4 u_highlight_colour;
layout(location = 6) uniform vec4 u_candidate_colour;
layout(location = 7) uniform int u_flag_count;
layout(std430, binding = 0) readonly buffer Candidates { int candidate[]; };  // 1 per photo

in float v_z;
flat in int v_photo;
layout(location = 0) out vec4 o_colour;

void main() {
  float scene_z = texelFetch(u_scene_depth, ivec2(gl_FragCoord.xy), 0).r;
  if (scene_z > 0.0 && v_z > scene_z * (1.0 + u_tolerance)) discard;
  bool is_candidate = v_photo < u_flag_count && candidate[v_photo] != 0;
  o_colour = v_photo == u_highlight ? u_highlight_colour
             : is_candidate        ? u_candidate_colour
                                   : u_colour;
}
