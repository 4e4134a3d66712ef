#include "frontend/patch_match.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>

#include "frontend/ncc.h"
#include "frontend/parallel.h"

namespace hdribr {
namespace {

using Mat3 = Eigen::Matrix3f;
using Vec3 = Eigen::Vector3f;

constexpr float kMaxCost = 2.f;        // 1 - NCC of a source that cannot score the pixel
constexpr float kNoCost = 1e9f;        // cost of a pixel without a valid hypothesis
constexpr int kMaxSources = 32;        // sources used per photo at most
constexpr float kMinVariance = 1e-6f;  // flat window (intensities in [0, 1])

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

// A photo at one pyramid level, in OpenCV's pixel convention (pixel centres at integers).
struct LevelImage {
  cv::Mat gray;  // CV_32F
  Mat3 k, k_inv;
};

LevelImage MakeLevel(const DepthMap& m, int level) {
  LevelImage out;
  const double s = std::ldexp(1.0, -level);
  const int w = std::max(1, static_cast<int>(std::lround(m.gray.cols * s)));
  const int h = std::max(1, static_cast<int>(std::lround(m.gray.rows * s)));
  if (level == 0) {
    out.gray = m.gray;
  } else {
    cv::resize(m.gray, out.gray, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  }
  Eigen::Matrix3d k = m.camera.Scaled(w, h).K();
  k(0, 2) -= 0.5;
  k(1, 2) -= 0.5;
  out.k = k.cast<float>();
  out.k_inv = k.inverse().cast<float>();
  return out;
}

// A source photo as seen from the reference at one level.
struct SourceView {
  const LevelImage* image = nullptr;
  Mat3 a;         // K_s R K_r^-1: the homography's plane-independent part
  Vec3 b;         // K_s t
  Mat3 rotation;  // src_from_ref
  Vec3 translation;
  const cv::Mat* depth = nullptr;  // its depth from the previous level or pass (geometric cost)
  Mat3 depth_k, depth_k_inv;       // the intrinsics of that depth map, OpenCV convention
};

// Sample offsets of the window: a grid of n x n at -r, -r + step, ..., with spatial weights.
struct WindowGrid {
  std::vector<int> offsets;    // per axis
  std::vector<float> spatial;  // per sample, row-major
  int n = 0;
};

WindowGrid MakeWindow(int radius, int step) {
  WindowGrid g;
  for (int o = -radius; o <= radius; o += step) g.offsets.push_back(o);
  g.n = static_cast<int>(g.offsets.size());
  const float sigma = static_cast<float>(radius);
  for (int dy : g.offsets) {
    for (int dx : g.offsets) {
      g.spatial.push_back(std::exp(-static_cast<float>(dx * dx + dy * dy) / (2 * sigma * sigma)));
    }
  }
  return g;
}

// Everything the cost of one reference photo at one level needs.
struct Level {
  const LevelImage* ref = nullptr;
  std::vector<SourceView> sources;
  const WindowGrid* window = nullptr;
  int w = 0, h = 0;
  float depth_min = 0, depth_max = 0;
  int best_views = 1;
  float inv_two_sigma_color2 = 1;
  bool geometric = false;
  float geom_weight = 0, geom_max_error = 0;
};

// Per-pixel hypotheses and their costs.
struct State {
  int w = 0, h = 0;
  std::vector<float> depth, cost, ncc;
  std::vector<Vec3> normal;
  void Resize(int width, int height) {
    w = width;
    h = height;
    depth.assign(size_t(w) * h, 0.f);
    cost.assign(size_t(w) * h, kNoCost);
    ncc.assign(size_t(w) * h, -1.f);
    normal.assign(size_t(w) * h, Vec3(0, 0, -1));
  }
};

// Bilateral NCC weights of the reference window at a pixel, arranged so that the weighted NCC
// with a source patch s is sum(a s) / sqrt(sum(b s^2) - sum(b s)^2) (Schönberger et al. 2016,
// eq. 8 with COLMAP's bilateral weights). False when the window is flat.
bool PrepareWindow(const Level& lv, int x, int y, std::vector<float>& a, std::vector<float>& b) {
  const cv::Mat& g = lv.ref->gray;
  const WindowGrid& win = *lv.window;
  const float center = g.at<float>(y, x);
  float sw = 0, sr = 0, srr = 0;
  int k = 0;
  for (int dy : win.offsets) {
    const float* row = g.ptr<float>(std::clamp(y + dy, 0, lv.h - 1));
    for (int dx : win.offsets) {
      const float r = row[std::clamp(x + dx, 0, lv.w - 1)];
      const float diff = r - center;
      const float wk = win.spatial[k] * std::exp(-diff * diff * lv.inv_two_sigma_color2);
      a[k] = r;
      b[k] = wk;
      sw += wk;
      sr += wk * r;
      srr += wk * r * r;
      ++k;
    }
  }
  const float mean = sr / sw;
  const float var = srr / sw - mean * mean;
  if (!(var > kMinVariance)) return false;
  const float inv = 1.f / (sw * std::sqrt(var));
  for (int i = 0; i < k; ++i) {
    a[i] = b[i] * (a[i] - mean) * inv;
    b[i] /= sw;
  }
  return true;
}

inline float Bilinear(const cv::Mat& img, float u, float v) {
  u = std::clamp(u, 0.f, static_cast<float>(img.cols) - 1.001f);
  v = std::clamp(v, 0.f, static_cast<float>(img.rows) - 1.001f);
  const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
  const float fx = u - x0, fy = v - y0;
  const float* p0 = img.ptr<float>(y0) + x0;
  const float* p1 = img.ptr<float>(y0 + 1) + x0;
  const float top = p0[0] + fx * (p0[1] - p0[0]);
  const float bottom = p1[0] + fx * (p1[1] - p1[0]);
  return top + fy * (bottom - top);
}

// 1 - weighted NCC of the reference window with the source patch through homography `hm`.
// `framed` is set when the whole patch lies inside the source photo.
float SourcePhotoCost(const Level& lv, const SourceView& src, const Mat3& hm, int x, int y,
                      const std::vector<float>& a, const std::vector<float>& b, bool* framed) {
  const cv::Mat& img = src.image->gray;
  auto inside = [&](const Vec3& p) {
    if (!(p.z() > 0)) return false;
    const float u = p.x() / p.z(), v = p.y() / p.z();
    return u >= 0 && v >= 0 && u <= img.cols - 1 && v <= img.rows - 1;
  };
  const Vec3 center = hm * Vec3(float(x), float(y), 1.f);
  if (!inside(center)) return kMaxCost;
  const WindowGrid& win = *lv.window;
  const float o0 = static_cast<float>(win.offsets.front());
  const float o1 = static_cast<float>(win.offsets.back());
  const float step = win.n > 1 ? static_cast<float>(win.offsets[1] - win.offsets[0]) : 1.f;
  const Vec3 hx = hm.col(0), hy = hm.col(1);
  *framed = inside(center + o0 * hx + o0 * hy) && inside(center + o1 * hx + o0 * hy) &&
            inside(center + o0 * hx + o1 * hy) && inside(center + o1 * hx + o1 * hy);
  Vec3 row = center + o0 * hx + o0 * hy;
  const Vec3 sx = step * hx, sy = step * hy;
  float s1 = 0, s2 = 0, s3 = 0;
  int k = 0;
  for (int iy = 0; iy < win.n; ++iy, row += sy) {
    Vec3 p = row;
    for (int ix = 0; ix < win.n; ++ix, ++k, p += sx) {
      const float inv = 1.f / p.z();
      const float s = Bilinear(img, p.x() * inv, p.y() * inv);
      s1 += b[k] * s;
      s2 += b[k] * s * s;
      s3 += a[k] * s;
    }
  }
  const float var = s2 - s1 * s1;
  if (!(var > kMinVariance)) return kMaxCost;
  return 1.f - std::clamp(s3 / std::sqrt(var), -1.f, 1.f);
}

// Depth at (u, v): bilinear where the four pixels around are valid, else the nearest; 0 outside.
float SampleDepth(const cv::Mat& depth, float u, float v) {
  if (!(u >= 0 && v >= 0 && u <= depth.cols - 1 && v <= depth.rows - 1)) return 0.f;
  const int x0 = std::min(static_cast<int>(u), depth.cols - 2);
  const int y0 = std::min(static_cast<int>(v), depth.rows - 2);
  if (x0 < 0 || y0 < 0) return depth.at<float>(std::lround(v), std::lround(u));
  const float* p0 = depth.ptr<float>(y0) + x0;
  const float* p1 = depth.ptr<float>(y0 + 1) + x0;
  if (p0[0] > 0 && p0[1] > 0 && p1[0] > 0 && p1[1] > 0) {
    const float fx = u - x0, fy = v - y0;
    const float top = p0[0] + fx * (p0[1] - p0[0]);
    const float bottom = p1[0] + fx * (p1[1] - p1[0]);
    return top + fy * (bottom - top);
  }
  return depth.at<float>(static_cast<int>(std::lround(v)), static_cast<int>(std::lround(u)));
}

// Forward-backward reprojection error (pixels) of the reference point `xr` through the source's
// depth map (Schönberger et al. 2016, sec. 4.3).
float ReprojectionError(const Level& lv, const SourceView& src, const Vec3& xr, int x, int y) {
  const Vec3 xs = src.rotation * xr + src.translation;
  if (!(xs.z() > 0)) return lv.geom_max_error;
  const Vec3 ps = src.depth_k * xs;
  const float u = ps.x() / ps.z(), v = ps.y() / ps.z();
  const float ds = SampleDepth(*src.depth, u, v);
  if (!(ds > 0)) return lv.geom_max_error;
  const Vec3 back =
      src.rotation.transpose() * (ds * (src.depth_k_inv * Vec3(u, v, 1.f)) - src.translation);
  const Vec3 pr = lv.ref->k * back;
  if (!(pr.z() > 0)) return lv.geom_max_error;
  const float err = std::hypot(pr.x() / pr.z() - x, pr.y() / pr.z() - y);
  return std::min(err, lv.geom_max_error);
}

// Cost of the plane through depth `d` at pixel (x, y) with normal `n`: mean of the best views'
// costs (per-pixel view selection, so that sources where the pixel is occluded do not vote)
// among the sources that frame the patch, or all of them when none does. `ncc` gets the mean
// NCC of those views.
float PlaneCost(const Level& lv, int x, int y, const Vec3& ray, float d, const Vec3& n,
                const std::vector<float>& a, const std::vector<float>& b, float* ncc) {
  const float nr = n.dot(ray);
  if (!(nr < -1e-3f) || !(d >= lv.depth_min && d <= lv.depth_max)) return kNoCost;
  // Plane n^T X = c; plane-induced homography K_s (R + t n^T / c) K_r^-1 (Hartley & Zisserman
  // 2004, eq. 13.1).
  const float c = d * nr;
  const Vec3 m = lv.ref->k_inv.transpose() * n / c;
  const int ns = std::min<int>(static_cast<int>(lv.sources.size()), kMaxSources);
  std::array<float, kMaxSources> photo, total;
  std::array<int, kMaxSources> order;
  const Vec3 xr = d * ray;
  // The sources that frame the patch first in `order`.
  int framing = 0;
  for (int s = 0; s < ns; ++s) {
    const SourceView& src = lv.sources[s];
    const Mat3 hm = src.a + src.b * m.transpose();
    bool framed = false;
    photo[s] = SourcePhotoCost(lv, src, hm, x, y, a, b, &framed);
    total[s] = photo[s];
    if (lv.geometric) total[s] += lv.geom_weight * ReprojectionError(lv, src, xr, x, y);
    order[s] = s;
    if (framed) std::swap(order[s], order[framing++]);
  }
  const int pool = framing > 0 ? framing : ns;
  const int k = std::min(lv.best_views, pool);
  std::partial_sort(order.begin(), order.begin() + k, order.begin() + pool,
                    [&](int i, int j) { return total[i] < total[j]; });
  float sum_total = 0, sum_photo = 0;
  for (int i = 0; i < k; ++i) {
    sum_total += total[order[i]];
    sum_photo += photo[order[i]];
  }
  *ncc = 1.f - sum_photo / k;
  return sum_total / k;
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

struct Scratch {
  std::vector<float> a, b;
};

// Propagation then refinement at one pixel (Galliani et al. 2015, sec. 3.2-3.3).
void UpdatePixel(const Level& lv, State& st, int x, int y, float depth_scale, float normal_scale,
                 Rng& rng, Scratch& sc) {
  if (!PrepareWindow(lv, x, y, sc.a, sc.b)) return;
  const int i = y * st.w + x;
  const Vec3 ray = lv.ref->k_inv * Vec3(float(x), float(y), 1.f);
  const Vec3 view = ray.normalized();
  float best_cost = st.cost[i], best_ncc = st.ncc[i], best_d = st.depth[i];
  Vec3 best_n = st.normal[i];
  auto consider = [&](float d, const Vec3& n) {
    float ncc;
    const float c = PlaneCost(lv, x, y, ray, d, n, sc.a, sc.b, &ncc);
    if (c < best_cost) {
      best_cost = c;
      best_ncc = ncc;
      best_d = d;
      best_n = n;
    }
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
    if (std::abs(d - best_d) <= 1e-5f * best_d && (nq - best_n).squaredNorm() < 1e-10f) continue;
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

// Cost of every pixel's current hypothesis.
void ScoreAll(const Level& lv, State& st, int threads) {
  ParallelFor(st.h, threads, [&](int y) {
    Scratch sc{std::vector<float>(lv.window->spatial.size()),
               std::vector<float>(lv.window->spatial.size())};
    for (int x = 0; x < st.w; ++x) {
      const int i = y * st.w + x;
      st.cost[i] = kNoCost;
      st.ncc[i] = -1.f;
      if (!PrepareWindow(lv, x, y, sc.a, sc.b)) continue;
      const Vec3 ray = lv.ref->k_inv * Vec3(float(x), float(y), 1.f);
      st.cost[i] = PlaneCost(lv, x, y, ray, st.depth[i], st.normal[i], sc.a, sc.b, &st.ncc[i]);
    }
  });
}

// Red-black iterations: all pixels of one colour update in parallel over rows, reading only
// pixels of the other colour.
void Iterate(const Level& lv, State& st, int iterations, int first_scale, int photo, int level,
             int pass, int threads) {
  for (int it = 0; it < iterations; ++it) {
    const float shrink = std::ldexp(1.f, -(first_scale + it));
    for (int color = 0; color < 2; ++color) {
      ParallelFor(st.h, threads, [&](int y) {
        Rng rng(Seed(photo, level, pass, it * 2 + color, y));
        Scratch sc{std::vector<float>(lv.window->spatial.size()),
                   std::vector<float>(lv.window->spatial.size())};
        for (int x = (y + color) % 2; x < st.w; x += 2) {
          UpdatePixel(lv, st, x, y, 0.1f * shrink, 0.6f * shrink, rng, sc);
        }
      });
    }
  }
}

// Random hypotheses, with fronto-parallel depth seeds from the sparse points around their
// projections.
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

// The parent of pixel (x, y) at the next coarser level (`parent`: its index in `coarse`) and the
// depth at which the parent's plane meets the ray of (x, y) (`k_inv`: this level's intrinsics).
// False, leaving `depth` unset, when that ray does not meet the plane in front of the camera.
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

// The coarser level's planes at the pixels of this level (nearest parent; the next iterations
// refine them).
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

// A photo's result at one level: its state and depth map with the intrinsics of that level.
struct Result {
  State state;
  cv::Mat depth;  // CV_32F, 0 where invalid
  Mat3 k, k_inv;
};

Result MakeResult(State st, const LevelImage& image) {
  Result r;
  r.depth = cv::Mat(st.h, st.w, CV_32F, st.depth.data()).clone();
  for (int i = 0; i < st.w * st.h; ++i) {
    if (st.cost[i] >= kNoCost) r.depth.at<float>(i / st.w, i % st.w) = 0.f;
  }
  r.state = std::move(st);
  r.k = image.k;
  r.k_inv = image.k_inv;
  return r;
}

// The cost context of photo `ref` at `level`; with `guide` (the sources' results of the previous
// level or pass) the cost includes the geometric term.
Level MakeLevelContext(const std::vector<std::vector<LevelImage>>& pyramids,
                       const std::vector<DepthMap>& maps, int ref, const PatchMatchTask& task,
                       int level, const WindowGrid& window, const DenseOptions& options,
                       const std::vector<Result>* guide) {
  const PatchMatchOptions& pm = options.patch_match;
  Level lv;
  lv.ref = &pyramids[ref][level];
  lv.w = lv.ref->gray.cols;
  lv.h = lv.ref->gray.rows;
  lv.window = &window;
  lv.depth_min = static_cast<float>(task.depth_min);
  lv.depth_max = static_cast<float>(task.depth_max);
  lv.inv_two_sigma_color2 = 1.f / (2.f * pm.sigma_color * pm.sigma_color);
  lv.geometric = guide != nullptr && pm.geom_weight > 0;
  lv.geom_weight = pm.geom_weight;
  lv.geom_max_error = pm.geom_max_error;
  const Rigid3d world_from_ref = maps[ref].cam_from_world.Inverse();
  for (int s : task.sources) {
    if (static_cast<int>(lv.sources.size()) >= kMaxSources) break;
    SourceView v;
    v.image = &pyramids[s][level];
    const Rigid3d src_from_ref = maps[s].cam_from_world * world_from_ref;
    v.rotation = src_from_ref.rotation.toRotationMatrix().cast<float>();
    v.translation = src_from_ref.translation.cast<float>();
    v.a = v.image->k * v.rotation * lv.ref->k_inv;
    v.b = v.image->k * v.translation;
    if (guide) {
      v.depth = &(*guide)[s].depth;
      v.depth_k = (*guide)[s].k;
      v.depth_k_inv = (*guide)[s].k_inv;
    }
    lv.sources.push_back(v);
  }
  const int ns = static_cast<int>(lv.sources.size());
  lv.best_views = pm.best_views > 0 ? std::min(pm.best_views, ns) : std::max(1, (ns + 1) / 2);
  return lv;
}

// One level of one photo: random and seeded (coarsest) or upsampled hypotheses, then red-black
// iterations. Finer levels add the geometric cost against the sources' coarser results
// (multi-scale geometric consistency guidance, Xu & Tao 2019, sec. 3.3).
Result RunLevel(const std::vector<std::vector<LevelImage>>& pyramids,
                const std::vector<DepthMap>& maps, int ref, const PatchMatchTask& task, int level,
                const WindowGrid& window, const DenseOptions& options,
                const std::vector<Result>* previous, int threads) {
  const PatchMatchOptions& pm = options.patch_match;
  const int levels = static_cast<int>(pyramids[ref].size());
  const bool coarsest = level == levels - 1;
  const Level lv = MakeLevelContext(pyramids, maps, ref, task, level, window, options,
                                    coarsest ? nullptr : previous);
  State st;
  st.Resize(lv.w, lv.h);
  if (coarsest) {
    Initialise(lv, st, task.seeds, pm.seed_radius, ref);
  } else {
    Upsample((*previous)[ref].state, pyramids[ref][level + 1], lv, st);
  }
  ScoreAll(lv, st, threads);
  Iterate(lv, st, coarsest ? pm.coarse_iterations : pm.iterations, coarsest ? 0 : 2, ref, level, 0,
          threads);
  return MakeResult(std::move(st), *lv.ref);
}

// The geometric pass of one photo at the finest level: starts from its result, adds the
// reprojection error through the sources' finest results to the cost.
Result GeometricPass(const std::vector<std::vector<LevelImage>>& pyramids,
                     const std::vector<DepthMap>& maps, int ref, const PatchMatchTask& task,
                     const WindowGrid& window, const DenseOptions& options,
                     const std::vector<Result>& finest, int threads) {
  const Level lv = MakeLevelContext(pyramids, maps, ref, task, 0, window, options, &finest);
  State st = finest[ref].state;
  ScoreAll(lv, st, threads);
  Iterate(lv, st, options.patch_match.geom_iterations, 3, ref, 0, 1, threads);
  return MakeResult(std::move(st), *lv.ref);
}

// Writes a state into a map's depth, normal and score (depth 0 where the NCC is too low or the
// window too flat). With `coarse` (the next coarser level's result), a pixel that fails keeps
// the coarse plane through its parent where that plane passed the same tests at its level.
void StoreState(const State& st, const PatchMatchOptions& pm, const Result* coarse,
                const LevelImage* coarse_image, const LevelImage& image, DepthMap& m) {
  cv::Mat mean, var, coarse_var;
  WindowStats(m.gray, pm.window_radius, mean, var);
  if (coarse) WindowStats(coarse_image->gray, pm.window_radius, mean, coarse_var);
  // The output filter: no cost, NCC below min_ncc, or window variance below min_texture.
  const auto fails = [&](const State& s, int i, const cv::Mat& window_var) {
    return s.cost[i] >= kNoCost || s.ncc[i] < pm.min_ncc ||
           window_var.at<float>(i / s.w, i % s.w) < pm.min_texture;
  };
  m.depth = cv::Mat::zeros(st.h, st.w, CV_32F);
  m.score = cv::Mat::zeros(st.h, st.w, CV_32F);
  m.normal = cv::Mat::zeros(st.h, st.w, CV_32FC3);
  for (int y = 0; y < st.h; ++y) {
    for (int x = 0; x < st.w; ++x) {
      const int i = y * st.w + x;
      float d = st.depth[i], score = st.ncc[i];
      Vec3 n = st.normal[i];
      if (fails(st, i, var)) {
        if (!coarse) continue;
        const State& cs = coarse->state;
        int j = 0;
        if (!ParentPlaneDepth(cs, *coarse_image, image.k_inv, x, y, j, d) ||
            fails(cs, j, coarse_var)) {
          continue;
        }
        n = cs.normal[j];
        score = cs.ncc[j];
      }
      m.depth.at<float>(y, x) = d;
      m.score.at<float>(y, x) = score;
      m.normal.at<cv::Vec3f>(y, x) = cv::Vec3f(n.x(), n.y(), n.z());
    }
  }
}

bool HasWork(const PatchMatchTask& t) {
  return !t.sources.empty() && t.depth_min > 0 && t.depth_max > t.depth_min;
}

}  // namespace

void PatchMatchDepthMaps(std::vector<DepthMap>& maps, const std::vector<PatchMatchTask>& tasks,
                         const DenseOptions& options,
                         const std::function<void(int, int)>& progress) {
  const PatchMatchOptions& pm = options.patch_match;
  const int n = static_cast<int>(maps.size());
  const int threads = ThreadCount(options.threads);
  // Pyramids of the same depth for all photos; they stop before a side falls below 16 pixels.
  int levels = std::max(1, pm.num_levels);
  for (int i = 0; i < n; ++i) {
    while (levels > 1 && std::min(maps[i].gray.cols, maps[i].gray.rows) >> (levels - 1) < 16) {
      --levels;
    }
  }
  std::vector<std::vector<LevelImage>> pyramids(n);
  for (int i = 0; i < n; ++i) {
    for (int l = 0; l < levels; ++l) pyramids[i].push_back(MakeLevel(maps[i], l));
  }
  const WindowGrid window = MakeWindow(pm.window_radius, pm.window_step);
  const bool geometric = pm.geom_iterations > 0 && pm.geom_weight > 0;
  const int total = n * (levels + (geometric ? 1 : 0));
  int done = 0;
  // Level by level over all photos, so that each finer level can use the sources' coarser
  // results.
  std::vector<Result> results(n), coarse;  // coarse: the half-size level's, for the fill
  for (int level = levels - 1; level >= 0; --level) {
    std::vector<Result> next(n);
    for (int i = 0; i < n; ++i) {
      if (HasWork(tasks[i])) {
        next[i] = RunLevel(pyramids, maps, i, tasks[i], level, window, options, &results, threads);
      }
      if (progress) progress(++done, total);
    }
    if (level == 0 && levels > 1) coarse = std::move(results);
    results = std::move(next);
  }
  if (geometric) {
    std::vector<Result> refined(n);
    for (int i = 0; i < n; ++i) {
      if (!results[i].depth.empty()) {
        refined[i] = GeometricPass(pyramids, maps, i, tasks[i], window, options, results, threads);
      }
      if (progress) progress(++done, total);
    }
    results = std::move(refined);
  }
  for (int i = 0; i < n; ++i) {
    maps[i].depth.release();
    maps[i].normal.release();
    maps[i].score.release();
    if (results[i].depth.empty()) continue;
    const bool fill = pm.coarse_fill && !coarse.empty() && !coarse[i].depth.empty();
    StoreState(results[i].state, pm, fill ? &coarse[i] : nullptr, fill ? &pyramids[i][1] : nullptr,
               pyramids[i][0], maps[i]);
  }
}

}  // namespace hdribr
