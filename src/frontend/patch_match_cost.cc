#include "frontend/patch_match_cost.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hdribr::patch_match {

WindowGrid MakeWindow(int radius, int step) {
  WindowGrid g;
  for (int o = -radius; o <= radius; o += step) g.offsets.push_back(o);
  g.n = static_cast<int>(g.offsets.size());
  g.samples = g.n * g.n;
  g.padded = (g.samples + 3) / 4 * 4;
  const float sigma = static_cast<float>(radius);
  for (int dy : g.offsets) {
    for (int dx : g.offsets) {
      g.spatial.push_back(std::exp(-static_cast<float>(dx * dx + dy * dy) / (2 * sigma * sigma)));
      g.dx.push_back(static_cast<float>(dx));
      g.dy.push_back(static_cast<float>(dy));
    }
  }
  g.spatial.resize(g.padded, 0.f);
  g.dx.resize(g.padded, 0.f);
  g.dy.resize(g.padded, 0.f);
  return g;
}

bool PrepareWindow(const Level& lv, int x, int y, RefWindow& out) {
  const cv::Mat& g = lv.ref->gray;
  const WindowGrid& win = *lv.window;
  out.a.resize(win.padded, 0.f);
  out.b.resize(win.padded, 0.f);
  out.samples.resize(win.padded, 0.f);
  const float center = g.at<float>(y, x);
  float sw = 0, sr = 0, srr = 0;
  int k = 0;
  for (int dy : win.offsets) {
    const float* row = g.ptr<float>(std::clamp(y + dy, 0, lv.h - 1));
    for (int dx : win.offsets) {
      const float r = row[std::clamp(x + dx, 0, lv.w - 1)];
      const float diff = r - center;
      const float wk = win.spatial[k] * std::exp(-diff * diff * lv.inv_two_sigma_color2);
      out.a[k] = r;
      out.b[k] = wk;
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
    out.a[i] = out.b[i] * (out.a[i] - mean) * inv;
    out.b[i] /= sw;
  }
  return true;
}

namespace {

// hm (x, y, 1)^T, written out: Eigen's 3x3 product is not always inlined.
Vec3 Apply(const Mat3& hm, float x, float y) {
  return Vec3(hm(0, 0) * x + hm(0, 1) * y + hm(0, 2), hm(1, 0) * x + hm(1, 1) * y + hm(1, 2),
              hm(2, 0) * x + hm(2, 1) * y + hm(2, 2));
}

}  // namespace

Footprint PatchFootprint(const cv::Mat& image, const WindowGrid& window, const Mat3& hm, int x,
                         int y) {
  // Inside the image without a division: 0 <= p.x / p.z <= cols - 1 for p.z > 0.
  const float umax = static_cast<float>(image.cols - 1), vmax = static_cast<float>(image.rows - 1);
  const auto inside = [&](float px, float py, float pz) {
    return pz > 0 && px >= 0 && py >= 0 && px <= umax * pz && py <= vmax * pz;
  };
  const Vec3 c = Apply(hm, float(x), float(y));
  if (!inside(c.x(), c.y(), c.z())) return Footprint::kOutside;
  const float o0 = static_cast<float>(window.offsets.front());
  const float o1 = static_cast<float>(window.offsets.back());
  for (const auto& [ox, oy] :
       {std::pair(o0, o0), std::pair(o1, o0), std::pair(o0, o1), std::pair(o1, o1)}) {
    if (!inside(c.x() + ox * hm(0, 0) + oy * hm(0, 1), c.y() + ox * hm(1, 0) + oy * hm(1, 1),
                c.z() + ox * hm(2, 0) + oy * hm(2, 1))) {
      return Footprint::kCentre;
    }
  }
  return Footprint::kFramed;
}

float SourcePhotoCost(const cv::Mat& image, const WindowGrid& window, const Mat3& hm, int x, int y,
                      RefWindow& ref) {
  // Window point (x + dx, y + dy) maps to c + dx h0 + dy h1 (homogeneous), h0, h1 hm's columns.
  const Vec3 c = Apply(hm, float(x), float(y));
  // Bilinear interpolation needs the pixel right of and below (u, v): clamp inside by 0.001 px.
  const float umax = static_cast<float>(image.cols) - 1.001f;
  const float vmax = static_cast<float>(image.rows) - 1.001f;
  const float* data = image.ptr<float>(0);
  const std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(image.step1());
  // Two passes over the samples (kept in ref.samples): the weighted mean, then the weighted
  // variance and covariance about it; one pass (sum(b s^2) - sum(b s)^2) loses digits in float
  // where the patch varies little about a bright mean.
  float* samples = ref.samples.data();
#if defined(__SSE2__)
  const __m128 cx = _mm_set1_ps(c.x()), cy = _mm_set1_ps(c.y()), cz = _mm_set1_ps(c.z());
  const __m128 h00 = _mm_set1_ps(hm(0, 0)), h10 = _mm_set1_ps(hm(1, 0)),
               h20 = _mm_set1_ps(hm(2, 0));
  const __m128 h01 = _mm_set1_ps(hm(0, 1)), h11 = _mm_set1_ps(hm(1, 1)),
               h21 = _mm_set1_ps(hm(2, 1));
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.f);
  const __m128 vumax = _mm_set1_ps(umax), vvmax = _mm_set1_ps(vmax);
  __m128 acc = zero;
  alignas(16) std::int32_t xs[4], ys[4];
  // Two neighbouring pixels of a row, as the low or high half of a vector.
  const auto pair = [](const float* p) { return reinterpret_cast<const __m64*>(p); };
  for (int k = 0; k < window.padded; k += 4) {
    const __m128 dx = _mm_loadu_ps(&window.dx[k]), dy = _mm_loadu_ps(&window.dy[k]);
    const __m128 px = _mm_add_ps(cx, _mm_add_ps(_mm_mul_ps(dx, h00), _mm_mul_ps(dy, h01)));
    const __m128 py = _mm_add_ps(cy, _mm_add_ps(_mm_mul_ps(dx, h10), _mm_mul_ps(dy, h11)));
    const __m128 pz = _mm_add_ps(cz, _mm_add_ps(_mm_mul_ps(dx, h20), _mm_mul_ps(dy, h21)));
    const __m128 inv = _mm_div_ps(one, pz);
    // max(NaN, 0) is 0 (SSE returns the second operand), so points behind the camera stay in.
    const __m128 u = _mm_min_ps(_mm_max_ps(_mm_mul_ps(px, inv), zero), vumax);
    const __m128 v = _mm_min_ps(_mm_max_ps(_mm_mul_ps(py, inv), zero), vvmax);
    const __m128i xi = _mm_cvttps_epi32(u), yi = _mm_cvttps_epi32(v);
    const __m128 fx = _mm_sub_ps(u, _mm_cvtepi32_ps(xi));
    const __m128 fy = _mm_sub_ps(v, _mm_cvtepi32_ps(yi));
    _mm_store_si128(reinterpret_cast<__m128i*>(xs), xi);
    _mm_store_si128(reinterpret_cast<__m128i*>(ys), yi);
    const float* q0 = data + ys[0] * stride + xs[0];
    const float* q1 = data + ys[1] * stride + xs[1];
    const float* q2 = data + ys[2] * stride + xs[2];
    const float* q3 = data + ys[3] * stride + xs[3];
    // [left0 right0 left1 right1] and [left2 right2 left3 right3] of the upper and lower rows.
    const __m128 up01 = _mm_loadh_pi(_mm_loadl_pi(zero, pair(q0)), pair(q1));
    const __m128 up23 = _mm_loadh_pi(_mm_loadl_pi(zero, pair(q2)), pair(q3));
    const __m128 lo01 = _mm_loadh_pi(_mm_loadl_pi(zero, pair(q0 + stride)), pair(q1 + stride));
    const __m128 lo23 = _mm_loadh_pi(_mm_loadl_pi(zero, pair(q2 + stride)), pair(q3 + stride));
    const __m128 ul = _mm_shuffle_ps(up01, up23, _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 ur = _mm_shuffle_ps(up01, up23, _MM_SHUFFLE(3, 1, 3, 1));
    const __m128 ll = _mm_shuffle_ps(lo01, lo23, _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 lr = _mm_shuffle_ps(lo01, lo23, _MM_SHUFFLE(3, 1, 3, 1));
    const __m128 top = _mm_add_ps(ul, _mm_mul_ps(fx, _mm_sub_ps(ur, ul)));
    const __m128 bottom = _mm_add_ps(ll, _mm_mul_ps(fx, _mm_sub_ps(lr, ll)));
    const __m128 s = _mm_add_ps(top, _mm_mul_ps(fy, _mm_sub_ps(bottom, top)));
    _mm_storeu_ps(samples + k, s);
    acc = _mm_add_ps(acc, _mm_mul_ps(_mm_loadu_ps(&ref.b[k]), s));
  }
  const auto sum = [](__m128 a) {
    const __m128 t = _mm_add_ps(a, _mm_movehl_ps(a, a));
    return _mm_cvtss_f32(_mm_add_ss(t, _mm_shuffle_ps(t, t, 1)));
  };
  const float mean = sum(acc);  // the weights b sum to 1
  const __m128 vmean = _mm_set1_ps(mean);
  __m128 acc_var = zero, acc_cov = zero;
  for (int k = 0; k < window.padded; k += 4) {
    const __m128 diff = _mm_sub_ps(_mm_loadu_ps(samples + k), vmean);
    acc_var = _mm_add_ps(acc_var, _mm_mul_ps(_mm_loadu_ps(&ref.b[k]), _mm_mul_ps(diff, diff)));
    acc_cov = _mm_add_ps(acc_cov, _mm_mul_ps(_mm_loadu_ps(&ref.a[k]), diff));
  }
  const float var = sum(acc_var), cov = sum(acc_cov);
#else
  float mean = 0;
  for (int k = 0; k < window.samples; ++k) {
    const float dx = window.dx[k], dy = window.dy[k];
    const float inv = 1.f / (c.z() + dx * hm(2, 0) + dy * hm(2, 1));
    float u = (c.x() + dx * hm(0, 0) + dy * hm(0, 1)) * inv;
    float v = (c.y() + dx * hm(1, 0) + dy * hm(1, 1)) * inv;
    u = u > 0 ? std::min(u, umax) : 0.f;  // NaN to 0
    v = v > 0 ? std::min(v, vmax) : 0.f;
    const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
    const float fx = u - x0, fy = v - y0;
    const float* p0 = data + y0 * stride + x0;
    const float* p1 = p0 + stride;
    const float top = p0[0] + fx * (p0[1] - p0[0]);
    const float bottom = p1[0] + fx * (p1[1] - p1[0]);
    samples[k] = top + fy * (bottom - top);
    mean += ref.b[k] * samples[k];
  }
  float var = 0, cov = 0;
  for (int k = 0; k < window.samples; ++k) {
    const float diff = samples[k] - mean;
    var += ref.b[k] * diff * diff;
    cov += ref.a[k] * diff;
  }
#endif
  if (!(var > kMinVariance)) return kMaxCost;
  return 1.f - std::clamp(cov / std::sqrt(var), -1.f, 1.f);
}

namespace {

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
  const float ex = pr.x() / pr.z() - x, ey = pr.y() / pr.z() - y;
  const float err = std::sqrt(ex * ex + ey * ey);
  return std::min(err, lv.geom_max_error);
}

}  // namespace

float PlaneCost(const Level& lv, int x, int y, const Vec3& ray, float d, const Vec3& n,
                RefWindow& ref, float bound, float* ncc) {
  const float nr = n.dot(ray);
  if (!(nr < -1e-3f) || !(d >= lv.depth_min && d <= lv.depth_max)) return kNoCost;
  // Plane n^T X = c; plane-induced homography K_s (R + t n^T / c) K_r^-1 (Hartley & Zisserman
  // 2004, eq. 13.1).
  const float c = d * nr;
  const Vec3 m = lv.ref->k_inv.transpose() * n / c;
  const int ns = std::min<int>(static_cast<int>(lv.sources.size()), kMaxSources);
  std::array<Mat3, kMaxSources> hm;
  std::array<Footprint, kMaxSources> footprint;
  // The sources that frame the patch are the pool the best views are chosen from; only when
  // none does, all of them are. The footprint is cheap (five projections): the pool is known
  // before any source is scored, and sources outside it are never scored.
  int framing = 0;
  for (int s = 0; s < ns; ++s) {
    const SourceView& src = lv.sources[s];
    hm[s] = src.a + src.b * m.transpose();
    footprint[s] = PatchFootprint(src.image->gray, *lv.window, hm[s], x, y);
    if (footprint[s] == Footprint::kFramed) ++framing;
  }
  const int pool = framing > 0 ? framing : ns;
  const int k = std::min(lv.best_views, pool);
  // (total, photo) of the scored sources, ascending in total.
  std::array<std::pair<float, float>, kMaxSources> scored;
  const Vec3 xr = d * ray;
  int done = 0;
  for (int s = 0; s < ns; ++s) {
    if (framing > 0 && footprint[s] != Footprint::kFramed) continue;
    const SourceView& src = lv.sources[s];
    const float photo = footprint[s] == Footprint::kOutside
                            ? kMaxCost
                            : SourcePhotoCost(src.image->gray, *lv.window, hm[s], x, y, ref);
    float total = photo;
    if (lv.geometric) total += lv.geom_weight * ReprojectionError(lv, src, xr, x, y);
    int j = done++;
    for (; j > 0 && scored[j - 1].first > total; --j) scored[j] = scored[j - 1];
    scored[j] = {total, photo};
    // Early termination: costs are >= 0, so the k best of the pool sum to at least the
    // `needed` smallest scored totals, the other k - needed coming from unscored sources.
    const int needed = k - (pool - done);
    if (needed > 0 && done < pool && bound < kNoCost) {
      float partial = 0;
      for (int i = 0; i < needed; ++i) partial += scored[i].first;
      if (partial >= bound * k) return std::max(partial / k, bound);
    }
  }
  float sum_total = 0, sum_photo = 0;
  for (int i = 0; i < k; ++i) {
    sum_total += scored[i].first;
    sum_photo += scored[i].second;
  }
  *ncc = 1.f - sum_photo / k;
  return sum_total / k;
}

}  // namespace hdribr::patch_match
