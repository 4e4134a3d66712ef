#include "hdr/multiview_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core/utility.hpp>

#include "core/error.h"
#include "hdr/multiview_solver.h"
#include "hdr/re_expose.h"

namespace hdribr {
namespace {

// Throws OptionError naming the first option no computation can use.
void ValidateOptions(const MultiViewOptions& o) {
  if (!std::isfinite(o.lambda) || o.lambda < 0) {
    throw OptionError("lambda", "must be a non-negative number");
  }
  if (o.clip_margin < 0 || o.clip_margin > 126) {
    throw OptionError("clip_margin", "must be in 0..126");
  }
  if (!(o.prior_sigma > 0) || !std::isfinite(o.prior_sigma)) {
    throw OptionError("prior_sigma", "must be a positive number");
  }
  if (!(o.observation_sigma > 0) || !std::isfinite(o.observation_sigma)) {
    throw OptionError("observation_sigma", "must be a positive number");
  }
  if (o.robust_rounds < 0) throw OptionError("robust_rounds", "must be >= 0");
  if (!(o.response_prior >= 0) || !std::isfinite(o.response_prior)) {
    throw OptionError("response_prior", "must be a non-negative number");
  }
  for (double candidate : o.response_prior_candidates) {
    if (!(candidate >= 0) || !std::isfinite(candidate)) {
      throw OptionError("response_prior_candidates", "must be non-negative numbers");
    }
  }
  if (!(o.channel_sigma > 0) || !std::isfinite(o.channel_sigma)) {
    throw OptionError("channel_sigma", "must be a positive number");
  }
  if (!(o.cauchy_scale > 0) || !std::isfinite(o.cauchy_scale)) {
    throw OptionError("cauchy_scale", "must be a positive number");
  }
  if (!(o.trim_scale > 0)) throw OptionError("trim_scale", "must be a positive number");
  if (!(o.assumed_log_span >= 0) || !std::isfinite(o.assumed_log_span)) {
    throw OptionError("assumed_log_span", "must be a non-negative number");
  }
}
// The calibration for options.response_prior (no cross-validation): with
// per_channel_exposure, a solve with one exposure per photo first, to whose exposures the
// channels' offsets are held orthogonal, then the per-channel solve.
MultiViewCalibration CalibrateOnePrior(const std::vector<MultiViewSample>& samples,
                                       const std::vector<double>& prior_log_exposure,
                                       const MultiViewOptions& options) {
  if (!options.per_channel_exposure) return SolveMultiView(samples, prior_log_exposure, options);
  MultiViewOptions scalar_options = options;
  scalar_options.per_channel_exposure = false;
  const MultiViewCalibration scalar = SolveMultiView(samples, prior_log_exposure, scalar_options);
  return SolveMultiView(samples, prior_log_exposure, options, scalar.log_exposure);
}

// Mean |z - g^-1(ln E + ln t)| (DN) over the observations of `samples` from calibrated photos
// with values in (margin, 255 - margin), ln E the w(z)^2-weighted mean of g(z) - ln t over the
// sample's other such observations in the channel. Adds the errors and their squares to `sum`
// and `sum2`, their number to `count`.
void AddCodeError(const MultiViewCalibration& fit, const std::vector<MultiViewSample>& samples,
                  int margin, double& sum, double& sum2, long& count) {
  std::vector<std::pair<int, double>> obs;  // (z, ln t)
  for (const MultiViewSample& sample : samples) {
    for (int c = 0; c < 3; ++c) {
      const std::vector<double>& g = fit.response.log_inverse[c];
      obs.clear();
      double total = 0, weighted = 0;
      for (const MultiViewObservation& o : sample.observations) {
        const int z = o.bgr[c];
        if (z <= margin || z >= 255 - margin || !fit.calibrated[o.photo]) continue;
        const double log_t = fit.channel_log_exposure[o.photo][c];
        const double a = HatWeight(z) * HatWeight(z);
        obs.emplace_back(z, log_t);
        total += a;
        weighted += a * (g[z] - log_t);
      }
      if (obs.size() < 2) continue;
      for (const auto& [z, log_t] : obs) {
        const double a = HatWeight(z) * HatWeight(z);
        if (!(total - a > 0)) continue;
        const double log_e = (weighted - a * (g[z] - log_t)) / (total - a);
        const double e = std::abs(CodeOfLog(g, log_e + log_t) - z);
        sum += e;
        sum2 += e * e;
        ++count;
      }
    }
  }
}

// Mean of a cross-validated error and its standard error.
struct CodeError {
  double mean = std::numeric_limits<double>::infinity();
  double standard_error = 0.0;
};

// Per candidate of options.response_prior_candidates, the two-fold cross-validated
// re-exposure error (MultiViewOptions::response_prior_candidates); an infinite mean when a
// half cannot be calibrated. The fits run in parallel.
std::vector<CodeError> CrossValidatedCodeErrors(const std::vector<MultiViewSample>& samples,
                                                const std::vector<double>& prior,
                                                const MultiViewOptions& options) {
  std::array<std::vector<MultiViewSample>, 2> half;  // even and odd samples
  for (size_t j = 0; j < samples.size(); ++j) half[j % 2].push_back(samples[j]);
  const int candidates = static_cast<int>(options.response_prior_candidates.size());
  struct Sums {
    double sum = 0, sum2 = 0;
    long count = 0;
    bool failed = false;
  };
  std::vector<Sums> sums(2 * candidates);  // per candidate and test half
  cv::parallel_for_(cv::Range(0, 2 * candidates), [&](const cv::Range& range) {
    for (int k = range.start; k < range.end; ++k) {
      MultiViewOptions single = options;
      single.response_prior_candidates.clear();
      single.response_prior = options.response_prior_candidates[k / 2];
      // Two robust rounds: the first ones drop the outliers; the last ones move the fit
      // little and would multiply the cost.
      single.robust_rounds = std::min(single.robust_rounds, 2);
      const int test = k % 2;
      try {
        const MultiViewCalibration fit = CalibrateOnePrior(half[1 - test], prior, single);
        AddCodeError(fit, half[test], options.clip_margin, sums[k].sum, sums[k].sum2,
                     sums[k].count);
      } catch (const UsageError&) {
        sums[k].failed = true;
      }
    }
  });
  std::vector<CodeError> errors(candidates);
  for (int c = 0; c < candidates; ++c) {
    const Sums& a = sums[2 * c];
    const Sums& b = sums[2 * c + 1];
    const long count = a.count + b.count;
    if (a.failed || b.failed || count < 2) continue;
    const double mean = (a.sum + b.sum) / count;
    const double variance = std::max(0.0, (a.sum2 + b.sum2 - count * mean * mean) / (count - 1.0));
    errors[c] = {mean, std::sqrt(variance / count)};
  }
  return errors;
}

}  // namespace

MultiViewCalibration CalibrateMultiView(const std::vector<MultiViewSample>& samples,
                                        const std::vector<double>& prior_log_exposure,
                                        const MultiViewOptions& options) {
  ValidateOptions(options);
  if (options.response_prior_candidates.size() >= 2) {
    MultiViewOptions single = options;
    single.response_prior_candidates.clear();
    const std::vector<CodeError> errors =
        CrossValidatedCodeErrors(samples, prior_log_exposure, options);
    CodeError lowest;
    for (const CodeError& e : errors) {
      if (e.mean < lowest.mean) lowest = e;
    }
    // The weakest prior within one standard error of the lowest error (the one-standard-error
    // rule, Hastie, Tibshirani & Friedman, The Elements of Statistical Learning, 7.10): the
    // prior pulls toward sRGB only as far as the data show a gain.
    single.response_prior = options.response_prior;  // when no candidate calibrates the halves
    double weakest = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < errors.size(); ++k) {
      const double candidate = options.response_prior_candidates[k];
      if (errors[k].mean <= lowest.mean + lowest.standard_error && candidate < weakest) {
        weakest = candidate;
        single.response_prior = candidate;
      }
    }
    MultiViewCalibration result = CalibrateOnePrior(samples, prior_log_exposure, single);
    for (const CodeError& e : errors) result.stats.prior_code_error.push_back(e.mean);
    return result;
  }
  return CalibrateOnePrior(samples, prior_log_exposure, options);
}

}  // namespace hdribr
