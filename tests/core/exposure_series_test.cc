#include "core/exposure_series.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hdribr {
namespace {

Photo WithExposure(double t, double iso, double f) {
  Photo p;
  p.exposure.time_s = t;
  p.exposure.iso = iso;
  p.exposure.f_number = f;
  return p;
}

TEST(Exposure, RelativeFormula) {
  EXPECT_DOUBLE_EQ(WithExposure(0.01, 200, 2.0).exposure.Relative(), 0.01 * 2.0 / 4.0);
  Exposure missing;
  EXPECT_DOUBLE_EQ(missing.Relative(), 1.0);
  EXPECT_FALSE(missing.Complete());
}

TEST(GroupByExposure, GroupsWithinOneSixthEv) {
  std::vector<Photo> photos = {
      WithExposure(1.0 / 60, 100, 4),  WithExposure(1.0 / 15, 100, 4),
      WithExposure(1.0 / 60, 110, 4),  // +0.14 EV: same series
      WithExposure(1.0 / 250, 100, 4), WithExposure(1.0 / 15, 100, 4),
      WithExposure(1.0 / 60, 125, 4),  // +0.32 EV: a new series
  };
  const auto series = GroupByExposure(photos);
  ASSERT_EQ(series.size(), 4u);
  EXPECT_EQ(series[0].photo_indices, std::vector<int>({3}));
  EXPECT_EQ(series[1].photo_indices, std::vector<int>({0, 2}));
  EXPECT_EQ(series[2].photo_indices, std::vector<int>({5}));
  EXPECT_EQ(series[3].photo_indices, std::vector<int>({1, 4}));
  EXPECT_EQ(photos[2].series_id, 1);
  EXPECT_LT(series[0].relative_exposure, series[1].relative_exposure);
}

TEST(GroupByExposure, DriftDoesNotChain) {
  // Each step is 0.1 EV: chaining would give one series spanning 0.5 EV.
  std::vector<Photo> photos;
  for (int i = 0; i < 6; ++i) photos.push_back(WithExposure(0.01 * std::exp2(0.1 * i), 100, 1));
  const auto series = GroupByExposure(photos);
  EXPECT_GE(series.size(), 3u);
}

}  // namespace
}  // namespace hdribr
