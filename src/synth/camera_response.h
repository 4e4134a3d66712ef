// The synthetic camera's known response: linear exposure -> 8-bit value, per channel, with
// sensor noise. Its exact inverse is written as the capture's true response curve.
#pragma once

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>

#include "hdr/response_curve.h"

namespace hdribr::synth {

// z = 255 f_c(X / x_sat), f_c(x) = h(s_c(x)), h(y) = y (1 + k_c) / (y + k_c): a gamma curve
// with a linear toe (as sRGB's: s(x) = phi x below x = toe, (1 + a) x^(1/gamma) - a above, a
// and phi making value and slope continuous) followed by a soft shoulder, different per
// channel (BGR order), clipped at x = 1. Why the toe: a pure power law has an infinite gain at
// black, which turns the read noise into the lowest ~25 codes (real tone curves, sRGB and
// Rec. 709, have a bounded slope there).
struct SyntheticResponse {
  std::array<double, 3> gamma = {2.5, 2.2, 1.9};  // B, G, R
  std::array<double, 3> knee = {0.6, 0.45, 0.35};
  double x_sat = 0.011;  // linear exposure (radiance x seconds) that saturates the sensor
  // End of the linear toe in units of x (sRGB's 0.0031308: codes below about 25 linear);
  // 0 = a pure power law down to black (captures made before the toe).
  double toe = 0.0031308;
  // Noise in units of x = X / x_sat: sigma^2 = shot * x + read^2 (before the response).
  double shot = 5e-6;
  double read = 3e-4;

  // Continuous (unquantised) value in [0, 255] for a linear exposure X >= 0 in channel c.
  double ValueFromExposure(int c, double exposure) const;
  // Linear exposure that gives the continuous value z in (0, 255] in channel c.
  double ExposureFromValue(int c, double z) const;
  // g(z) = ln X for z = 0..255 per channel (z = 0 uses z = 0.5; z = 255 the clipping point).
  ResponseCurve Curve() const;
  // s_c(x) and its inverse: the toe-and-gamma part of the curve, before the shoulder.
  double Encode(int c, double x) const;
  double Decode(int c, double y) const;
  // An 8-bit BGR photo of linear BGR radiance (CV_32FC3) exposed for `time_s` seconds, with
  // noise from generators seeded with `noise_seed` (deterministic for any thread count).
  cv::Mat Expose(const cv::Mat& radiance, double time_s, std::uint64_t noise_seed,
                 int threads = 0) const;
};

// SplitMix64: a small portable generator (same numbers on every platform and library).
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next();
  double Uniform();   // in [0, 1)
  double Gaussian();  // standard normal (Box-Muller)
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }

 private:
  std::uint64_t state_;
};

}  // namespace hdribr::synth
