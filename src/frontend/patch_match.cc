#include "frontend/patch_match.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "frontend/ncc.h"
#include "frontend/parallel.h"
#include "frontend/patch_match_cost.h"
#include "frontend/patch_match_search.h"

namespace hdribr {
namespace {

using patch_match::Initialise;
using patch_match::Iterate;
using patch_match::kMaxSources;
using patch_match::kNoCost;
using patch_match::Level;
using patch_match::LevelImage;
using patch_match::MakeWindow;
using patch_match::Mat3;
using patch_match::ParentPlaneDepth;
using patch_match::ScoreAll;
using patch_match::SourceView;
using patch_match::State;
using patch_match::Upsample;
using patch_match::Vec3;
using patch_match::WindowGrid;

// Photo `m` at pyramid `level` (halved `level` times), with its intrinsics.
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
