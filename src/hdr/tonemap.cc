#include "hdr/tonemap.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>

#include "core/error.h"

namespace hdribr {

double LogAverageLuminance(const cv::Mat& radiance, const cv::Mat& valid, double epsilon) {
  HDRIBR_CHECK(radiance.type() == CV_32FC3);
  HDRIBR_CHECK(valid.empty() || (valid.type() == CV_8UC1 && valid.size() == radiance.size()));
  double sum = 0;
  long count = 0;
  for (int y = 0; y < radiance.rows; ++y) {
    const float* px = radiance.ptr<float>(y);
    const uint8_t* m = valid.empty() ? nullptr : valid.ptr<uint8_t>(y);
    for (int x = 0; x < radiance.cols; ++x) {
      if (m && !m[x]) continue;
      const double l = std::max(0.0, Luminance(px[3 * x], px[3 * x + 1], px[3 * x + 2]));
      sum += std::log(epsilon + l);
      ++count;
    }
  }
  if (count == 0) return 1.0;
  const double result = std::exp(sum / static_cast<double>(count));
  return std::isfinite(result) && result > 0 ? result : 1.0;
}

cv::Mat ToneMapReinhard(const cv::Mat& radiance, const ReinhardOptions& options,
                        const cv::Mat& valid) {
  HDRIBR_CHECK(radiance.type() == CV_32FC3);
  HDRIBR_CHECK(valid.empty() || (valid.type() == CV_8UC1 && valid.size() == radiance.size()));
  if (!(options.key > 0) || !(options.gamma > 0) || !(options.exposure >= 0) ||
      !std::isfinite(options.key) || !std::isfinite(options.gamma) ||
      !std::isfinite(options.exposure)) {
    throw UsageError("tone mapping needs key > 0, gamma > 0 and exposure >= 0");
  }
  if (options.log_average && !(*options.log_average > 0 && std::isfinite(*options.log_average))) {
    throw UsageError("a fixed log-average luminance must be positive");
  }
  const double l_a = options.log_average ? *options.log_average
                                         : LogAverageLuminance(radiance, valid, options.epsilon);
  const double scale = options.key / l_a;
  const double inv_gamma = 1.0 / options.gamma;
  cv::Mat display(radiance.size(), CV_32FC3);
  cv::parallel_for_(cv::Range(0, radiance.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const float* in = radiance.ptr<float>(y);
      const uint8_t* m = valid.empty() ? nullptr : valid.ptr<uint8_t>(y);
      float* out = display.ptr<float>(y);
      for (int x = 0; x < radiance.cols; ++x) {
        const double l = Luminance(in[3 * x], in[3 * x + 1], in[3 * x + 2]);
        if ((m && !m[x]) || !(l > 0) || !std::isfinite(l)) {
          out[3 * x] = out[3 * x + 1] = out[3 * x + 2] = 0.0f;
          continue;
        }
        const double l_s = scale * l;
        const double ratio = options.exposure * (l_s / (1.0 + l_s)) / l;
        for (int c = 0; c < 3; ++c) {
          const double v = std::max(0.0, ratio * in[3 * x + c]);
          out[3 * x + c] = static_cast<float>(std::min(1.0, std::pow(v, inv_gamma)));
        }
      }
    }
  });
  return display;
}

cv::Mat DisplayToBgr8(const cv::Mat& display) {
  HDRIBR_CHECK(display.type() == CV_32FC3);
  cv::Mat out;
  display.convertTo(out, CV_8UC3, 255.0);  // saturate_cast rounds and clamps
  return out;
}

}  // namespace hdribr
