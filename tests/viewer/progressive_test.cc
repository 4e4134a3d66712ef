// ProgressiveSchedule: reduced frames that fit the budget while the view changes, full quality
// once it has been still, and the costs it learns from.
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
