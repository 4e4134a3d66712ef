// Reinhard et al. 2002 global tone-mapping operator, CPU reference (LEC19 equations 8-12).
// The GPU tone-map pass must agree with this within 1e-3.
#pragma once

#include <opencv2/core.hpp>
#include <optional>

namespace hdribr {

struct ReinhardOptions {
  double key = 0.18;                  // k: the key, mid-grey of the scaled image (eq. 10)
  double exposure = 1.0;              // multiplier before gamma (eq. 12)
  double gamma = 2.2;                 // display gamma (eq. 12)
  double epsilon = 1e-6;              // offset inside the log of the log-average (eq. 9)
  std::optional<double> log_average;  // fixed L_a (e.g. over a whole photo set): no flicker
};

// Rec. 709 luminance of a linear BGR pixel (eq. 8): 0.2126 R + 0.7152 G + 0.0722 B.
inline double Luminance(double b, double g, double r) {
  return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

// L_a = exp(mean(log(epsilon + L))) over the pixels of a CV_32FC3 radiance map where `valid`
// (optional CV_8UC1) is nonzero. This is the standard log-average: the paper's equation 9
// puts 1/N outside the exp by mistake. Returns 1 when no pixel is valid.
double LogAverageLuminance(const cv::Mat& radiance, const cv::Mat& valid = {},
                           double epsilon = 1e-6);

// Display colour per channel C: (exposure * C * L_d / L)^(1/gamma) clamped to [0, 1], with
// L_s = key / L_a * L and L_d = L_s / (1 + L_s). Pixels with L <= 0 or invalid give 0.
// Returns CV_32FC3 in [0, 1].
cv::Mat ToneMapReinhard(const cv::Mat& radiance, const ReinhardOptions& options,
                        const cv::Mat& valid = {});

// 8-bit display image from a [0, 1] CV_32FC3 image (rounded).
cv::Mat DisplayToBgr8(const cv::Mat& display);

}  // namespace hdribr
