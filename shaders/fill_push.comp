#version 450 core
// Push of the colour fill (Gortler et al. 1996, sec. 3.3): a texel of level l with weight
// w < 1 becomes w * itself + (1 - w) * the bilinear interpolation of level l+1 (pushed before
// it, so complete wherever anything was pulled), weight 1. In the colour target (level 0) the
// empty pixels (alpha 0) take the interpolation with alpha FILLED_ALPHA.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0, rgba32f) uniform image2D u_fine;
layout(binding = 1, rgba32f) readonly uniform image2D u_coarse;
layout(location = 0) uniform bool u_fine_is_target;

void main() {
  ivec2 f = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(f, imageSize(u_fine)))) return;
  vec4 t = imageLoad(u_fine, f);
  float w = u_fine_is_target ? (t.a == 1.0 ? 1.0 : 0.0) : t.a;
  if (w >= 1.0) return;
  // The fine texel's centre in coarse texels, and its 4 nearest coarse texels.
  vec2 g = (vec2(f) + 0.5) * 0.5 - 0.5;
  ivec2 base = ivec2(floor(g));
  vec2 fr = g - floor(g);
  ivec2 coarse_size = imageSize(u_coarse);
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (int i = 0; i < 4; ++i) {
    ivec2 o = ivec2(i & 1, i >> 1);
    vec4 c = imageLoad(u_coarse, clamp(base + o, ivec2(0), coarse_size - 1));
    float b = (o.x == 1 ? fr.x : 1.0 - fr.x) * (o.y == 1 ? fr.y : 1.0 - fr.y) * c.a;
    sum += b * c.rgb;
    weight += b;
  }
  if (!(weight > 0.0)) return;
  vec3 pushed = sum / weight;
  if (u_fine_is_target) {
    imageStore(u_fine, f, vec4(pushed, FILLED_ALPHA));
  } else {
    imageStore(u_fine, f, vec4(w * t.rgb + (1.0 - w) * pushed, 1.0));
  }
}
