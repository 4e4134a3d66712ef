// Synthetic exposure stacks with a known camera response, made in code for the HDR tests.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/core.hpp>
#include <random>
#include <vector>

#include "hdr/exposure_stack.h"
#include "hdr/radiance_compare.h"
#include "hdr/response_curve.h"

namespace hdribr::test {

// A smooth S-shaped gamma response per channel: z = 255 s(min(X, 1)^(1/gamma_c)) with
// s(u) = u + 0.08 sin(2 pi u) / (2 pi), strictly increasing.
class SyntheticResponse {
 public:
  double Pixel(int c, double x) const {
    const double u = std::pow(std::clamp(x, 0.0, 1.0), 1.0 / kGamma[c]);
    return 255.0 * (u + 0.08 * std::sin(2 * M_PI * u) / (2 * M_PI));
  }
  // X with Pixel(c, X) = z (bisection), z in (0, 255].
  double Inverse(int c, double z) const {
    double lo = 0, hi = 1;
    for (int i = 0; i < 80; ++i) {
      const double mid = 0.5 * (lo + hi);
      (Pixel(c, mid) < z ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
  // The true g = ln f^-1 at each 8-bit value (value 0 is taken at 0.25 DN).
  ResponseCurve Truth() const {
    ResponseCurve curve;
    curve.source = "synthetic-truth";
    for (int c = 0; c < 3; ++c) {
      curve.log_inverse[c].resize(256);
      for (int z = 0; z < 256; ++z)
        curve.log_inverse[c][z] = std::log(Inverse(c, z == 0 ? 0.25 : z));
    }
    return curve;
  }

 private:
  static constexpr double kGamma[3] = {1.8, 2.2, 2.6};
};

// Radiance map with a smooth horizontal ramp over e^-7..e^2 and a vertical tint (CV_32FC3).
inline cv::Mat SyntheticRadiance(int width = 160, int height = 120) {
  cv::Mat e(height, width, CV_32FC3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double base = std::exp(-7.0 + 9.0 * x / (width - 1)) * (1.0 + 0.5 * y / height);
      e.at<cv::Vec3f>(y, x) = cv::Vec3f(0.7 * base, 1.0 * base, 1.3 * base);
    }
  }
  return e;
}

// Quantised exposures of `radiance` at `times` through `response`, with Gaussian sensor noise.
inline ExposureStack SyntheticStack(const cv::Mat& radiance, const std::vector<double>& times,
                                    const SyntheticResponse& response, double noise_dn = 0.5,
                                    unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_dn);
  ExposureStack stack;
  stack.times = times;
  for (double t : times) {
    cv::Mat image(radiance.size(), CV_8UC3);
    for (int y = 0; y < radiance.rows; ++y) {
      for (int x = 0; x < radiance.cols; ++x) {
        for (int c = 0; c < 3; ++c) {
          const double z = response.Pixel(c, radiance.at<cv::Vec3f>(y, x)[c] * t) + noise(rng);
          image.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uint8_t>(std::lround(z));
        }
      }
    }
    stack.images.push_back(image);
  }
  return stack;
}

// The comparison used by the tests lives in the library (hdr/radiance_compare.h).
using ::hdribr::MedianAbsLogRatio;

}  // namespace hdribr::test
