// Blend pass, the photo-consistent depth (REFINE): each point moves along the view's ray to
// where its ranked photos agree best. Docs: docs/algorithms/blend.md.

#if REFINE == 1
const int kRefineSteps = 1;     // depths tested on each side of the depth pass's z
const float kRefinePatch = 1.0;  // offset of the patch's 4 diagonal rays, view pixels

// Disagreement of the listed photos (weights w, levels of detail uvl.z) at the point of view
// depth z on the ray C + z d (d: camera z 1): the weighted variance, summed over RGB, of the
// logs of their blended values (a gain between photos adds the same to every depth); false in
// ok when a listed photo does not frame the point.
float Disagreement(vec3 C, vec3 d, float z, int ids[KEEP], float w[KEEP], vec3 uvl[KEEP],
                   out bool ok) {
  vec3 P = C + d * z;
  vec3 m = vec3(0.0), m2 = vec3(0.0);
  float ws = 0.0;
  ok = true;
  for (int j = 0; j < KEEP; ++j) {
    if (w[j] <= 0.0) continue;
    int i = ids[j];
    vec2 px;
    if (!PixelIn(i, (photos[i].cam_from_world * vec4(P, 1.0)).xyz, px)) {
      ok = false;
      return 0.0;
    }
    vec3 v = LogValue(i, px, max(uvl[j].z, 0.0));
    m += w[j] * v;
    m2 += w[j] * v * v;
    ws += w[j];
  }
  m /= ws;
  vec3 var = max(m2 / ws - m * m, vec3(0.0));
  return var.r + var.g + var.b;
}

// Photo-consistent depth: the view depth, among the depth pass's z (sample s) and kRefineSteps
// steps on each side of it within +-u_refine * z, where the listed photos disagree least over
// a patch: the pixel's ray at that depth and 4 diagonal rays kRefinePatch pixels away where
// they meet the plane through that point with the sample's normal (PatchMatch stereo's slanted
// windows, Bleyer et al. 2011; a depth ratio beyond 1.25 counts as fronto-parallel). Winner
// takes all; z itself on ties or where a photo does not frame a depth; a patch ray that leaves
// a photo's frame adds nothing. The photos' texture coordinates move with it; their list,
// weights and visibility stay those of z (a depth within the occlusion tolerance of it, of the
// same surface). Point clouds from multi-view stereo are off by a fraction of a pixel's
// parallax, which blurs the blend of several photos; the search realigns them: per-view depth
// from photo-consistency, as in Soft 3D (Penner & Zhang 2017), within a small range about the
// cloud's depth.
void RefineDepth(inout Sample s, vec3 C, vec3 d, int ids[KEEP], float w[KEEP],
                 inout vec3 uvl[KEEP]) {
  int used = 0;
  for (int j = 0; j < KEEP; ++j) used += w[j] > 0.0 ? 1 : 0;
  if (used < 2) return;
  vec3 dx, dy;
  PatchOffsets(kRefinePatch, dx, dy);
  float z0 = s.z_new;
  // Ratios of the patch rays' depths to the centre's on the sample's plane (normal s.N).
  float nd = dot(s.N, d);
  vec4 tilt = nd / vec4(dot(s.N, d + dx + dy), dot(s.N, d + dx - dy), dot(s.N, d - dx + dy),
                        dot(s.N, d - dx - dy));
  tilt = mix(vec4(1.0), tilt, equal(clamp(tilt, 0.8, 1.25), tilt));
  float best_cost = 3.0e38;
  float best_z = z0;
  for (int r = 0; r <= 2 * kRefineSteps; ++r) {
    // z first, then outwards (-1, +1, -2, +2, ... steps), so a tie keeps the nearest to z.
    int step = (r + 1) / 2 * ((r & 1) == 1 ? -1 : 1);
    float z = z0 * (1.0 + u_refine * float(step) / float(kRefineSteps));
    bool ok, ok_patch;
    float cost = Disagreement(C, d, z, ids, w, uvl, ok);
    if (!ok) continue;
    cost += Disagreement(C, d + dx + dy, z * tilt.x, ids, w, uvl, ok_patch);
    cost += Disagreement(C, d + dx - dy, z * tilt.y, ids, w, uvl, ok_patch);
    cost += Disagreement(C, d - dx + dy, z * tilt.z, ids, w, uvl, ok_patch);
    cost += Disagreement(C, d - dx - dy, z * tilt.w, ids, w, uvl, ok_patch);
    if (cost < best_cost) {
      best_cost = cost;
      best_z = z;
    }
  }
  if (best_z == z0) return;
  vec3 n = s.N;
  PlaceAt(s, C, C + d * best_z, best_z);
  s.N = n;
  for (int j = 0; j < KEEP; ++j) {
    if (w[j] <= 0.0) continue;
    vec2 px;
    vec3 pk;
    if (ProjectInto(ids[j], s, px, pk)) {
      vec4 tex = photos[ids[j]].tex;
      uvl[j].xy = clamp(px * tex.xy, vec2(0.0), tex.zw);
    }
  }
}
#endif
