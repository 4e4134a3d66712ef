#include "render/photo_cache_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.h"

namespace hdribr::render {
namespace {

// `n` RGBA8 photos of 256 x 256 with a full mipmap chain (9 levels).
PhotoLayout Layout(int n) {
  PhotoLayout l;
  l.sizes.assign(static_cast<size_t>(n), cv::Size(256, 256));
  l.width = l.height = 256;
  l.levels = 9;
  return l;
}

TEST(PhotoCachePlan, LayoutsOfTheCoarseCopiesAndTheSlots) {
  const PhotoLayout full = Layout(3);
  EXPECT_EQ(full.LayerBytes(), 4u * 87381u);  // 4 bytes x (256^2 + 128^2 + ... + 1)
  const PhotoLayout coarse = FallbackLayout(full, 2);
  EXPECT_EQ(coarse.width, 64);
  EXPECT_EQ(coarse.sizes.size(), 3u);
  EXPECT_EQ(coarse.sizes[0], cv::Size(64, 64));
  EXPECT_EQ(coarse.levels, 7);
  const PhotoLayout half = TierLayout(full, 1);
  EXPECT_EQ(half.width, 128);
  EXPECT_EQ(half.levels, 8);
  // Reduced slots need the full-size staging layer; full-size slots alone do not.
  EXPECT_EQ(SplitBytes(full, {2, 0, 0}), 2 * full.LayerBytes());
  EXPECT_EQ(SplitBytes(full, {1, 1, 0}), 2 * full.LayerBytes() + TierLayout(full, 1).LayerBytes());
}

TEST(PhotoCachePlan, NoneWhenEverythingFits) {
  const PhotoLayout l = Layout(10);
  EXPECT_FALSE(PlanPhotoCache(l, 1000, 0, l.Bytes() + 10 * 1000).has_value());
  EXPECT_TRUE(PlanPhotoCache(l, 1000, 0, l.Bytes() + 10 * 1000 - 1).has_value());
}

TEST(PhotoCachePlan, FitsTheBudget) {
  const PhotoLayout l = Layout(40);
  const size_t depth = 256 * 256 * 4;
  const size_t budget = l.Bytes() / 4 + 40 * depth;
  const auto plan = PlanPhotoCache(l, depth, 0, budget);
  ASSERT_TRUE(plan.has_value());
  EXPECT_EQ(plan->depth_slots, 0);  // every photo is a candidate: the depth maps stay resident
  EXPECT_EQ(plan->depth_bytes, 40 * depth);
  EXPECT_GE(plan->slots, 1);
  EXPECT_EQ(plan->slot_bytes, static_cast<size_t>(plan->slots) * l.LayerBytes());
  EXPECT_LE(plan->fallback_bytes, kFallbackShare * (budget - plan->depth_bytes));
  EXPECT_EQ(plan->fallback_bytes, FallbackLayout(l, plan->fallback_shift).Bytes());
  EXPECT_EQ(plan->pool_bytes, budget - plan->depth_bytes - plan->fallback_bytes);
  EXPECT_LE(plan->slot_bytes, plan->pool_bytes);
}

TEST(PhotoCachePlan, SlotsTheDepthMapsWhenThatLeavesMoreSlots) {
  const PhotoLayout l = Layout(40);
  const size_t depth = l.LayerBytes();  // depth maps as large as the photos
  const size_t budget = 30 * l.LayerBytes();
  const auto all = PlanPhotoCache(l, depth, 0, 2 * budget);
  ASSERT_TRUE(all.has_value());
  EXPECT_EQ(all->depth_slots, 0);
  const auto slotted = PlanPhotoCache(l, depth, 8, budget);
  ASSERT_TRUE(slotted.has_value());
  EXPECT_EQ(slotted->depth_slots, 8);
  EXPECT_EQ(slotted->depth_bytes, 8 * depth);
  EXPECT_GE(slotted->slots, 8);
}

TEST(PhotoCachePlan, BudgetsTooSmallOrInvalidAreOptionErrors) {
  const PhotoLayout l = Layout(10);
  try {
    PlanPhotoCache(l, 1000, 0, l.LayerBytes() / 2);
    ADD_FAILURE() << "half a photo accepted";
  } catch (const OptionError& e) {
    EXPECT_EQ(e.field(), "gpu_memory_mb");
    EXPECT_NE(std::string(e.what()).find("at least"), std::string::npos) << e.what();
  }
  for (double mb :
       {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    EXPECT_THROW(CheckGpuMemoryMb(mb), OptionError) << mb;
  }
  EXPECT_NO_THROW(CheckGpuMemoryMb(0));
  EXPECT_NO_THROW(CheckGpuMemoryMb(512));
}

TEST(PhotoCachePlan, BetterSplitGivesTheWantedPhotosSlotsAtTheirLevel) {
  const PhotoLayout l = Layout(40);
  const size_t pool = 4 * l.LayerBytes();
  // Four full-size slots; eight wanted photos that need a quarter of the size: smaller slots
  // give all eight one, within the pool.
  const std::vector<int> split = BetterSplit(l, pool, 40, {0, 0, 8}, {4, 0, 0});
  ASSERT_EQ(split.size(), 3u);
  EXPECT_GE(split[1] + split[2] + std::min(split[0], 8), 8);
  EXPECT_LE(SplitBytes(l, split), pool);
  EXPECT_GT(std::accumulate(split.begin(), split.end(), 0), 4);
  // Slots that already serve every wanted photo at its level stay.
  EXPECT_TRUE(BetterSplit(l, pool, 40, {2, 1, 0}, {4, 0, 0}).empty());
  EXPECT_TRUE(BetterSplit(l, pool, 40, {0, 0, 0}, {4, 0, 0}).empty());
}

TEST(PhotoCachePlan, PickSlotTakesAFreeOneThenTheLeastRecentlyUsed) {
  const auto by_photo = [](const CacheSlot& c) {
    if (c.pending) return SlotUse::kNone;
    if (c.photo < 0) return SlotUse::kFree;
    if (c.photo >= 10) return SlotUse::kEvict;  // not wanted
    return c.photo == 5 ? SlotUse::kLastResort : SlotUse::kNone;
  };
  std::vector<CacheSlot> slots = {{1, false, 3}, {11, false, 7}, {12, false, 2}, {-1, false, -1}};
  EXPECT_EQ(PickSlot(slots, by_photo), 3);  // the free one, wherever it is
  slots[3] = {13, false, 9};
  EXPECT_EQ(PickSlot(slots, by_photo), 2);  // least recently used of the evictable
  slots[2] = {14, true, 1};                 // a load in flight: never taken
  EXPECT_EQ(PickSlot(slots, by_photo), 1);
  std::vector<CacheSlot> wanted = {{1, false, 3}, {5, false, 8}, {2, false, 1}};
  EXPECT_EQ(PickSlot(wanted, by_photo), 1);  // only the last resort
  wanted[1].photo = 6;
  EXPECT_EQ(PickSlot(wanted, by_photo), -1);
  EXPECT_EQ(PickSlot({}, by_photo), -1);
}

}  // namespace
}  // namespace hdribr::render
