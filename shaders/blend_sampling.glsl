// Blend pass, how a photo is read at a sample's projection: trilinear or Catmull-Rom, through
// the photo cache's slots, low-passed (filtered blending), in display values or radiance.
// Docs: docs/algorithms/blend.md.

const float kCubicMaxLod = 0.5;  // CUBIC: coarser levels of detail are sampled trilinearly

// Photo i's stored value at uvl (texture coordinate, level of detail).
// A slot of 1 / 2^t of the full size holds levels t and coarser at the same texture
// coordinates: sampled at level of detail lod - t, it returns the full array's texels.
vec3 FetchPhoto(int i, vec3 uvl) {
  if (CACHED == 0) return textureLod(u_photos, vec3(uvl.xy, float(i)), uvl.z).rgb;
#if CACHED == 1
  int level = int(max(uvl.z, 0.0));  // trilinear reads this level and the next
  if (sampled_level[i] > level) atomicMin(sampled_level[i], level);
#endif
  int slot = slot_of[i];
  if (slot >= 0) {
    int tier = slot >> 24;
    vec3 at = vec3(uvl.xy, float(slot & 0xffffff));
    if (TIERS == 1 || tier == 0) return textureLod(u_photos, at, uvl.z).rgb;
    if (TIERS == 2 || tier == 1) return textureLod(u_tier1, at, uvl.z - 1.0).rgb;
    return textureLod(u_tier2, at, uvl.z - 2.0).rgb;
  }
  vec4 co = photos[i].coarse;
  return textureLod(u_coarse, vec3(min(uvl.xy * co.xy, co.zw), float(i)), uvl.z + photos[i].size.w)
      .rgb;
}

// Keys' cubic convolution weights (a = -0.5: Catmull-Rom) of the 4 texels at distances 1 + f,
// f, 1 - f and 2 - f from the sample.
vec4 CatmullRomWeights(float f) {
  float f2 = f * f;
  return vec4(f * (-0.5 + f * (1.0 - 0.5 * f)), 1.0 + f2 * (-2.5 + 1.5 * f),
              f * (0.5 + f * (2.0 - 1.5 * f)), f2 * (-0.5 + 0.5 * f));
}

// Photo i's stored value at uvl, sampled with CUBIC's filter: Catmull-Rom from 9 bilinear taps
// at level 0 (the two middle texels of each axis share one tap; the negative lobes' undershoot
// clamped at 0); trilinear (FetchPhoto) beyond kCubicMaxLod.
vec3 FetchCubic(int i, vec3 uvl) {
  if (CUBIC == 0 || uvl.z > kCubicMaxLod) return FetchPhoto(i, uvl);
  vec2 texels = u_photo_texels;
  vec2 sp = uvl.xy * texels;
  vec2 t1 = floor(sp - 0.5) + 0.5;  // centre of the texel left of / above the sample
  vec2 f = sp - t1;
  vec4 wx = CatmullRomWeights(f.x);
  vec4 wy = CatmullRomWeights(f.y);
  vec3 xs = vec3(t1.x - 1.0, t1.x + wx[2] / (wx[1] + wx[2]), t1.x + 2.0) / texels.x;
  vec3 ys = vec3(t1.y - 1.0, t1.y + wy[2] / (wy[1] + wy[2]), t1.y + 2.0) / texels.y;
  vec3 cx = vec3(wx[0], wx[1] + wx[2], wx[3]);
  vec3 cy = vec3(wy[0], wy[1] + wy[2], wy[3]);
  vec3 sum = vec3(0.0);
  for (int b = 0; b < 3; ++b) {
    for (int a = 0; a < 3; ++a) sum += cx[a] * cy[b] * FetchPhoto(i, vec3(xs[a], ys[b], 0.0));
  }
  return max(sum, vec3(0.0));
}

// Photo i's stored value low-passed along its line of disparity (Eisemann et al. 2007, sec. 4):
// the segment between the projections of the points at relative depths 1 - u and 1 + u along
// the view's ray through s.P, sampled with 5 binomial taps at the level of detail of their
// spacing (a single tap where the segment is under a texel).
vec3 FetchFiltered(int i, Sample s, vec3 uvl, float u) {
#ifndef FILTERED
  return FetchCubic(i, uvl);
#else
  if (u <= 0.0 || s.background) return FetchCubic(i, uvl);
  vec3 C = u_world_from_cam[3].xyz;
  vec3 a = (photos[i].cam_from_world * vec4(C + (s.P - C) * (1.0 - u), 1.0)).xyz;
  vec3 b = (photos[i].cam_from_world * vec4(C + (s.P - C) * (1.0 + u), 1.0)).xyz;
  if (a.z <= 0.0 || b.z <= 0.0) return FetchCubic(i, uvl);
  vec4 intr = photos[i].intrinsics;
  vec2 pa = intr.xy * a.xy / a.z + intr.zw;
  vec2 pb = intr.xy * b.xy / b.z + intr.zw;
  float texels = length(pb - pa) * photos[i].size.z;
  if (texels <= 1.0) return FetchCubic(i, uvl);
  vec4 tex = photos[i].tex;
  float lod = max(uvl.z, log2(texels * 0.25));
  const float kTap[5] = float[5](1.0, 4.0, 6.0, 4.0, 1.0);
  vec3 sum = vec3(0.0);
  for (int t = 0; t < 5; ++t) {
    vec2 px = mix(pa, pb, float(t) * 0.25);
    sum += kTap[t] * FetchPhoto(i, vec3(clamp(px * tex.xy, vec2(0.0), tex.zw), lod));
  }
  return sum / 16.0;
#endif
}

// Debevec's g(Z) per channel of a stored photo value c (radiance encoding): ln of the exposure
// that gives the value, before the photo's own exposure.
vec3 ResponseLog(vec3 c) {
  vec3 t = (clamp(c * 255.0, 0.0, 255.0) + 0.5) / 256.0;
  return vec3(texture(u_response, vec2(t.r, 0.5)).r, texture(u_response, vec2(t.g, 0.5)).g,
              texture(u_response, vec2(t.b, 0.5)).b);
}

// The blended quantity of photo i from its stored value c; hat receives Debevec's hat weight
// (radiance encoding; 1 otherwise).
vec3 Blended(int i, vec3 c, out vec3 hat) {
  hat = vec3(1.0);
  if (ENCODING == 1) {
    vec3 z = clamp(c * 255.0, 0.0, 255.0);
    // min(Z, 255 - Z) per channel, floored so that a value saturated in every photo keeps its
    // (clipped) radiance instead of going invalid.
    hat = max(min(z, 255.0 - z), vec3(1e-3));
    c = exp(ResponseLog(c)) * photos[i].center.w;
  }
  return c;
}

// World offsets dx, dy of the view's ray direction (camera z 1) that move it `pixels` view
// pixels along the view's x and y axes: a patch's diagonal rays are d +- dx +- dy.
void PatchOffsets(float pixels, out vec3 dx, out vec3 dy) {
  dx = mat3(u_world_from_cam) * vec3(pixels / u_intrinsics.x, 0.0, 0.0);
  dy = mat3(u_world_from_cam) * vec3(0.0, pixels / u_intrinsics.y, 0.0);
}

// ln of photo i's blended quantity (radiance: g(Z) + ln of the exposure) at its camera pixel
// px and level of detail lod, at least ln 1e-4: a gain between photos adds the same to every
// pixel.
vec3 LogValue(int i, vec2 px, float lod) {
  vec4 tex = photos[i].tex;
  vec3 c = FetchPhoto(i, vec3(clamp(px * tex.xy, vec2(0.0), tex.zw), lod));
  return ENCODING == 1 ? max(ResponseLog(c) + log(photos[i].center.w), vec3(log(1e-4)))
                       : log(max(c, vec3(1e-4)));
}

