// Pull-push texels (Marroquim et al. 2007, as used by Lechelek et al. 2019 sec. 4, step 3).
// Texel a = (camera-space position of the splat centre, splat radius in level-0 pixels),
// texel b = (camera-space normal, weight); weight 0 = empty.
#include "camera.glsl"

struct Texel {
  vec4 a;
  vec4 b;
};

bool Valid(Texel t) { return t.b.w > 0.0; }

// Half-width of a texel's depth interval: its splat radius in world units.
float DepthHalfWidth(Texel t) { return t.a.w * t.a.z / u_intrinsics.y; }

// Averages up to 4 texels, keeping only those whose depth interval overlaps the nearest one's
// (so a back surface never mixes with a front one). The radius of the result bounds the
// kept splats.
Texel Average(Texel t[4], float wt[4]) {
  int nearest = -1;
  for (int i = 0; i < 4; ++i) {
    if (wt[i] > 0.0 && (nearest < 0 || t[i].a.z < t[nearest].a.z)) nearest = i;
  }
  Texel r;
  r.a = vec4(0.0);
  r.b = vec4(0.0);
  if (nearest < 0) return r;
  float limit = t[nearest].a.z + DepthHalfWidth(t[nearest]);
  vec3 p = vec3(0.0);
  vec3 n = vec3(0.0);
  float sw = 0.0;
  bool keep[4];
  for (int i = 0; i < 4; ++i) {
    keep[i] = wt[i] > 0.0 && t[i].a.z - DepthHalfWidth(t[i]) <= limit;
    if (!keep[i]) continue;
    p += wt[i] * t[i].a.xyz;
    n += wt[i] * t[i].b.xyz;
    sw += wt[i];
  }
  p /= sw;
  vec2 c = PixelFromCam(p);
  float radius = 0.0;
  for (int i = 0; i < 4; ++i) {
    if (keep[i]) radius = max(radius, length(PixelFromCam(t[i].a.xyz) - c) + t[i].a.w);
  }
  float ln = length(n);
  r.a = vec4(p, radius);
  r.b = vec4(ln > 1e-6 ? n / ln : t[nearest].b.xyz, sw);
  return r;
}

// Push (Marroquim et al. 2007) into fine texel f of level l (fine_scale = 2^l level-0 pixels
// per texel): the bilinear, depth-grouped average of the 4 nearest level l+1 texels whose
// splat ellipse covers the texel centre. Coarse texel i is PushBase(f) + (i & 1, i >> 1),
// clamped to the coarse level by the caller.
ivec2 PushBase(ivec2 f) { return ivec2(floor((vec2(f) + 0.5) * 0.5 - 0.5)); }

Texel PushAverage(Texel t[4], ivec2 f, float fine_scale) {
  vec2 centre = (vec2(f) + 0.5) * fine_scale;  // level-0 pixels
  vec2 g = (vec2(f) + 0.5) * 0.5 - 0.5;
  vec2 fr = g - floor(g);
  float wt[4];
  for (int i = 0; i < 4; ++i) {
    ivec2 o = ivec2(i & 1, i >> 1);
    float w = (o.x == 1 ? fr.x : 1.0 - fr.x) * (o.y == 1 ? fr.y : 1.0 - fr.y) + 1e-4;
    bool covers = Valid(t[i]) && InsideEllipse(centre - PixelFromCam(t[i].a.xyz),
                                               t[i].a.w + 0.5 * fine_scale,
                                               EllipseAxes(t[i].b.xyz, t[i].a.xyz));
    wt[i] = covers ? w : 0.0;
  }
  return Average(t, wt);
}
