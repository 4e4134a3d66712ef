// Blend pass, what a pixel without a point shows (blend_background.comp): the background
// surface (BACKGROUND), the plane of the surface around a hole of the view's depth
// (EnclosedDepth), the surface that the photos' depth maps hold along the pixel's ray
// (HoleDepth), and the depth along it where the photos agree (SweepDepth).
// Docs: docs/algorithms/blend.md.

// Pixels without depth: 0 left empty, 1 at infinity, 2 on the sphere u_sphere, 3 on the plane
// u_plane within its extent, else on the sphere (render::Background).
#ifndef BACKGROUND
#define BACKGROUND 3
#endif

const int kMarchSteps = 64;   // MarchDepth: steps along the ray before the bisection
const int kRankPhotos = 4;   // RankByPenalty: photos ranked
const int kMarchPhotos = 2;  // HoleDepth: photos marched, smallest penalty first
const float kMarchNear = 0.01;  // MarchDepth: nearest view depth searched, in scene scales
const float kMarchTolerance = 0.05;  // MarchDepth: relative depth gap of a continuous surface
const int kSweepSteps = 64;     // SweepDepth: depths, uniform in inverse depth, before refining
const int kHollowSteps = 16;    // SweepDepth inside a non-planar surface: depths before refining
const float kHollowFar = 2.0;   // ... searched to this multiple of the surface's farthest depth
const float kSweepNear = 0.5;   // SweepDepth: nearest view depth searched, in scene scales
const float kSweepPatch = 2.0;  // SweepDepth: offset of the patch's 4 diagonal rays, view pixels
const float kSweepMaxCost = 0.02;  // SweepDepth: largest SweepCost accepted (ln units^2)
const float kEnclosedReach = 1.0 / 8.0;  // EnclosedDepth: search reach, share of the longer side
const int kEnclosedSteps = 32;  // EnclosedDepth: steps to the reach past the first 8 pixels
const float kEnclosedPlanar = 0.05;  // EnclosedDepth: spread of the lines' inverse depths

// Camera z of the background sphere (centre u_sphere.xyz, radius u_sphere.w, around every
// camera) along the world ray C + u d (d with camera z 1); 0 when the ray does not leave it.
float SphereDepth(vec3 C, vec3 d) {
  vec3 o = C - u_sphere.xyz;
  float a = dot(d, d);
  float b = dot(o, d);
  float c = dot(o, o) - u_sphere.w * u_sphere.w;
  float disc = b * b - a * c;
  if (disc < 0.0) return 0.0;
  return max((-b + sqrt(disc)) / a, 0.0);
}

// Camera z of the background surface along the world ray C + u d (d with camera z 1): the plane
// (BACKGROUND 3) where the ray meets it inside its extent before it leaves the sphere, else the
// sphere; 0 when there is none.
float SurfaceDepth(vec3 C, vec3 d) {
  float t = SphereDepth(C, d);
#if BACKGROUND == 3
  // The cameras lie on the side the normal points to: only a ray going against it meets the
  // plane's face.
  float along = dot(u_plane.xyz, d);
  if (along < 0.0) {
    float t_plane = -(dot(u_plane.xyz, C) + u_plane.w) / along;
    vec3 X = C + t_plane * d;
    vec2 uv = vec2(dot(u_plane_u.xyz, X), dot(u_plane_v.xyz, X));
    bool inside = all(greaterThanEqual(uv, u_plane_extent.xz)) &&
                  all(lessThanEqual(uv, u_plane_extent.yw));
    if (t_plane > 0.0 && t_plane < t && inside) t = t_plane;
  }
#endif
  return t;
}

// Places the sample on the background: at infinity (BACKGROUND 1), else on the surface at the
// view depth z_surface of the world ray C + t d; false where there is none (z_surface 0).
bool PlaceOnBackground(inout Sample s, vec3 C, vec3 d, float z_surface) {
  s.at_infinity = BACKGROUND == 1;
  if (s.at_infinity) {
    PlaceAtInfinity(s, d);
  } else if (z_surface > 0.0) {
    PlaceAt(s, C, C + z_surface * d, z_surface);
  } else {
    return false;
  }
  return true;
}

// Photo i's depth map and its camera z at the view's ray point C + t d: in front (true) when the
// map holds no point there or a farther one. False in `inside` when the point is behind photo i
// or outside its frame.
bool InFrontOf(int i, int layer, vec3 P, out bool inside, out float z_k, out float d_k) {
  vec3 pk = (photos[i].cam_from_world * vec4(P, 1.0)).xyz;
  z_k = pk.z;
  d_k = 0.0;
  vec2 px;
  inside = PixelIn(i, pk, px);
  if (!inside) return false;
  ivec2 t = clamp(ivec2(px * photos[i].dmap.xy), ivec2(0), ivec2(photos[i].dmap.zw) - 1);
  d_k = texelFetch(u_photo_depth, ivec3(t, layer), 0).r;
  return d_k <= 0.0 || pk.z < d_k;
}

// The view depths [t.x, t.y] over which the ray C + t d lies in front of photo i and inside its
// frame, within [t0, t1] (t1 <= 0: unbounded); t.x >= t.y when it never does. Each frame edge
// and the photo's image plane are a linear condition a + b t >= 0 on t.
vec2 FrustumSpan(int i, vec3 C, vec3 d, float t0, float t1) {
  vec3 o = (photos[i].cam_from_world * vec4(C, 1.0)).xyz;
  vec3 e = mat3(photos[i].cam_from_world) * d;
  vec4 f = photos[i].intrinsics;
  vec2 size = photos[i].size.xy;
  vec2 span = vec2(t0, t1 > 0.0 ? t1 : 3.0e38);
  vec2 conds[5];
  conds[0] = vec2(o.z - 1e-3 * t0, e.z);
  conds[1] = vec2(f.x * o.x + f.z * o.z, f.x * e.x + f.z * e.z);
  conds[2] = vec2(size.x * o.z, size.x * e.z) - conds[1];
  conds[3] = vec2(f.y * o.y + f.w * o.z, f.y * e.y + f.w * e.z);
  conds[4] = vec2(size.y * o.z, size.y * e.z) - conds[3];
  for (int c = 0; c < 5; ++c) {
    float a = conds[c].x, b = conds[c].y;
    if (b > 0.0) {
      span.x = max(span.x, -a / b);
    } else if (b < 0.0) {
      span.y = min(span.y, -a / b);
    } else if (a < 0.0) {
      span.y = span.x;
    }
  }
  return span;
}

// View depth (camera z) where the view's ray C + t d (d: camera z 1) first passes behind the
// surface of photo i's depth map, searched where the ray is in photo i's frame between t0 and
// t1 (t1 <= 0: infinity) in kMarchSteps steps uniform in inverse depth (uniform along the
// epipolar line in the photo), then bisected; 0 when the ray meets no continuous surface there
// (only silhouettes it passes behind, where the map's depth jumps away from the ray's).
float MarchDepth(int i, vec3 C, vec3 d, float t0, float t1) {
  int layer = CACHED_DEPTH == 1 ? depth_slot_of[i] : i;
  if (layer < 0) return 0.0;
  vec2 span = FrustumSpan(i, C, d, t0, t1);
  if (span.x >= span.y) return 0.0;
  float inv0 = 1.0 / span.x;
  float inv1 = span.y < 3.0e38 ? 1.0 / span.y : 0.0;
  bool prev_front = false;
  float prev_inv = inv0;
  for (int j = 0; j <= kMarchSteps; ++j) {
    float inv = max(mix(inv0, inv1, float(j) / float(kMarchSteps)), 1e-3 * inv0);
    bool inside;
    float z_k, d_k;
    bool front = InFrontOf(i, layer, C + d / inv, inside, z_k, d_k);
    if (inside && !front && prev_front) {
      float lo = prev_inv, hi = inv;  // in front at lo, behind at hi (inside, z_k, d_k at hi)
      for (int b = 0; b < 8; ++b) {
        float mid = 0.5 * (lo + hi);
        bool mid_inside;
        float mid_z, mid_d;
        if (InFrontOf(i, layer, C + d / mid, mid_inside, mid_z, mid_d)) {
          lo = mid;
        } else {
          hi = mid;
          inside = mid_inside;
          z_k = mid_z;
          d_k = mid_d;
        }
      }
      if (inside && d_k > 0.0 && z_k - d_k <= kMarchTolerance * d_k) return 1.0 / hi;
    }
    prev_front = inside && front;
    prev_inv = inv;
  }
  return 0.0;
}

// The kRankPhotos photos that frame sample s with the smallest Unstructured Lumigraph penalty
// (angle + distance, as in Weight), smallest first; -1 past the photos that frame it.
void RankByPenalty(Sample s, out int ids[kRankPhotos]) {
  float best_p[kRankPhotos];
  for (int j = 0; j < kRankPhotos; ++j) {
    best_p[j] = 3.0e38;
    ids[j] = -1;
  }
  for (int a = 0; a < u_active_count; ++a) {
    int i = active_photos[a];
    vec2 px;
    vec3 pk;
    if (!ProjectInto(i, s, px, pk)) continue;
    float delta;
    float p =
        acos(clamp(dot(s.V, TowardPhoto(i, s, delta)), -1.0, 1.0)) + DELTA_WEIGHT * delta;
    for (int j = 0; j < kRankPhotos; ++j) {  // insertion with constant indices
      if (p < best_p[j]) {
        float t_p = best_p[j];
        int t_i = ids[j];
        best_p[j] = p;
        ids[j] = i;
        p = t_p;
        i = t_i;
      }
    }
  }
}

// Where a background sample that no photo passes (each photo's depth map holds a point where
// the sample projects: a hole in the view's geometry), or without a background a pixel without
// depth (ranked as its ray's direction), lies on the photos' surfaces: the view depth at which
// its ray meets the depth map of the first of the kMarchPhotos photos of ids (RankByPenalty of
// the sample) that holds a continuous surface along the ray; 0 when none does.
float HoleDepth(int ids[kRankPhotos], vec3 C, vec3 d, float t_far) {
  float t0 = kMarchNear / u_inv_scene_scale;
  for (int j = 0; j < kMarchPhotos; ++j) {
    float t = ids[j] >= 0 ? MarchDepth(ids[j], C, d, t0, t_far) : 0.0;
    if (t > 0.0) return t;
  }
  return 0.0;
}

// Disagreement of the ranked photos ids at view depth z on the view's ray C + z d, and when
// rays_used is 5 on 4 diagonal rays d +- dx +- dy beside it at the same depth: the variance of
// their log values (LogValue), summed over RGB and averaged over the rays, among the photos
// that see the centre ray's point (their depth map holds no surface there) and frame each
// ray's. False in ok when fewer than two photos see it, or when one holds a surface beyond it:
// it saw through the point, which lies in free space.
float SweepCost(vec3 C, vec3 d, vec3 dx, vec3 dy, float z, int ids[kRankPhotos], int rays_used,
                out bool ok) {
  float cost = 0.0;
  ok = false;
  vec3 rays[5] = vec3[5](d, d + dx + dy, d + dx - dy, d - dx + dy, d - dx - dy);
  bool sees[kRankPhotos];
  for (int r = 0; r < rays_used; ++r) {
    vec3 P = C + rays[r] * z;
    vec3 m = vec3(0.0), m2 = vec3(0.0);
    float n = 0.0;
    for (int j = 0; j < kRankPhotos; ++j) {
      int i = ids[j];
      if (r == 0) {
        int layer = i < 0 ? -1 : CACHED_DEPTH == 1 ? depth_slot_of[i] : i;
        bool inside = false;
        float z_k = 0.0, d_k = 0.0;
        sees[j] = layer >= 0 && InFrontOf(i, layer, P, inside, z_k, d_k) && d_k <= 0.0;
        if (inside && d_k > (1.0 + u_tolerance) * z_k) return 0.0;
      }
      if (!sees[j]) continue;
      vec3 pk = (photos[i].cam_from_world * vec4(P, 1.0)).xyz;
      vec2 px;
      if (!PixelIn(i, pk, px)) continue;
      // Photo texels per view pixel at this depth (as in Weight).
      float footprint = z / u_intrinsics.x * photos[i].intrinsics.x / pk.z * photos[i].size.z;
      vec3 v = LogValue(i, px, max(log2(max(footprint, 1e-6)), 0.0));
      m += v;
      m2 += v * v;
      n += 1.0;
    }
    if (n < 2.0) {
      if (r == 0) return 0.0;
      continue;
    }
    m /= n;
    vec3 var = max(m2 / n - m * m, vec3(0.0));
    cost += var.r + var.g + var.b;
  }
  ok = true;
  return cost / float(rays_used);
}

// View depth of the plane that encloses pixel p's hole in the view's depth map: along each of
// the 4 lines through p (horizontal, vertical, the diagonals), the first depth on both sides
// within kEnclosedReach of the frame, interpolated linearly in inverse depth (exact across a
// plane, whose inverse depth is affine in the image); 0 unless at least 3 lines find both sides
// and their estimates agree within kEnclosedPlanar (a silhouette, where the sides are different
// surfaces, gives no depth). What multi-view stereo leaves without points inside a surface (an
// untextured wall or door) is drawn on the surface around it. span receives the smallest and
// largest of the lines' inverse depths when at least 3 lines find both sides (the hole is
// enclosed, planar or not), else 0.
float EnclosedDepth(ivec2 p, out vec2 span) {
  span = vec2(0.0);
  const ivec2 kDirs[4] = ivec2[4](ivec2(1, 0), ivec2(0, 1), ivec2(1, 1), ivec2(1, -1));
  int reach = int(kEnclosedReach * float(max(u_size.x, u_size.y)));
  int stride = max(1, reach / kEnclosedSteps);
  float lo = 3.0e38, hi = 0.0, sum = 0.0;
  int lines = 0;
  for (int l = 0; l < 4; ++l) {
    if (l - lines >= 2) return 0.0;  // 3 lines can no longer be found
    float inv[2] = float[2](0.0, 0.0);
    float dist[2] = float[2](0.0, 0.0);
    for (int side = 0; side < 2; ++side) {
      if (side == 1 && dist[0] <= 0.0) break;
      ivec2 dir = side == 0 ? kDirs[l] : -kDirs[l];
      for (int k = 1; k <= reach; k += k < 8 ? 1 : stride) {
        ivec2 q = p + k * dir;
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, u_size))) break;
        float zq = texelFetch(u_depth, q, 0).r;
        if (zq > 0.0) {
          inv[side] = 1.0 / zq;
          dist[side] = float(k);
          break;
        }
      }
    }
    if (dist[0] <= 0.0 || dist[1] <= 0.0) continue;
    float e = (inv[0] * dist[1] + inv[1] * dist[0]) / (dist[0] + dist[1]);
    lo = min(lo, e);
    hi = max(hi, e);
    sum += e;
    ++lines;
  }
  if (lines >= 3) span = vec2(lo, hi);
  if (lines < 3 || hi > (1.0 + kEnclosedPlanar) * lo) return 0.0;
  return float(lines) / sum;
}

// Depth of a background sample that no photo passes and whose ray meets no surface of the
// photos' depth maps (HoleDepth), or that a non-planar surface encloses, from a plane sweep
// along the view's ray C + t d (d: camera z 1) over the photos ids (RankByPenalty of the
// sample): `steps` depths uniform in inverse depth over inv_range (view inverse depths,
// farthest first) scored on the ray alone (SweepCost), then every eighth of a step within one
// step of the best scored over the patch; the depth where the photos agree best (on ties the
// farthest, as befits what lies beyond the points), 0 when no depth is seen by two photos or
// the best disagrees more than kSweepMaxCost. What multi-view stereo left without points
// (untextured walls, far buildings seen through gaps) is drawn at the depth where its photos
// agree: a plane sweep (Collins 1996) for the view's holes alone.
float SweepDepth(int ids[kRankPhotos], vec3 C, vec3 d, vec2 inv_range, int steps) {
  if (ids[1] < 0) return 0.0;
  vec3 dx, dy;
  PatchOffsets(kSweepPatch, dx, dy);
  float step = (inv_range.y - inv_range.x) / float(steps);
  float best_cost = 3.0e38;
  float best_inv = 0.0;
  for (int k = 0; k < steps; ++k) {  // far to near, from half a step short of the far end
    float inv = inv_range.x + step * (float(k) + 0.5);
    bool ok;
    float cost = SweepCost(C, d, dx, dy, 1.0 / inv, ids, 1, ok);
    if (ok && cost < best_cost) {
      best_cost = cost;
      best_inv = inv;
    }
  }
  if (best_inv <= 0.0) return 0.0;
  float center = best_inv;
  best_cost = 3.0e38;
  for (int k = -8; k <= 8; ++k) {
    float inv = center + step * float(k) / 8.0;
    if (inv <= 0.0) continue;
    bool ok;
    float cost = SweepCost(C, d, dx, dy, 1.0 / inv, ids, 5, ok);
    if (ok && cost < best_cost) {
      best_cost = cost;
      best_inv = inv;
    }
  }
  return best_cost <= kSweepMaxCost ? 1.0 / best_inv : 0.0;
}

