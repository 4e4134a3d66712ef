// Blend pass, which photos see a sample and with what weight: projection, the shadow-map test
// against each photo's depth map (Lechelek et al. 2019, sec. 4, "Occlusion and visibility"),
// eq. 5 and the Unstructured Lumigraph penalty. Docs: docs/algorithms/blend.md.

// Photo i's camera pixel of the point pk of its camera space; false when pk is behind the photo
// or outside its frame.
bool PixelIn(int i, vec3 pk, out vec2 px) {
  px = vec2(0.0);
  if (pk.z <= 0.0) return false;
  vec4 intr = photos[i].intrinsics;
  px = intr.xy * pk.xy / pk.z + intr.zw;
  return all(greaterThanEqual(px, vec2(0.0))) && all(lessThan(px, photos[i].size.xy));
}

// Unit direction V_k from the sample toward photo i's centre (V at infinity) and delta_k, the
// difference of the distances |C - P| and |C_k - P| in scene scales (eq. 4); at infinity the
// distance |C_k - C| between the centres (see Weight).
vec3 TowardPhoto(int i, Sample s, out float delta) {
  vec3 ck = photos[i].center.xyz;
  if (s.at_infinity) {
    delta = length(ck - u_world_from_cam[3].xyz) * u_inv_scene_scale;
    return s.V;
  }
  vec3 vk = ck - s.P;
  float dist_k = length(vk);
  delta = abs(s.dist_c - dist_k) * u_inv_scene_scale;
  return vk / dist_k;
}

// Where a sample projects in photo i, in the photo's camera pixels; false when it is behind
// the photo or outside its frame. pk receives the point (or direction) in photo i's camera.
bool ProjectInto(int i, Sample s, out vec2 px, out vec3 pk) {
  pk = s.at_infinity ? mat3(photos[i].cam_from_world) * s.P
                     : (photos[i].cam_from_world * vec4(s.P, 1.0)).xyz;
  return PixelIn(i, pk, px);
}

// Shadow-map test against photo i's depth map around px, on the 2x2 texels about the
// projection (a single texel rejects half the pixels along the photo's silhouettes): a point
// passes when it agrees with one of them, a background sample (which lies beyond every point,
// or on the plane around a hole of the view's depth) when one of them holds no point or agrees.
float VisibleIn(int i, Sample s, vec2 px, float z_k) {
  int layer = CACHED_DEPTH == 1 ? depth_slot_of[i] : i;
  if (layer < 0) return 0.0;  // no depth map resident: nothing to test against
  vec4 dmap = photos[i].dmap;
  ivec2 d0 = ivec2(floor(px * dmap.xy - 0.5));
  ivec2 dmax = ivec2(dmap.zw) - 1;
  int agree = 0;
  bool any_empty = false;
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      ivec2 t = clamp(d0 + ivec2(dx, dy), ivec2(0), dmax);
      float dk = texelFetch(u_photo_depth, ivec3(t, layer), 0).r;
      if (dk <= 0.0) any_empty = true;
      if (dk > 0.0 && abs(z_k - dk) <= u_tolerance * dk) ++agree;
    }
  }
  if (s.background) return any_empty || agree > 0 ? 1.0 : 0.0;
  if (SOFT_VISIBILITY == 1) return float(agree) / 4.0;
  return agree > 0 ? 1.0 : 0.0;
}

// True when photo i with ranking key `key` ranks before photo i2 with key2: a larger key, or
// an equal key and a smaller index.
bool Beats(float key, int i, float key2, int i2) { return key > key2 || (key == key2 && i < i2); }

// Geometric weight of photo i for the sample (0 when photo i does not see it, or when its
// ranking key, -penalty for the Unstructured Lumigraph or an upper bound of the weight
// otherwise, is < min_key: it could not enter the list of best photos, and the shadow-map test
// is skipped); uvl receives the texture coordinate and the level of detail in the photo,
// feather a factor in (0, 1] of the final weight (for the background: falling to 0 at the
// photo's frame, so that no seam shows where a photo's frame crosses the sky; for points, the
// soft visibility or 1), penalty the Unstructured Lumigraph penalty angle(V, V_k) (radians) +
// DELTA_WEIGHT delta_k. At infinity V_k = V (angle 0, cos 1), and delta_k is the distance
// |C_k - C| between the centres: what lies beyond the points is far but not infinitely far, and
// its parallax grows with that distance (the limit of eq. 4, (C_k - C) . d, would ignore
// sideways offsets).
float Weight(int i, Sample s, bool ulr, float min_key, out vec3 uvl, out float feather,
             out float penalty) {
  uvl = vec3(0.0);
  feather = 1.0;
  penalty = 0.0;
  vec2 px;
  vec3 pk;
  if (!ProjectInto(i, s, px, pk)) return 0.0;
  float cos_k = 1.0;
  float delta;
  vec3 vk = TowardPhoto(i, s, delta);  // eq. 4
  float footprint;  // photo texels per target pixel
  vec4 intr = photos[i].intrinsics;
  if (s.at_infinity) {
    // Angular size of a pixel: 1 / f_new in the view, 1 / f_i in the photo.
    footprint = intr.x / u_intrinsics.x * photos[i].size.z;
  } else {
    // Grazing or back-facing (paper: N_p . V_k > lambda).
    if (dot(s.N, vk) <= u_lambda) return 0.0;
    cos_k = max(0.0, dot(s.V, vk));  // eq. 2
    // A target pixel covers z_new / f_new world units at P, which photo i sees over that
    // times f_i / z_i camera pixels, times its texels per camera pixel.
    footprint = s.z_new / u_intrinsics.x * intr.x / pk.z * photos[i].size.z;
  }
  if (s.background) {
    vec2 size = photos[i].size.xy;
    vec2 border = min(px, size - px);
    feather = max(clamp(min(border.x, border.y) / (kFeather * max(size.x, size.y)), 0.0, 1.0),
                  1e-3);
  }
  if (NEAREST == 0) penalty = acos(min(cos_k, 1.0)) + DELTA_WEIGHT * delta;
  // The weight with full visibility bounds the weight (eq. 5).
  if ((ulr ? -penalty : NEAREST == 0 ? feather * cos_k / (delta + 1.0) : feather) < min_key) {
    return 0.0;
  }
  float visibility = VisibleIn(i, s, px, pk.z);
  if (visibility <= 0.0) return 0.0;
  feather *= visibility;
  vec4 tex = photos[i].tex;
  uvl = vec3(clamp(px * tex.xy, vec2(0.0), tex.zw), log2(max(footprint, 1e-6)));
  return NEAREST == 0 ? feather * cos_k / (delta + 1.0) : feather;  // eq. 5
}

