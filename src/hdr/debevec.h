// Debevec & Malik 1997, "Recovering High Dynamic Range Radiance Maps from Photographs":
// response calibration (section 2.1) and radiance merge (equation 6; LEC19 equation 7).
#pragma once

#include <array>
#include <opencv2/core.hpp>

#include "hdr/exposure_stack.h"
#include "hdr/response_curve.h"

namespace hdribr {

// Debevec's hat weight w(z) = min(z, 255 - z): 0 at 0 and 255, 127 in the middle.
double HatWeight(int z);

// Defaults: the data term grows with the number of samples while the smoothness term does not,
// so lambda goes with samples. The flat-sample selection, the trimmed refit and the log-code
// smoothness make the curve robust to misaligned or resampled exposures (their effect is
// measured in docs/decisions/0005 and 0008); PlainDebevec gives the
// published method.
struct CalibrationOptions {
  double lambda = 60.0;  // smoothness weight (Debevec's lambda)
  int samples = 1000;    // pixel locations per channel, spread over intensities and the image
  // Variable of the smoothness term's second difference: the pixel value z (Debevec's
  // g''(z)) or u = ln(z + 0.5), in which gamma-like curves (g ~ gamma ln z at the dark end)
  // are nearly straight, so that the term stops pulling the dark end toward a line in z.
  enum class Smoothness { kCode, kLogCode };
  Smoothness smoothness = Smoothness::kLogCode;
  // Share of the candidate pixels kept in each intensity bin, the flattest first (3x3 range
  // summed over the images, away from mask borders): at edges, resampled or misaligned
  // exposures disagree. 1 = every candidate (Debevec).
  double flat_fraction = 0.3;
  // Share of the samples with the largest residual (RMS over the images of g(Z) - ln t - ln E
  // after the fit) dropped before solving again, twice: over all samples, then, residuals
  // recomputed with that fit, within each intensity bin of the reference exposure (plus any
  // residual over 10x the median); 0 = a single solve (Debevec).
  double trim = 0.3;
};

// `options` with Debevec & Malik's method as published: smoothness in z, every candidate
// sample, a single solve (lambda and samples kept).
CalibrationOptions PlainDebevec(CalibrationOptions options = {});

// The smoothness term's second difference at code k (1..254) as coefficients of g(k-1), g(k),
// g(k+1): (1, -2, 1) in z (Debevec's g''), or in u = ln(z + 0.5) scaled by the mean step.
std::array<double, 3> SmoothnessStencil(int k, CalibrationOptions::Smoothness axis);

struct CalibrationStats {
  std::array<int, 3> samples_used{};    // samples well exposed in >= 2 images, kept after trim
  std::array<int, 3> monotone_fixes{};  // entries raised/lowered to keep g non-decreasing
};

// Recovers g = ln f^-1 per channel by weighted least squares with g(128) = 0. Samples are taken
// only where every image is valid. Throws UsageError when the stack cannot constrain a curve
// (fewer than two distinct exposure times, no pixel well exposed in two images).
ResponseCurve CalibrateDebevec(const ExposureStack& stack, const CalibrationOptions& options = {},
                               CalibrationStats* stats = nullptr);

struct MergeStats {
  int saturated = 0;  // pixel-channels saturated in every valid image (shortest exposure used)
  int dark = 0;       // pixel-channels black in every valid image (longest exposure used)
  int invalid = 0;    // pixels valid in no image (radiance 0, validity 0)
};

// Radiance map E (CV_32FC3, linear, in units of exp(g) per unit time) by
// ln E = sum_j w(Z_j) (g(Z_j) - ln t_j) / sum_j w(Z_j) over the images valid at the pixel.
// All-saturated pixel-channels take the shortest exposure's g(Z) - ln t, all-dark ones the
// longest's. Never NaN or Inf. `valid` (optional) receives CV_8UC1 255 where some image was valid.
cv::Mat MergeDebevec(const ExposureStack& stack, const ResponseCurve& response,
                     cv::Mat* valid = nullptr, MergeStats* stats = nullptr);

}  // namespace hdribr
