#include "hdr/radiance_compare.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "core/error.h"

namespace hdribr {
namespace {

double Median(std::vector<double>& v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

double MedianAbsLogRatio(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask,
                         bool per_channel) {
  HDRIBR_CHECK(a.type() == CV_32FC3 && b.type() == CV_32FC3 && a.size() == b.size());
  HDRIBR_CHECK(mask.empty() || (mask.type() == CV_8UC1 && mask.size() == a.size()));
  std::array<std::vector<double>, 3> d;
  for (int y = 0; y < a.rows; ++y) {
    const float* pa = a.ptr<float>(y);
    const float* pb = b.ptr<float>(y);
    const uint8_t* m = mask.empty() ? nullptr : mask.ptr<uint8_t>(y);
    for (int x = 0; x < a.cols; ++x) {
      if (m && !m[x]) continue;
      for (int c = 0; c < 3; ++c) {
        const double va = pa[3 * x + c], vb = pb[3 * x + c];
        if (va > 0 && vb > 0 && std::isfinite(va) && std::isfinite(vb)) {
          d[per_channel ? c : 0].push_back(std::log(va / vb));
        }
      }
    }
  }
  std::vector<double> residual;
  for (auto& dc : d) {
    if (dc.empty()) continue;
    const double scale = Median(dc);
    for (double v : dc) residual.push_back(std::abs(v - scale));
  }
  if (residual.empty()) return std::numeric_limits<double>::infinity();
  return Median(residual);
}

}  // namespace hdribr
