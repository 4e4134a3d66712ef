#include "core/exposure_series.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hdribr {

std::vector<ExposureSeries> GroupByExposure(std::vector<Photo>& photos, double tolerance_ev) {
  std::vector<int> order(photos.size());
  std::iota(order.begin(), order.end(), 0);
  auto ev = [&](int i) { return std::log2(photos[i].exposure.Relative()); };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return ev(a) < ev(b); });

  // Single-linkage clustering along the sorted EV axis, but a series never spans more than
  // tolerance_ev from its first member (so slow drifts do not chain into one series).
  std::vector<ExposureSeries> series;
  double first_ev = 0;
  for (int i : order) {
    if (series.empty() || ev(i) - first_ev > tolerance_ev + 1e-9) {
      ExposureSeries s;
      s.id = static_cast<int>(series.size());
      s.name = "series" + std::to_string(s.id);
      series.push_back(s);
      first_ev = ev(i);
    }
    series.back().photo_indices.push_back(i);
  }
  for (auto& s : series) {
    double sum = 0;
    for (int i : s.photo_indices) {
      sum += ev(i);
      photos[i].series_id = s.id;
    }
    s.relative_exposure = std::exp2(sum / static_cast<double>(s.photo_indices.size()));
    std::sort(s.photo_indices.begin(), s.photo_indices.end());
  }
  return series;
}

}  // namespace hdribr
