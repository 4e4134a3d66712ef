// Radiometric calibration from multi-view observations: the camera response g = ln f^-1 per
// channel (Debevec & Malik 1997, section 2.1) solved jointly with one log exposure per photo,
// from the 8-bit values of 3D points seen by several photos of any exposure series.
#pragma once

#include <array>
#include <vector>

#include "hdr/debevec.h"
#include "hdr/multiview_samples.h"
#include "hdr/response_curve.h"

namespace hdribr {

// Options of CalibrateMultiView. Weights are in the units of Debevec's equations: a data
// equation of value z has weight w(z) = HatWeight(z) (at most 127).
struct MultiViewOptions {
  // Smoothness weight of g'' (Debevec's lambda, equation 3). Larger than the aligned-stack
  // default: thousands of points seen by tens of photos give tens of thousands of data
  // equations per channel (docs/decisions/0018).
  double lambda = 600.0;
  // Variable of the smoothness term's second difference, as in CalibrationOptions.
  CalibrationOptions::Smoothness smoothness = CalibrationOptions::Smoothness::kLogCode;
  // Values <= margin or >= 255 - margin carry no data equation (clipped or nearly).
  int clip_margin = 2;
  // Standard deviation (natural log units) of a prior log exposure, and of a mid-grey
  // observation's g(z) - ln E - ln t: their ratio weighs the prior of one photo against the
  // data (a prior counts as (observation_sigma / prior_sigma)^2 mid-grey observations).
  double prior_sigma = 0.1;
  double observation_sigma = 0.02;
  // Robust refits after the first least-squares solve: iteratively reweighted with Cauchy
  // weights 1 / (1 + (rho / (cauchy_scale s))^2) on rho = w(z) r, s the robust (MAD) scale of
  // rho; observations with |rho| > trim_scale s are dropped. 0 = a single plain solve.
  int robust_rounds = 6;
  double cauchy_scale = 2.385;
  double trim_scale = 5.0;
  // Used only when no two prior exposures differ by 10 % (no prior, or one exposure for all
  // photos): the exponent that the response shares with the exposures, which the data cannot
  // fix (g -> k g, ln t -> k ln t, ln E -> k ln E only scales every residual by k), is set by
  // taking the mean over channels of g(192) - g(64) as this value (natural log; the default
  // is sRGB's, about 2.33).
  double assumed_log_span = 0.0;  // 0 = sRGB's value
  // Weight of a prior on the response's slope: response_prior w(k)^2 [g_c(k + 1) - g_c(k) -
  // s (r(k + 1) - r(k))]^2 for codes 1..253, r = ln of sRGB's decoding (IEC 61966-2-1) and s
  // the exponent the gauge sets (the mean g(192) - g(64) over sRGB's). The data alone bend g
  // flat where photos of nearly equal exposure disagree by noise or misregistration (the
  // flatter g, the smaller the log residual); 0 = no prior.
  double response_prior = 0.0;
  // Candidates for response_prior, chosen by two-fold cross-validation over the samples (even
  // and odd): each is fitted on one half and scored on the other by the mean |z - z'| (DN) of
  // every observation z against z' = g^-1(ln E + ln t), ln E from the sample's other
  // observations: the error of re-exposing one photo's values from the others'. Fewer than two
  // candidates: response_prior is used as given.
  std::vector<double> response_prior_candidates = {0.0, 1e2, 1e3, 1e4, 1e5, 1e6};
  // One log exposure per photo and channel (a per-shot white balance) instead of one per
  // photo: ln t_ic, with the mean over channels held to the photo's prior, each channel's
  // offset from that mean held to 0 with standard deviation channel_sigma (natural log), and
  // the offsets held orthogonal to the exposures of a first solve with one exposure per photo
  // (offsets growing with the exposure are an exponent per channel, which the data leave free).
  bool per_channel_exposure = false;
  double channel_sigma = 0.05;  // see per_channel_exposure
};

// Counts and figures of a multi-view calibration.
struct MultiViewStats {
  int samples_used = 0;           // samples with >= 2 usable observations in some channel
  int observations_used = 0;      // channel observations with a data equation (weight > 0)
  int observations_rejected = 0;  // of those, dropped by the robust trim in the last round
  // RMS of g(z) - ln E - ln t (natural log), w(z)-weighted, over the observations kept in
  // the last round.
  double residual_rms = 0.0;
  int iterations = 0;                   // least-squares solves
  bool exponent_from_prior = false;     // false: fixed by assumed_log_span (no prior ratios)
  std::array<int, 3> monotone_fixes{};  // entries clamped to keep g non-decreasing
  double response_prior = 0.0;          // the response prior's weight used
  // Per candidate of MultiViewOptions::response_prior_candidates: its cross-validated mean
  // re-exposure error (DN), infinity where a half could not be calibrated; empty without.
  std::vector<double> prior_code_error;
};

// Result of CalibrateMultiView.
struct MultiViewCalibration {
  ResponseCurve response;  // source "multiview", g(128) = 0 per channel
  // Per photo: natural log of the exposure (time x gain, in the prior's units when a prior
  // exists, else with mean 0 over the calibrated photos) and exp() of it.
  std::vector<double> log_exposure;
  std::vector<double> relative_exposure;
  // Per photo and channel (BGR): ln t_ic; the three equal log_exposure without
  // per_channel_exposure. Their mean over the channels is log_exposure.
  std::vector<std::array<double, 3>> channel_log_exposure;
  // Per photo: true when its exposure was solved from observations; false for a photo outside
  // the largest set of photos linked by shared scene points (e.g. one with no usable
  // observation), which keeps its prior or, without one, the calibrated photos' mean.
  std::vector<bool> calibrated;
  std::vector<int> photo_observations;  // channel observations per photo (before the trim)
  // Per photo: RMS of its kept observations' residuals (natural log, w(z)-weighted); 0 without.
  std::vector<double> photo_residual_rms;
  MultiViewStats stats;
};

// Recovers g per channel and ln t per photo (shared by the channels) by weighted least squares
// over w(z) [g_c(z_ijc) - ln E_jc - ln t_i] (Debevec & Malik equation 3 with the exposure an
// unknown), lambda w(z) g''(z), the gauge g_c(128) = 0, and the exposure prior:
// `prior_log_exposure` holds ln of each photo's EXIF relative exposure (Exposure::Relative()),
// NaN where unknown, or is empty. The data fix the exposures only up to a common factor and an
// exponent shared with g (g -> k g, ln t -> k ln t); the prior fixes both by regression (its
// mean and its slope against the solved exposures) when two priors differ by 10 % or more,
// and each photo's prior weighs as prior_sigma says. Otherwise the exposures have mean 0 (or
// the priors' mean) and the exponent comes from assumed_log_span. Photos are indices 0 ..
// prior size - 1 (up to the largest index observed when the prior is empty). Observations are
// reweighted robustly; the weight of the prior on the response's slope is chosen by
// cross-validation among MultiViewOptions::response_prior_candidates. Throws UsageError when
// the observations cannot constrain a curve (fewer than two photos, no point well exposed in
// two photos, photos all exposed alike without a prior telling them apart). Never NaN.
MultiViewCalibration CalibrateMultiView(const std::vector<MultiViewSample>& samples,
                                        const std::vector<double>& prior_log_exposure,
                                        const MultiViewOptions& options = {});

}  // namespace hdribr
