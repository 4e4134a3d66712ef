#include "frontend/photo_folder.h"

#include <gtest/gtest.h>

#include <set>

#include "core/error.h"
#include "test_util.h"

namespace hdribr {
namespace {

TEST(PhotoFolder, GroupsPhysicalCamerasByMakeModelAndSize) {
  std::vector<InputPhoto> photos(4);
  photos[0].exif.make = "Apple";
  photos[0].exif.model = "iPhone 7";
  photos[0].width = 1600;
  photos[0].height = 1200;
  photos[1] = photos[0];
  photos[2] = photos[0];
  photos[2].width = 1200;  // portrait crop: a different camera for COLMAP
  photos[2].height = 1600;
  photos[3] = photos[0];
  photos[3].exif.model = "iPhone 8";
  const auto groups = GroupByCamera(photos);
  ASSERT_EQ(groups.size(), 3u);
  EXPECT_EQ(groups[0].photo_indices, (std::vector<int>{0, 1}));
  EXPECT_EQ(groups[1].photo_indices, (std::vector<int>{2}));
  EXPECT_EQ(groups[2].photo_indices, (std::vector<int>{3}));
}

TEST(PhotoFolder, SeriesAwarePairsConnectNeighboursAndSeries) {
  // 3 series x 8 views shot in order.
  std::vector<int> series_of;
  for (int s = 0; s < 3; ++s)
    for (int v = 0; v < 8; ++v) series_of.push_back(s);
  const auto pairs = SeriesAwarePairs(series_of, 2);
  const std::set<std::pair<int, int>> set(pairs.begin(), pairs.end());
  EXPECT_TRUE(set.count({0, 1}));  // neighbours in series 0
  EXPECT_TRUE(set.count({0, 2}));
  EXPECT_FALSE(set.count({0, 3}));   // beyond the overlap
  EXPECT_TRUE(set.count({3, 11}));   // view 3 of series 0 with view 3 of series 1
  EXPECT_TRUE(set.count({3, 19}));   // ... and of series 2
  EXPECT_FALSE(set.count({0, 15}));  // opposite ends of two series
  EXPECT_LT(pairs.size(), 24u * 23u / 2u);
  for (const auto& [a, b] : pairs) EXPECT_LT(a, b);
}

TEST(PhotoFolder, MissingAndEmptyFoldersAreInputErrors) {
  const auto dir = test::TempDir("photos");
  EXPECT_THROW(ListPhotos(dir / "missing"), InputError);
  EXPECT_THROW(ListPhotos(dir), InputError);
}

}  // namespace
}  // namespace hdribr
