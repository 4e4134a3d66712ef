// Blend pass, one sample's blend (Lechelek et al. 2019, sec. 4, eqs. 1-5; the Unstructured
// Lumigraph, Buehler et al. 2001): the photos that see it ranked, weighted and blended.
// Docs: docs/algorithms/blend.md.

// Blends the photos that see sample s, on the view's ray C + t d (d: camera z 1): color
// receives the blended value with alpha 1, aux the photos blended (r) and the debug photo's
// normalised weight (g); false, with both zero, when no photo passes.
bool BlendSample(inout Sample s, vec3 C, vec3 d, out vec4 color, out vec4 aux) {
  vec3 sum = vec3(0.0);
  vec3 wsum = vec3(0.0);
  float geo_sum = 0.0;
  float debug_w = 0.0;
  float count = 0.0;
  // Candidates: every photo (paper, SUM_ALL), or the K best by weight, or the K + 1
  // smallest penalties (Unstructured Lumigraph), kept sorted (Beats), so the list does not
  // depend on the order the photos are visited in.
  bool ulr = ULR == 1 && NEAREST == 0;
  int k = ulr ? KEEP - 1 : KEEP;
  float best_key[KEEP];
  float best_w[KEEP];
  float best_f[KEEP];
  int best_i[KEEP];
  vec3 best_uvl[KEEP];
  for (int j = 0; j < KEEP; ++j) {
    best_key[j] = -3.0e38;
    best_w[j] = 0.0;
    best_f[j] = 0.0;
    best_i[j] = 0x7fffffff;
    best_uvl[j] = vec3(0.0);
  }
  int n_best = 0;
  for (int a = 0; a < u_active_count; ++a) {
    int i = active_photos[a];
    vec3 uvl;
    float feather;
    float penalty;
    float w = Weight(i, s, ulr, best_key[KEEP - 1], uvl, feather, penalty);
    if (w <= 0.0) continue;
    if (SUM_ALL == 1) {  // all photos: accumulate directly
      vec3 hat;
      vec3 c = Blended(i, FetchFiltered(i, s, uvl, u_filter), hat);
      sum += w * hat * c;
      wsum += w * hat;
      geo_sum += w;
      count += 1.0;
      if (i == u_debug_photo) debug_w = w;
      continue;
    }
    float key = ulr ? -penalty : w;  // larger is better
    if (!Beats(key, i, best_key[KEEP - 1], best_i[KEEP - 1])) continue;
    // Carried down the list, swapping with every entry it beats: an insertion with constant
    // indices; the entry carried past the end is dropped.
    for (int j = 0; j < KEEP; ++j) {
      if (Beats(key, i, best_key[j], best_i[j])) {
        float t_key = best_key[j], t_w = best_w[j], t_f = best_f[j];
        int t_i = best_i[j];
        vec3 t_uvl = best_uvl[j];
        best_key[j] = key;
        best_w[j] = w;
        best_f[j] = feather;
        best_i[j] = i;
        best_uvl[j] = uvl;
        key = t_key;
        w = t_w;
        feather = t_f;
        i = t_i;
        uvl = t_uvl;
      }
    }
    n_best = min(n_best + 1, KEEP);
  }
  if (ulr && n_best > 0) {
    // Threshold: the (K+1)-th penalty, or the paper's cosine horizon when fewer photos see P.
    // (floored: K + 1 photos from exactly the view's direction would give 0 / 0).
    float t = max(n_best > k ? -best_key[KEEP - 1] : kHalfPi, 1e-4);
    n_best = min(n_best, k);
    for (int j = 0; j < KEEP; ++j) {
      float p = -best_key[j];
      best_w[j] = j < n_best ? best_f[j] * max(0.0, 1.0 - p / t) / max(p, 1e-4) : 0.0;
    }
    if (best_w[0] <= 0.0) best_w[0] = 1.0;  // every penalty beyond the horizon: the best
  }
  for (int j = 0; j < KEEP; ++j) {  // entries past the list carry no weight
    if (j >= n_best) best_w[j] = 0.0;
  }
#if REFINE == 1
  if (!s.background) RefineDepth(s, C, d, best_i, best_w, best_uvl);
#endif
  vec3 stored[KEEP];
  for (int j = 0; j < KEEP; ++j) {
    bool used = j < n_best && best_w[j] > 0.0;
    stored[j] = used ? FetchFiltered(best_i[j], s, best_uvl[j], u_filter) : vec3(0.0);
    if (!used) best_w[j] = 0.0;
  }
#if OUTLIER == 1
  // One reweighting step (Cauchy's): photos whose value departs from the weighted mean by
  // more than the scale (ghosts of wrong depth or occlusion, highlights) lose their weight.
  vec3 mean = vec3(0.0);
  float mean_w = 0.0;
  for (int j = 0; j < KEEP; ++j) {
    mean += best_w[j] * stored[j];
    mean_w += best_w[j];
  }
  mean /= max(mean_w, 1e-30);
  for (int j = 0; j < KEEP; ++j) {
    vec3 r = (stored[j] - mean) / u_outlier_scale;
    best_w[j] /= 1.0 + dot(r, r);
  }
#endif
  for (int j = 0; j < KEEP; ++j) {
    if (best_w[j] <= 0.0) continue;
    vec3 hat;
    vec3 c = Blended(best_i[j], stored[j], hat);
    sum += best_w[j] * hat * c;
    wsum += best_w[j] * hat;
    geo_sum += best_w[j];
    count += 1.0;
    if (best_i[j] == u_debug_photo) debug_w = best_w[j];
  }
  color = vec4(0.0);
  aux = vec4(0.0);
  if (count <= 0.0 || !all(greaterThan(wsum, vec3(0.0)))) return false;
  color = vec4(sum / wsum, 1.0);
  aux = vec4(count, debug_w / geo_sum, 0.0, 0.0);
  return true;
}
