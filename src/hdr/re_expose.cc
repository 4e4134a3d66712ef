#include "hdr/re_expose.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace hdribr {

double CodeOfLog(const std::vector<double>& g, double log_value) {
  if (std::isnan(log_value)) return 0.0;
  // First code whose g exceeds the value; interpolate with the one below.
  const auto it = std::upper_bound(g.begin(), g.end(), log_value);
  if (it == g.begin()) return 0.0;
  if (it == g.end()) return static_cast<double>(g.size() - 1);
  const size_t hi = static_cast<size_t>(it - g.begin());
  const double g0 = g[hi - 1], g1 = g[hi];
  return static_cast<double>(hi - 1) + (g1 > g0 ? (log_value - g0) / (g1 - g0) : 0.0);
}

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
        const double code = CodeOfLog(g, std::log(v) + log_exposure);
        z[x][c] = static_cast<std::uint8_t>(std::clamp(std::lround(code), 0L, 255L));
      }
    }
  }
  return out;
}

}  // namespace hdribr
