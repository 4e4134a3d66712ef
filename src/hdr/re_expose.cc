#include "hdr/re_expose.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace hdribr {

cv::Mat ExposeThroughResponse(const cv::Mat& radiance, const ResponseCurve& response,
                              double exposure) {
  HDRIBR_CHECK(radiance.type() == CV_32FC3 && response.IsValid() && exposure > 0);
  const double log_exposure = std::log(exposure);
  cv::Mat out(radiance.size(), CV_8UC3);
  for (int y = 0; y < radiance.rows; ++y) {
    const auto* e = radiance.ptr<cv::Vec3f>(y);
    auto* z = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < radiance.cols; ++x) {
      for (int c = 0; c < 3; ++c) {
        const std::vector<double>& g = response.log_inverse[static_cast<size_t>(c)];
        const double v = e[x][c];
        if (!(v > 0) || !std::isfinite(v)) {
          z[x][c] = 0;
          continue;
        }
        const double target = std::log(v) + log_exposure;
        // First code whose g exceeds the target; interpolate with the one below.
        const auto it = std::upper_bound(g.begin(), g.end(), target);
        double code = 0;
        if (it == g.begin()) {
          code = 0;
        } else if (it == g.end()) {
          code = 255;
        } else {
          const int hi = static_cast<int>(it - g.begin());
          const double g0 = g[static_cast<size_t>(hi - 1)], g1 = g[static_cast<size_t>(hi)];
          code = hi - 1 + (g1 > g0 ? (target - g0) / (g1 - g0) : 0.0);
        }
        z[x][c] = static_cast<std::uint8_t>(std::clamp(std::lround(code), 0L, 255L));
      }
    }
  }
  return out;
}

}  // namespace hdribr
