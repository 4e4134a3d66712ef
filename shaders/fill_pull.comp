#version 450 core
// Pull of the colour fill (Gortler et al. 1996, "The Lumigraph", sec. 3.3): texel of level l+1
// = weighted mean of its 2x2 children in level l, its weight min(1, the sum of theirs). In the
// colour target (level 0) only the pixels blended from photos (alpha 1) count, with weight 1.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0, rgba32f) readonly uniform image2D u_fine;
layout(binding = 1, rgba32f) writeonly uniform image2D u_coarse;
layout(location = 0) uniform bool u_fine_is_target;

void main() {
  ivec2 c = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(c, imageSize(u_coarse)))) return;
  ivec2 fine_size = imageSize(u_fine);
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (int i = 0; i < 4; ++i) {
    ivec2 f = 2 * c + ivec2(i & 1, i >> 1);
    if (any(greaterThanEqual(f, fine_size))) continue;
    vec4 t = imageLoad(u_fine, f);
    float w = u_fine_is_target ? (t.a == 1.0 ? 1.0 : 0.0) : t.a;
    sum += w * t.rgb;
    weight += w;
  }
  imageStore(u_coarse, c, weight > 0.0 ? vec4(sum / weight, min(1.0, weight)) : vec4(0.0));
}
