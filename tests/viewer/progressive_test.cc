// ProgressiveSchedule: reduced frames that fit the budget while the view changes, full quality
// once it has been still (the depth search in a frame of its own), and the costs it learns from.
#include "viewer/progressive.h"

#include <gtest/gtest.h>

namespace hdribr::viewer {
namespace {

constexpr int kFull = ProgressiveSchedule::kFull;

TEST(ProgressiveSchedule, WithoutABudgetEveryChangeIsFullQuality) {
  ProgressiveSchedule s(0);
  EXPECT_EQ(s.Next(true, 0.0), kFull);
  EXPECT_EQ(s.Next(false, 0.01), -1);  // nothing changed: nothing to render
  s.Record(kFull, 1000);
  EXPECT_EQ(s.Next(true, 0.02), kFull);
  EXPECT_EQ(s.shown(), kFull);
}

TEST(ProgressiveSchedule, MovingFitsTheBudgetThenRefinesOnceStill) {
  ProgressiveSchedule s(100);
  // Nothing measured yet: a quick first picture, which measures the machine.
  EXPECT_EQ(s.Next(true, 0.0), kFirstLevel);
  s.Record(kFirstLevel, 800.0 * ProgressiveSchedule::kScales[kFirstLevel] *
                            ProgressiveSchedule::kScales[kFirstLevel]);
  EXPECT_EQ(s.Predicted(kFull), 800);
  // Refined once still: full quality, which measures the full size.
  EXPECT_EQ(s.Next(false, kRefineAfterStillS / 2), -1);
  EXPECT_EQ(s.Next(false, 2 * kRefineAfterStillS), kFull);
  s.Record(kFull, 800);
  // Moving: the largest level whose pixels (at 800 ms for all of them) fit 100 ms.
  const int moving = s.Next(true, 1.0);
  ASSERT_GE(moving, 0);
  ASSERT_LT(moving, kFull);
  EXPECT_LE(s.Predicted(moving), 100);
  EXPECT_GT(s.Predicted(moving + 1), 100);
  EXPECT_EQ(ProgressiveSchedule::kScales[static_cast<size_t>(moving)], 1.0 / 3);  // 800 / 9
  // Still, but not for long enough: the reduced picture stays.
  EXPECT_EQ(s.Next(false, 1.0 + kRefineAfterStillS / 2), -1);
  EXPECT_EQ(s.shown(), moving);
  // Still long enough: full quality, once.
  EXPECT_EQ(s.Next(false, 1.0 + 2 * kRefineAfterStillS), kFull);
  EXPECT_EQ(s.Next(false, 2.0), -1);
}

TEST(ProgressiveSchedule, LearnsTheCostOfReducedFrames) {
  ProgressiveSchedule s(100);
  s.Next(true, 0.0);
  s.Record(kFull, 800);  // as if measured by a full-quality frame
  int level = s.Next(true, 0.1);
  // Fixed costs make the reduced frame dearer than its share of the pixels: it steps down.
  for (int i = 0; i < 20; ++i) {
    s.Record(level, 160);
    level = s.Next(true, 0.2 + 0.1 * i);
  }
  EXPECT_LT(ProgressiveSchedule::kScales[static_cast<size_t>(level)], 1.0 / 3);
  // A level that now takes 70 ms stays (no step up to one predicted above 80% of the budget).
  const int settled = level;
  for (int i = 0; i < 10; ++i) {
    s.Record(level, 70);
    level = s.Next(true, 3.0 + 0.1 * i);
  }
  EXPECT_EQ(level, settled);
}

TEST(ProgressiveSchedule, AStaleFullPictureIsRenderedAgainAtOnce) {
  ProgressiveSchedule s(100);
  s.Next(true, 0.0);
  s.Record(kFirstLevel, 50);
  EXPECT_EQ(s.Next(false, 1.0), kFull);
  EXPECT_EQ(s.Next(false, 1.1), -1);
  s.MarkStale();  // e.g. photos it was drawn without have arrived
  EXPECT_EQ(s.Next(false, 1.11), kFull);
  EXPECT_EQ(s.Next(false, 1.2), -1);
  // A reduced picture is not marked: it is refined once still anyway.
  s.Record(kFull, 800);
  const int moving = s.Next(true, 2.0);
  ASSERT_LT(moving, kFull);
  s.MarkStale();
  EXPECT_EQ(s.Next(false, 2.01), -1);
  EXPECT_EQ(s.Next(false, 2.0 + 2 * kRefineAfterStillS), kFull);
}

TEST(ProgressiveSchedule, CheapFramesStayFullQualityWhileMoving) {
  ProgressiveSchedule s(100);
  s.Next(true, 0.0);
  s.Record(kFull, 30);
  for (int i = 1; i < 5; ++i) EXPECT_EQ(s.Next(true, 0.1 * i), kFull);
}

TEST(ProgressiveSchedule, TheSearchStageFollowsTheFullSizeFrame) {
  ProgressiveSchedule s(100);
  s.SetSearchStage(true);
  s.Next(true, 0.0);
  EXPECT_FALSE(s.search());  // reduced frames skip it
  s.Record(kFirstLevel, 50);
  // Still: full size without the search, then at once with it; then nothing.
  EXPECT_EQ(s.Next(false, 1.0), kFull);
  EXPECT_FALSE(s.search());
  EXPECT_FALSE(s.final());
  s.Record(kFull, 400);
  EXPECT_EQ(s.Next(false, 1.01), kFull);
  EXPECT_TRUE(s.search());
  EXPECT_TRUE(s.final());
  s.Record(kFull, 1000);  // the search stage's cost does not plan the reduced frames
  EXPECT_EQ(s.Predicted(kFull), 400);
  EXPECT_EQ(s.Next(false, 1.02), -1);
  // A stale final picture is redrawn with the search.
  s.MarkStale();
  EXPECT_EQ(s.Next(false, 1.03), kFull);
  EXPECT_TRUE(s.search());
  // A change between the two frames drops the second.
  EXPECT_LT(s.Next(true, 2.0), kFull);
  EXPECT_EQ(s.Next(false, 2.0 + 2 * kRefineAfterStillS), kFull);
  EXPECT_FALSE(s.search());
  EXPECT_LT(s.Next(true, 3.0), kFull);
  EXPECT_EQ(s.Next(false, 3.01), -1);
  EXPECT_FALSE(s.final());
}

TEST(ProgressiveSchedule, ACheapFullSizeViewGetsTheSearchOnceStill) {
  ProgressiveSchedule s(100);
  s.SetSearchStage(true);
  s.Next(true, 0.0);
  s.Record(kFull, 30);
  EXPECT_EQ(s.Next(true, 0.1), kFull);  // moving, at full size without the search
  EXPECT_FALSE(s.search());
  EXPECT_FALSE(s.final());
  EXPECT_EQ(s.Next(false, 0.1 + 2 * kRefineAfterStillS), kFull);
  EXPECT_TRUE(s.search());
  EXPECT_EQ(s.Next(false, 1.0), -1);
}

TEST(ProgressiveSchedule, WithoutABudgetEveryFrameSearches) {
  ProgressiveSchedule s(0);
  s.SetSearchStage(true);
  EXPECT_EQ(s.Next(true, 0.0), kFull);
  EXPECT_TRUE(s.search());
  EXPECT_TRUE(s.final());
  EXPECT_EQ(s.Next(false, 0.1), -1);
  s.SetSearchStage(false);
  EXPECT_EQ(s.Next(true, 0.2), kFull);
  EXPECT_FALSE(s.search());
  EXPECT_TRUE(s.final());
}

TEST(ProgressiveSchedule, ForgetsCostsAndLevelSizes) {
  ProgressiveSchedule s(100);
  s.Next(true, 0.0);
  s.Record(kFull, 800);
  EXPECT_GT(s.Predicted(0), 0);
  s.ResetCosts();
  EXPECT_EQ(s.Predicted(0), 0);
  EXPECT_EQ(LevelSize(640, kFull), 640);
  EXPECT_EQ(LevelSize(640, 0), 80);
  EXPECT_EQ(LevelSize(64, 0), 16);  // at least 16 px
  EXPECT_EQ(LevelSize(10, 0), 10);  // never larger than the window
}

}  // namespace
}  // namespace hdribr::viewer
