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
// so lambda goes with samples. On memorial, 1000 samples with lambda 30 give a monotonic curve
// (lambda 10 bends it back at ~90 entries) with the lowest merge dispersion (docs/algorithms.md).
struct CalibrationOptions {
  double lambda = 30.0;  // smoothness weight (Debevec's lambda)
  int samples = 1000;    // pixel locations per channel, spread over intensities and the image
};

struct CalibrationStats {
  std::array<int, 3> samples_used{};    // samples seen well exposed in >= 2 images, per channel
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
