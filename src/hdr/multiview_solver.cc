#include "hdr/multiview_solver.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "core/error.h"

namespace hdribr {
namespace {
constexpr int kLevels = 256;
constexpr int kMid = 128;  // g_c(kMid) = 0 fixes each curve's additive constant
constexpr int kCurveVars = 3 * (kLevels - 1);
constexpr double kMidWeight = 127.0;  // HatWeight of a mid-grey value
// Minimum spread (natural log, max - min) of the prior log exposures for them to fix the
// exponent shared by g and ln t; below it the exponent comes from assumed_log_span.
constexpr double kMinPriorSpread = 0.1;
// Minimum spread of the solved log exposures when no prior fixes them: photos all exposed
// alike cannot constrain a curve.
constexpr double kMinSolvedSpread = 0.1;

// Index of g_c(z) among the unknowns; -1 for the gauge g_c(128) = 0.
int CurveVar(int c, int z) {
  if (z == kMid) return -1;
  return c * (kLevels - 1) + (z < kMid ? z : z - 1);
}

// sRGB's g(192) - g(64): the natural log of the ratio of the linear values of those codes.
double SrgbLogSpan() {
  const auto decode = [](double v) { return std::pow((v + 0.055) / 1.055, 2.4); };
  return std::log(decode(192.0 / 255.0) / decode(64.0 / 255.0));
}

// ln of sRGB's decoding of code z (IEC 61966-2-1), z in 1..255.
double SrgbLog(int z) {
  const double v = z / 255.0;
  return std::log(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
}

// Channel observations grouped by (sample, channel): one group per scene radiance E_jc.
struct Groups {
  std::vector<int> begin{0};  // observations of group k: [begin[k], begin[k + 1])
  std::vector<int> channel;   // per group
  std::vector<int> sample;    // per group: index of its sample (non-decreasing)
  std::vector<int> photo;     // per observation
  std::vector<int> z;         // per observation
  int size() const { return static_cast<int>(channel.size()); }
};

// The groups whose observations (values in (margin, 255 - margin)) come from >= 2 distinct
// photos with keep[photo].
Groups BuildGroups(const std::vector<MultiViewSample>& samples, int margin,
                   const std::vector<char>& keep) {
  Groups groups;
  for (size_t j = 0; j < samples.size(); ++j) {
    const MultiViewSample& sample = samples[j];
    for (int c = 0; c < 3; ++c) {
      const size_t start = groups.photo.size();
      for (const MultiViewObservation& o : sample.observations) {
        const int z = o.bgr[c];
        if (z <= margin || z >= 255 - margin || !keep[o.photo]) continue;
        groups.photo.push_back(o.photo);
        groups.z.push_back(z);
      }
      bool distinct = false;
      for (size_t k = start + 1; k < groups.photo.size(); ++k) {
        distinct = distinct || groups.photo[k] != groups.photo[start];
      }
      if (distinct) {
        groups.channel.push_back(c);
        groups.sample.push_back(static_cast<int>(j));
        groups.begin.push_back(static_cast<int>(groups.photo.size()));
      } else {
        groups.photo.resize(start);
        groups.z.resize(start);
      }
    }
  }
  return groups;
}

// Root of i in a union-find forest (with path halving).
int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Photos whose exposures the observations fix together: the connected component (photos
// linked by shared groups) with the most observations.
std::vector<char> SolvablePhotos(const Groups& groups, int photos) {
  std::vector<int> parent(photos);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<int> count(photos, 0);
  for (int k = 0; k < groups.size(); ++k) {
    const int first = groups.photo[groups.begin[k]];
    for (int o = groups.begin[k]; o < groups.begin[k + 1]; ++o) {
      parent[Find(parent, groups.photo[o])] = Find(parent, first);
      ++count[groups.photo[o]];
    }
  }
  std::vector<long> root_count(photos, 0);
  for (int i = 0; i < photos; ++i) root_count[Find(parent, i)] += count[i];
  const int largest =
      static_cast<int>(std::max_element(root_count.begin(), root_count.end()) - root_count.begin());
  std::vector<char> solvable(photos, 0);
  for (int i = 0; i < photos; ++i) solvable[i] = count[i] > 0 && Find(parent, i) == largest;
  return solvable;
}

// How the solve fixes the exposures' common factor and the exponent shared by g and ln t.
struct Gauge {
  bool exponent_from_prior = false;  // else from MultiViewOptions::assumed_log_span
  std::vector<int> prior_photos;     // solved photos with a prior
  double mean_prior = 0.0;           // mean prior over them (0 without)
  // Per-channel exposures: per photo, ln t of a solve with one exposure per photo (centred),
  // to which the channels' offsets are held orthogonal; empty otherwise.
  std::vector<double> scalar_log_exposure;
};

// One least-squares problem: unknowns g (kCurveVars) then ln t of the solved photos (one per
// photo, or one per photo and channel with MultiViewOptions::per_channel_exposure).
class Solver {
 public:
  Solver(const Groups& groups, const std::vector<double>& prior, const std::vector<int>& slot,
         int solved, const MultiViewOptions& options, const Gauge& gauge)
      : groups_(groups),
        prior_(prior),
        slot_(slot),
        options_(options),
        gauge_(gauge),
        channels_(options.per_channel_exposure ? 3 : 1),
        n_(kCurveVars + channels_ * solved) {}

  // The data and smoothness part of the normal equations (right-hand side 0) for the
  // observation weights `robust` (in [0, 1], per observation).
  Eigen::MatrixXd Assemble(const std::vector<double>& robust) const {
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n_, n_);
    AddData(robust, h);
    AddSmoothness(h);
    AddChannelPrior(h);
    AddResponsePrior(h, nullptr, 0.0);
    return h;
  }

  // Solves `base` plus the gauge (mean over channels of g(192) - g(64) = span) and, with
  // `use_prior`, each photo's prior. Returns false when there is no finite solution.
  bool Solve(const Eigen::MatrixXd& base, double span, bool use_prior, Eigen::VectorXd& x) const {
    Eigen::MatrixXd h = base;
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n_);
    if (use_prior) AddPrior(h, b);
    AddResponsePrior(h, &b, span);
    AddGauge(span, h, b);
    const Eigen::LLT<Eigen::MatrixXd> llt(h);  // blocked: several times faster than LDLT
    if (llt.info() == Eigen::Success) {
      x = llt.solve(b);
      if (x.allFinite()) return true;
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(h);
    x = ldlt.solve(b);
    return ldlt.info() == Eigen::Success && x.allFinite();
  }

  // Index of ln t of `photo` in channel c.
  int TimeVar(int photo, int c) const {
    return kCurveVars + channels_ * slot_[photo] + (channels_ == 3 ? c : 0);
  }

  // ln t of `photo`: the mean over the channels.
  double MeanTime(const Eigen::VectorXd& x, int photo) const {
    double sum = 0;
    for (int c = 0; c < channels_; ++c) sum += x(TimeVar(photo, c));
    return sum / channels_;
  }

  // g_c(z) from a solution (0 at the gauge).
  static double Curve(const Eigen::VectorXd& x, int c, int z) {
    const int v = CurveVar(c, z);
    return v < 0 ? 0.0 : x(v);
  }

 private:
  // Debevec's data term sum a_o (g_c(z_o) - ln t_o - ln E)^2 per group, a_o = w(z_o)^2 x robust
  // weight, with ln E eliminated (Schur complement): sum a l l^T - (sum a l)(sum a l)^T / A for
  // l_o the coefficient vector of g_c(z_o) - ln t_o. The right-hand side is 0.
  void AddData(const std::vector<double>& robust, Eigen::MatrixXd& h) const {
    std::vector<std::pair<int, double>> s;
    for (int k = 0; k < groups_.size(); ++k) {
      const int c = groups_.channel[k];
      double total = 0;
      s.clear();
      for (int o = groups_.begin[k]; o < groups_.begin[k + 1]; ++o) {
        const double w = HatWeight(groups_.z[o]);
        const double a = w * w * robust[o];
        if (a <= 0) continue;
        total += a;
        const int g = CurveVar(c, groups_.z[o]);
        const int t = TimeVar(groups_.photo[o], c);
        h(t, t) += a;
        if (g >= 0) {
          h(g, g) += a;
          h(g, t) -= a;
          h(t, g) -= a;
          s.emplace_back(g, a);
        }
        s.emplace_back(t, -a);
      }
      if (total <= 0) continue;
      for (const auto& [i, ai] : s) {
        const double f = ai / total;
        for (const auto& [j, aj] : s) h(i, j) -= f * aj;
      }
    }
  }

  // lambda w(k) D(g_c)(k) = 0 for k = 1..254 (Debevec's equation 3, second sum).
  void AddSmoothness(Eigen::MatrixXd& h) const {
    for (int c = 0; c < 3; ++c) {
      for (int k = 1; k + 1 < kLevels; ++k) {
        const double s = options_.lambda * options_.lambda * HatWeight(k) * HatWeight(k);
        const std::array<double, 3> d = SmoothnessStencil(k, options_.smoothness);
        for (int u = 0; u < 3; ++u) {
          const int iu = CurveVar(c, k - 1 + u);
          if (iu < 0) continue;
          for (int v = 0; v < 3; ++v) {
            const int iv = CurveVar(c, k - 1 + v);
            if (iv >= 0) h(iu, iv) += s * d[u] * d[v];
          }
        }
      }
    }
  }

  // Each photo's own prior: (observation_sigma / prior_sigma) w_mid (ln t - prior) = 0, ln t
  // the mean over the channels.
  void AddPrior(Eigen::MatrixXd& h, Eigen::VectorXd& b) const {
    const double ratio = options_.observation_sigma / options_.prior_sigma;
    const double weight = kMidWeight * kMidWeight * ratio * ratio / (channels_ * channels_);
    for (int i : gauge_.prior_photos) {
      for (int c = 0; c < channels_; ++c) {
        for (int d = 0; d < channels_; ++d) h(TimeVar(i, c), TimeVar(i, d)) += weight;
        b(TimeVar(i, c)) += weight * channels_ * prior_[i];
      }
    }
  }

  // The slope prior response_prior w(k)^2 [g(k + 1) - g(k) - s (r(k + 1) - r(k))]^2, r sRGB's
  // ln decoding, s = span / (sRGB's span): its matrix part into h when b is null (it does not
  // depend on the span), else its right-hand side into b.
  void AddResponsePrior(Eigen::MatrixXd& h, Eigen::VectorXd* b, double span) const {
    if (!(options_.response_prior > 0)) return;
    const double s = span / SrgbLogSpan();
    for (int c = 0; c < 3; ++c) {
      for (int k = 1; k + 1 < kLevels - 1; ++k) {
        const double w = 0.5 * (HatWeight(k) + HatWeight(k + 1));
        const double a = options_.response_prior * w * w;
        const int i = CurveVar(c, k), j = CurveVar(c, k + 1);
        if (b) {
          const double d = s * (SrgbLog(k + 1) - SrgbLog(k));
          if (j >= 0) (*b)(j) += a * d;
          if (i >= 0) (*b)(i) -= a * d;
          continue;
        }
        if (i >= 0) h(i, i) += a;
        if (j >= 0) h(j, j) += a;
        if (i >= 0 && j >= 0) h(i, j) -= a, h(j, i) -= a;
      }
    }
  }

  // With per-channel exposures: (observation_sigma / channel_sigma) w_mid (ln t_ic - ln t_i)
  // = 0 for each photo and channel, ln t_i the mean over the channels.
  void AddChannelPrior(Eigen::MatrixXd& h) const {
    if (channels_ == 1) return;
    const double ratio = options_.observation_sigma / options_.channel_sigma;
    const double weight = kMidWeight * kMidWeight * ratio * ratio;
    for (int i = 0; i < static_cast<int>(slot_.size()); ++i) {
      if (slot_[i] < 0) continue;
      for (int c = 0; c < 3; ++c) {
        for (int d = 0; d < 3; ++d) {
          h(TimeVar(i, c), TimeVar(i, d)) += weight * ((c == d ? 1.0 : 0.0) - 1.0 / 3.0);
        }
      }
    }
  }

  // Constraints a^T x = beta (|a| = 1) added with a weight far above the data's, fixing the
  // directions the data leave free: the exposures' common factor (their mean over the photos
  // with a prior is the prior's, else their mean is 0) and the exponent shared by g and ln t
  // (g -> k g, ln t -> k ln t: the mean over channels of g(192) - g(64) is `span`).
  void AddGauge(double span, Eigen::MatrixXd& h, Eigen::VectorXd& b) const {
    const double heavy = 1e4 * std::max(1.0, h.diagonal().maxCoeff());
    const auto add = [&](const std::vector<std::pair<int, double>>& a, double beta) {
      double norm2 = 0;
      for (const auto& entry : a) norm2 += entry.second * entry.second;
      if (!(norm2 > 0)) return;
      for (const auto& [i, ai] : a) {
        b(i) += heavy * ai * beta / norm2;
        for (const auto& [j, aj] : a) h(i, j) += heavy * ai * aj / norm2;
      }
    };
    std::vector<std::pair<int, double>> a;
    for (int c = 0; c < channels_; ++c) {  // per channel: ln E_jc - k, ln t_ic + k is free
      a.clear();
      if (!gauge_.prior_photos.empty()) {
        for (int i : gauge_.prior_photos) a.emplace_back(TimeVar(i, c), 1.0);
      } else {
        for (int i = 0; i < static_cast<int>(slot_.size()); ++i) {
          if (slot_[i] >= 0) a.emplace_back(TimeVar(i, c), 1.0);
        }
      }
      add(a, gauge_.mean_prior * static_cast<double>(a.size()));
    }
    // Per channel, g_c -> k_c g_c, ln t_ic -> k_c ln t_ic: offsets ln t_ic - ln t_i that grow
    // with the exposure are an exponent per channel, which the data leave free: the offsets
    // are held orthogonal to the exposures (sum_i (ln t_ic - ln t_i) s_i = 0, s_i centred).
    if (channels_ == 3 && !gauge_.scalar_log_exposure.empty()) {
      for (int c = 0; c < 3; ++c) {
        a.clear();
        for (int i = 0; i < static_cast<int>(slot_.size()); ++i) {
          if (slot_[i] < 0) continue;
          const double si = gauge_.scalar_log_exposure[i];
          for (int d = 0; d < 3; ++d)
            a.emplace_back(TimeVar(i, d), si * ((c == d ? 1.0 : 0.0) - 1.0 / 3.0));
        }
        add(a, 0.0);
      }
    }
    a.clear();
    for (int c = 0; c < 3; ++c) {
      a.emplace_back(CurveVar(c, 192), 1.0);
      a.emplace_back(CurveVar(c, 64), -1.0);
    }
    add(a, 3.0 * span);
    // A tiny ridge keeps codes no equation reaches (lambda = 0) from making h singular.
    h.diagonal().array() += 1e-12 * std::max(1.0, h.diagonal().maxCoeff());
  }

  const Groups& groups_;
  const std::vector<double>& prior_;
  const std::vector<int>& slot_;
  const MultiViewOptions& options_;
  const Gauge& gauge_;
  const int channels_;
  const int n_;
};

// Residuals g_c(z_o) - ln t_o - ln E of every observation, ln E the group's weighted mean.
std::vector<double> Residuals(const Groups& groups, const Solver& solver,
                              const std::vector<double>& robust, const Eigen::VectorXd& x) {
  std::vector<double> r(groups.photo.size(), 0.0);
  for (int k = 0; k < groups.size(); ++k) {
    const int c = groups.channel[k];
    double total = 0, sum = 0;
    for (int o = groups.begin[k]; o < groups.begin[k + 1]; ++o) {
      r[o] = Solver::Curve(x, c, groups.z[o]) - x(solver.TimeVar(groups.photo[o], c));
      const double w = HatWeight(groups.z[o]);
      total += w * w * robust[o];
      sum += w * w * robust[o] * r[o];
    }
    const double log_e = total > 0 ? sum / total : 0.0;
    for (int o = groups.begin[k]; o < groups.begin[k + 1]; ++o) r[o] -= log_e;
  }
  return r;
}

// Robust scale of rho = w(z) r: 1.4826 x the median |rho|.
double RobustScale(const Groups& groups, const std::vector<double>& r) {
  std::vector<double> rho(r.size());
  for (size_t o = 0; o < r.size(); ++o) rho[o] = std::abs(HatWeight(groups.z[o]) * r[o]);
  if (rho.empty()) return 0.0;
  const auto mid = rho.begin() + static_cast<long>(rho.size() / 2);
  std::nth_element(rho.begin(), mid, rho.end());
  return 1.4826 * *mid;
}

// The photo count: the prior's size, or one past the largest index observed.
int PhotoCount(const std::vector<MultiViewSample>& samples, const std::vector<double>& prior) {
  int largest = -1;
  for (const MultiViewSample& s : samples) {
    for (const MultiViewObservation& o : s.observations) {
      if (o.photo < 0 || (!prior.empty() && o.photo >= static_cast<int>(prior.size()))) {
        throw UsageError("multi-view calibration: observation of photo " + std::to_string(o.photo) +
                         " outside the " + std::to_string(prior.size()) +
                         " photos of the exposure prior");
      }
      largest = std::max(largest, o.photo);
    }
  }
  return prior.empty() ? largest + 1 : static_cast<int>(prior.size());
}

// Clamps g outward from the fixed middle so that it is non-decreasing; returns the changes.
int MakeMonotone(std::vector<double>& g) {
  int fixes = 0;
  for (int k = kMid + 1; k < kLevels; ++k) {
    if (g[k] < g[k - 1]) g[k] = g[k - 1], ++fixes;
  }
  for (int k = kMid - 1; k >= 0; --k) {
    if (g[k] > g[k + 1]) g[k] = g[k + 1], ++fixes;
  }
  return fixes;
}

// Slope of the least-squares line prior ~ slope x ln t + offset over the prior photos.
double PriorSlope(const Solver& solver, const Gauge& gauge, const std::vector<double>& prior,
                  const Eigen::VectorXd& x) {
  const double n = static_cast<double>(gauge.prior_photos.size());
  double mean_t = 0;
  for (int i : gauge.prior_photos) mean_t += solver.MeanTime(x, i) / n;
  double sxy = 0, sxx = 0;
  for (int i : gauge.prior_photos) {
    const double dt = solver.MeanTime(x, i) - mean_t;
    sxy += dt * (prior[i] - gauge.mean_prior);
    sxx += dt * dt;
  }
  return sxx > 0 ? sxy / sxx : 0.0;
}

// One least-squares fit for the weights `robust`. With exponent_from_prior, the exponent
// (`span`, the mean g(192) - g(64)) is then scaled by the slope of the prior against the
// solved log exposures and the system solved again, until the slope is 1: the data term and
// the smoothness are homogeneous in (g, ln t, ln E), so scaling the span scales the fit, and
// the prior sets the scale by regression on the data's exposures. The first solve of the first
// round leaves out the photos' own priors (made for exposures at the prior's scale).
// Throws UsageError when the system has no finite solution or the prior contradicts the data.
void SolveRound(const Solver& solver, const Gauge& gauge, const std::vector<double>& prior,
                const std::vector<double>& robust, bool first, double& span, Eigen::VectorXd& x,
                int& solves) {
  const Eigen::MatrixXd base = solver.Assemble(robust);
  constexpr int kMaxSolves = 6;
  for (int k = 0; k < kMaxSolves; ++k) {
    const bool use_prior = gauge.exponent_from_prior && !(first && k == 0);
    Eigen::VectorXd next;
    if (!solver.Solve(base, span, use_prior, next)) {
      if (x.size() > 0) return;  // keep the previous fit
      throw UsageError(
          "multi-view calibration: the least-squares system has no finite solution (too few "
          "observations; try a larger smoothness weight lambda)");
    }
    x = next;
    ++solves;
    if (!gauge.exponent_from_prior) return;
    const double slope = PriorSlope(solver, gauge, prior, x);
    if (!(slope > 0.05 && slope < 20)) {
      throw UsageError(
          "multi-view calibration: the exposure prior contradicts the observations (the "
          "photos' prior exposures do not grow with the exposures the pixel values show)");
    }
    span *= slope;
    if (std::abs(slope - 1.0) < 1e-4) return;
  }
}

}  // namespace

MultiViewCalibration SolveMultiView(const std::vector<MultiViewSample>& samples,
                                    const std::vector<double>& prior_log_exposure,
                                    const MultiViewOptions& options,
                                    const std::vector<double>& scalar_log_exposure) {
  const int photos = PhotoCount(samples, prior_log_exposure);
  if (photos < 2) {
    throw UsageError("multi-view calibration needs observations from at least two photos");
  }
  std::vector<double> prior(photos, std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < prior_log_exposure.size(); ++i) {
    if (std::isfinite(prior_log_exposure[i])) prior[i] = prior_log_exposure[i];
  }
  const Groups linked = BuildGroups(samples, options.clip_margin, std::vector<char>(photos, 1));
  if (linked.size() == 0) {
    throw UsageError(
        "multi-view calibration: no scene point is well exposed (values within the clip "
        "margin of 0-255 excluded) in two or more photos: the observations cannot constrain a "
        "response curve");
  }
  const std::vector<char> solvable = SolvablePhotos(linked, photos);
  const Groups groups = BuildGroups(samples, options.clip_margin, solvable);
  std::vector<int> slot(photos, -1);
  int solved = 0;
  for (int i = 0; i < photos; ++i) {
    if (solvable[i]) slot[i] = solved++;
  }
  HDRIBR_CHECK(solved >= 2 && groups.size() > 0);

  Gauge gauge;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i = 0; i < photos; ++i) {
    if (!solvable[i] || !std::isfinite(prior[i])) continue;
    gauge.prior_photos.push_back(i);
    gauge.mean_prior += prior[i];
    lo = std::min(lo, prior[i]);
    hi = std::max(hi, prior[i]);
  }
  if (!gauge.prior_photos.empty()) gauge.mean_prior /= gauge.prior_photos.size();
  gauge.exponent_from_prior = gauge.prior_photos.size() >= 2 && hi - lo >= kMinPriorSpread;
  if (options.per_channel_exposure) {
    HDRIBR_CHECK(static_cast<int>(scalar_log_exposure.size()) == photos);
    double mean = 0;
    for (int i = 0; i < photos; ++i) mean += solvable[i] ? scalar_log_exposure[i] / solved : 0.0;
    gauge.scalar_log_exposure.assign(photos, 0.0);
    for (int i = 0; i < photos; ++i) {
      if (solvable[i]) gauge.scalar_log_exposure[i] = scalar_log_exposure[i] - mean;
    }
  }

  const Solver solver(groups, prior, slot, solved, options, gauge);
  std::vector<double> robust(groups.photo.size(), 1.0);
  double span = options.assumed_log_span > 0 ? options.assumed_log_span : SrgbLogSpan();
  Eigen::VectorXd x;
  MultiViewStats stats;
  stats.exponent_from_prior = gauge.exponent_from_prior;
  stats.response_prior = options.response_prior;
  SolveRound(solver, gauge, prior, robust, /*first=*/true, span, x, stats.iterations);
  std::vector<double> r = Residuals(groups, solver, robust, x);
  for (int round = 0; round < options.robust_rounds; ++round) {
    const double scale = RobustScale(groups, r);
    if (!(scale > 1e-12)) break;  // exact data: nothing to reweigh
    for (size_t o = 0; o < r.size(); ++o) {
      const double rho = HatWeight(groups.z[o]) * r[o];
      const double u = rho / (options.cauchy_scale * scale);
      robust[o] = std::abs(rho) > options.trim_scale * scale ? 0.0 : 1.0 / (1.0 + u * u);
    }
    SolveRound(solver, gauge, prior, robust, /*first=*/false, span, x, stats.iterations);
    r = Residuals(groups, solver, robust, x);
  }

  MultiViewCalibration result;
  result.response.source = "multiview";
  result.response.lambda = options.lambda;
  for (int c = 0; c < 3; ++c) {
    std::vector<double>& g = result.response.log_inverse[c];
    g.resize(kLevels);
    for (int z = 0; z < kLevels; ++z) g[z] = Solver::Curve(x, c, z);
    stats.monotone_fixes[c] = MakeMonotone(g);
  }
  result.log_exposure.assign(photos, 0.0);
  result.channel_log_exposure.assign(photos, {0.0, 0.0, 0.0});
  result.calibrated.assign(photos, false);
  result.photo_observations.assign(photos, 0);
  result.photo_residual_rms.assign(photos, 0.0);
  double mean_solved = 0;
  double solved_lo = std::numeric_limits<double>::infinity(), solved_hi = -solved_lo;
  for (int i = 0; i < photos; ++i) {
    if (slot[i] < 0) continue;
    const double t = solver.MeanTime(x, i);
    result.log_exposure[i] = t;
    for (int c = 0; c < 3; ++c) result.channel_log_exposure[i][c] = x(solver.TimeVar(i, c));
    result.calibrated[i] = true;
    mean_solved += t / solved;
    solved_lo = std::min(solved_lo, t);
    solved_hi = std::max(solved_hi, t);
  }
  if (!gauge.exponent_from_prior && solved_hi - solved_lo < kMinSolvedSpread) {
    throw UsageError(
        "multi-view calibration: the photos' exposures do not differ (by 10% or more) and no "
        "exposure prior tells them apart: the observations cannot constrain a response curve");
  }
  for (int i = 0; i < photos; ++i) {
    if (slot[i] < 0) {
      result.log_exposure[i] = std::isfinite(prior[i]) ? prior[i] : mean_solved;
      result.channel_log_exposure[i].fill(result.log_exposure[i]);
    }
  }
  double sum_a = 0, sum_ar2 = 0;
  std::vector<double> photo_a(photos, 0.0), photo_ar2(photos, 0.0);
  for (size_t o = 0; o < r.size(); ++o) {
    ++result.photo_observations[groups.photo[o]];
    if (robust[o] <= 0) {
      ++stats.observations_rejected;
      continue;
    }
    const double w = HatWeight(groups.z[o]);
    sum_a += w * w;
    sum_ar2 += w * w * r[o] * r[o];
    photo_a[groups.photo[o]] += w * w;
    photo_ar2[groups.photo[o]] += w * w * r[o] * r[o];
  }
  for (int i = 0; i < photos; ++i) {
    result.photo_residual_rms[i] = photo_a[i] > 0 ? std::sqrt(photo_ar2[i] / photo_a[i]) : 0.0;
  }
  stats.observations_used = static_cast<int>(r.size());
  stats.residual_rms = sum_a > 0 ? std::sqrt(sum_ar2 / sum_a) : 0.0;
  for (int k = 0; k < groups.size(); ++k) {
    stats.samples_used += k == 0 || groups.sample[k] != groups.sample[k - 1];
  }
  result.relative_exposure.resize(photos);
  for (int i = 0; i < photos; ++i) {
    result.relative_exposure[i] = std::exp(std::clamp(result.log_exposure[i], -700.0, 700.0));
  }
  result.stats = stats;
  return result;
}

}  // namespace hdribr
