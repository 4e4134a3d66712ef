#include "frontend/patch_match_search.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <utility>

#include "frontend/parallel.h"

namespace hdribr::patch_match {

void State::Resize(int width, int height) {
  w = width;
  h = height;
  depth.assign(size_t(w) * h, 0.f);
  cost.assign(size_t(w) * h, kNoCost);
  ncc.assign(size_t(w) * h, -1.f);
  normal.assign(size_t(w) * h, Vec3(0, 0, -1));
}

namespace {

// splitmix64, seeded per row and pass so that results do not depend on the thread count.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1).
  float Uniform() { return static_cast<float>(Next() >> 40) * (1.f / 16777216.f); }
  // Uniform in [-1, 1).
  float Symmetric() { return 2.f * Uniform() - 1.f; }

 private:
  std::uint64_t state_;
};

std::uint64_t Seed(int photo, int level, int pass, int iteration, int y) {
  return (static_cast<std::uint64_t>(photo) << 40) ^ (static_cast<std::uint64_t>(level) << 32) ^
         (static_cast<std::uint64_t>(pass) << 28) ^ (static_cast<std::uint64_t>(iteration) << 20) ^
         static_cast<std::uint64_t>(y);
}

float RandomDepth(const Level& lv, Rng& rng) {
  const float inv_far = 1.f / lv.depth_max, inv_near = 1.f / lv.depth_min;
  return 1.f / (inv_far + rng.Uniform() * (inv_near - inv_far));
}

// A random unit normal facing the camera along `view` (unit ray).
Vec3 RandomNormal(const Vec3& view, Rng& rng) {
  Vec3 v;
  do {
    v = Vec3(rng.Symmetric(), rng.Symmetric(), rng.Symmetric());
  } while (v.squaredNorm() > 1.f || v.squaredNorm() < 1e-4f);
  v.normalize();
  if (v.dot(view) > 0) v = -v;
  if (v.dot(view) > -0.1f) v = (v - 0.5f * view).normalized();
  return v;
}

// `n` turned by a random vector of length up to `scale`, still facing the camera.
Vec3 PerturbNormal(const Vec3& n, const Vec3& view, float scale, Rng& rng) {
  const Vec3 v = (n + scale * Vec3(rng.Symmetric(), rng.Symmetric(), rng.Symmetric())).normalized();
  return v.dot(view) < -0.05f ? v : n;
}

// Regions sampled for propagation around a pixel, all of the other colour of the checkerboard:
// four short V-shaped regions and four long strips along the axes; the best-cost hypothesis of
// each region is a candidate (adaptive checkerboard sampling, Xu & Tao 2019, sec. 3.1).
const std::vector<std::vector<std::pair<int, int>>>& PropagationRegions() {
  static const auto regions = [] {
    std::vector<std::pair<int, int>> near_up, far_up;
    for (int dy = 1; dy <= 3; ++dy) {
      for (int dx = -(dy - 1); dx <= dy - 1; ++dx) {
        if ((dx + dy) % 2 != 0) near_up.push_back({dx, -dy});
      }
    }
    for (int d = 5; d <= 25; d += 2) far_up.push_back({0, -d});
    std::vector<std::vector<std::pair<int, int>>> out;
    for (const auto* base : {&near_up, &far_up}) {
      // Rotations by 0, 90, 180, 270 degrees.
      for (int r = 0; r < 4; ++r) {
        std::vector<std::pair<int, int>> region;
        for (auto [dx, dy] : *base) {
          for (int i = 0; i < r; ++i) std::tie(dx, dy) = std::make_pair(-dy, dx);
          region.push_back({dx, dy});
        }
        out.push_back(region);
      }
    }
    return out;
  }();
  return regions;
}

// Propagation then refinement at one pixel (Galliani et al. 2015, sec. 3.2-3.3).
void UpdatePixel(const Level& lv, State& st, int x, int y, float depth_scale, float normal_scale,
                 Rng& rng, RefWindow& window) {
  if (!PrepareWindow(lv, x, y, window)) return;
  const int i = y * st.w + x;
  const Vec3 ray = lv.ref->k_inv * Vec3(float(x), float(y), 1.f);
  const Vec3 view = ray.normalized();
  float best_cost = st.cost[i], best_ncc = st.ncc[i], best_d = st.depth[i];
  Vec3 best_n = st.normal[i];
  auto consider = [&](float d, const Vec3& n) {
    float ncc;
    const float c = PlaneCost(lv, x, y, ray, d, n, window, best_cost, &ncc);
    if (c < best_cost) {
      best_cost = c;
      best_ncc = ncc;
      best_d = d;
      best_n = n;
    }
  };
  // Planes already scored at this pixel: a region's best is often the plane of another region
  // (one plane spreads over a converged area), and scoring it again cannot change the best.
  std::array<std::pair<float, Vec3>, 8> scored;
  int num_scored = 0;
  const auto same_plane = [](float d, const Vec3& n, float d_ref, const Vec3& n_ref) {
    return std::abs(d - d_ref) <= 1e-5f * d_ref && (n - n_ref).squaredNorm() < 1e-10f;
  };
  for (const auto& region : PropagationRegions()) {
    int best_j = -1;
    float region_cost = kNoCost;
    for (const auto& [dx, dy] : region) {
      const int xx = x + dx, yy = y + dy;
      if (xx < 0 || yy < 0 || xx >= st.w || yy >= st.h) continue;
      const int j = yy * st.w + xx;
      if (st.cost[j] < region_cost) {
        region_cost = st.cost[j];
        best_j = j;
      }
    }
    if (best_j < 0) continue;
    // The neighbour's plane, intersected with this pixel's ray.
    const Vec3& nq = st.normal[best_j];
    const Vec3 ray_q = lv.ref->k_inv * Vec3(float(best_j % st.w), float(best_j / st.w), 1.f);
    const float denom = nq.dot(ray);
    if (!(denom < 0)) continue;
    const float d = st.depth[best_j] * nq.dot(ray_q) / denom;
    // The same plane as the best so far (common once a region has converged): nothing to score.
    if (same_plane(d, nq, best_d, best_n)) continue;
    if (std::any_of(scored.begin(), scored.begin() + num_scored,
                    [&](const auto& p) { return same_plane(d, nq, p.first, p.second); })) {
      continue;
    }
    if (num_scored < static_cast<int>(scored.size())) scored[num_scored++] = {d, nq};
    consider(d, nq);
  }
  // Refinement: random and perturbed depth and normal around the best (ACMM's combinations).
  const float d0 = best_d > 0 ? best_d : RandomDepth(lv, rng);
  const Vec3 n0 = best_n;
  const float d_pert = d0 * (1.f + depth_scale * rng.Symmetric());
  const Vec3 n_pert = PerturbNormal(n0, view, normal_scale, rng);
  consider(RandomDepth(lv, rng), RandomNormal(view, rng));
  consider(d_pert, n0);
  consider(d0, n_pert);
  consider(d_pert, n_pert);
  st.depth[i] = best_d;
  st.normal[i] = best_n;
  st.cost[i] = best_cost;
  st.ncc[i] = best_ncc;
}

}  // namespace

void ScoreAll(const Level& lv, State& st, int threads) {
  ParallelFor(st.h, threads, [&](int y) {
    RefWindow window;
    for (int x = 0; x < st.w; ++x) {
      const int i = y * st.w + x;
      st.cost[i] = kNoCost;
      st.ncc[i] = -1.f;
      if (!PrepareWindow(lv, x, y, window)) continue;
      const Vec3 ray = lv.ref->k_inv * Vec3(float(x), float(y), 1.f);
      st.cost[i] = PlaneCost(lv, x, y, ray, st.depth[i], st.normal[i], window, kNoCost, &st.ncc[i]);
    }
  });
}

void Iterate(const Level& lv, State& st, int iterations, int first_scale, int photo, int level,
             int pass, int threads) {
  for (int it = 0; it < iterations; ++it) {
    const float shrink = std::ldexp(1.f, -(first_scale + it));
    for (int color = 0; color < 2; ++color) {
      ParallelFor(st.h, threads, [&](int y) {
        Rng rng(Seed(photo, level, pass, it * 2 + color, y));
        RefWindow window;
        for (int x = (y + color) % 2; x < st.w; x += 2) {
          UpdatePixel(lv, st, x, y, 0.1f * shrink, 0.6f * shrink, rng, window);
        }
      });
    }
  }
}

void Initialise(const Level& lv, State& st, const std::vector<Eigen::Vector3d>& seeds, int radius,
                int photo) {
  for (int y = 0; y < st.h; ++y) {
    Rng rng(Seed(photo, 99, 0, 0, y));
    for (int x = 0; x < st.w; ++x) {
      const Vec3 view = (lv.ref->k_inv * Vec3(float(x), float(y), 1.f)).normalized();
      st.depth[y * st.w + x] = RandomDepth(lv, rng);
      st.normal[y * st.w + x] = RandomNormal(view, rng);
    }
  }
  for (const auto& s : seeds) {
    const Vec3 p = s.cast<float>();
    if (!(p.z() >= lv.depth_min && p.z() <= lv.depth_max)) continue;
    const Vec3 px = lv.ref->k * p;
    const int u = static_cast<int>(std::lround(px.x() / px.z()));
    const int v = static_cast<int>(std::lround(px.y() / px.z()));
    for (int y = std::max(0, v - radius); y <= std::min(st.h - 1, v + radius); ++y) {
      for (int x = std::max(0, u - radius); x <= std::min(st.w - 1, u + radius); ++x) {
        st.depth[y * st.w + x] = p.z();
        st.normal[y * st.w + x] = Vec3(0, 0, -1);
      }
    }
  }
}

bool ParentPlaneDepth(const State& coarse, const LevelImage& coarse_image, const Mat3& k_inv, int x,
                      int y, int& parent, float& depth) {
  const int px = std::min(x / 2, coarse.w - 1), py = std::min(y / 2, coarse.h - 1);
  parent = py * coarse.w + px;
  const Vec3& n = coarse.normal[parent];
  const Vec3 ray_q = coarse_image.k_inv * Vec3(float(px), float(py), 1.f);
  const Vec3 ray = k_inv * Vec3(float(x), float(y), 1.f);
  const float denom = n.dot(ray);
  if (!(denom < 0)) return false;
  depth = coarse.depth[parent] * n.dot(ray_q) / denom;
  return true;
}

void Upsample(const State& coarse, const LevelImage& coarse_image, const Level& lv, State& st) {
  for (int y = 0; y < st.h; ++y) {
    for (int x = 0; x < st.w; ++x) {
      int j = 0;
      float d = 0;
      if (!ParentPlaneDepth(coarse, coarse_image, lv.ref->k_inv, x, y, j, d)) d = coarse.depth[j];
      st.depth[y * st.w + x] = std::clamp(d, lv.depth_min, lv.depth_max);
      st.normal[y * st.w + x] = coarse.normal[j];
    }
  }
}

}  // namespace hdribr::patch_match
