// Progressive rendering as pure logic (no GL): while the picture's inputs change (camera, blend
// settings), frames render a share of the window's pixels chosen so that a frame fits a time
// budget, with fewer candidate photos and no photo-consistent depth search; once the view has
// been still for a moment, it renders at full size, then (when the search is on) once more with
// the search.
#pragma once

#include <array>

namespace hdribr::viewer {

// ProgressiveSchedule's default frame-time budget while moving, milliseconds.
inline constexpr double kDefaultFrameBudgetMs = 100;
// Seconds the view must stay still before the full-quality frame (a drag's pauses between
// input events are shorter).
inline constexpr double kRefineAfterStillS = 0.12;
// Most candidate photos of a reduced frame (the full-quality frame uses the viewer's setting).
inline constexpr int kMotionMaxCandidates = 8;
// The level of the first frame with a budget, before any cost is known: a quick first picture
// (it measures the machine), refined once still.
inline constexpr int kFirstLevel = 2;

class ProgressiveSchedule {
 public:
  // Resolution levels: the rendered size is the window's times kScales[level] on each axis;
  // the last level is full quality.
  static constexpr std::array<double, 8> kScales = {0.125, 1.0 / 6, 0.25,   1.0 / 3,
                                                    0.5,   2.0 / 3, 0.8125, 1.0};
  static constexpr int kFull = static_cast<int>(kScales.size()) - 1;

  // budget_ms <= 0: every frame at full quality.
  explicit ProgressiveSchedule(double budget_ms = kDefaultFrameBudgetMs);

  // Sets the budget (ms, <= 0 = off); the next frame re-plans.
  void SetBudget(double budget_ms);
  double budget_ms() const { return budget_ms_; }
  // Whether the full-quality picture includes a costlier last stage (the photo-consistent depth
  // search). With a budget it comes in two frames: full size without the stage, then with it.
  void SetSearchStage(bool on);

  // The level to render this frame, or -1 when the picture on screen is already what it
  // should be. `changed`: the picture's inputs differ from the last rendered frame's; now_s: a
  // monotonic clock in seconds.
  int Next(bool changed, double now_s);
  // The wall time (ms) a frame of `level` took; refines that level's cost estimate (the search
  // stage's frames are not counted: the reduced frames, planned from the costs, skip it).
  void Record(int level, double ms);
  // The cost expected of a frame at `level` (ms): measured, or extrapolated from the nearest
  // measured level in proportion to the pixels; 0 when no level was measured.
  double Predicted(int level) const;
  // The level of the picture on screen (-1 before the first).
  int shown() const { return shown_; }
  // True when the frame of the last Next runs the search stage.
  bool search() const { return search_; }
  // True when the picture on screen is the last this view gets: full size, with the search
  // stage when it has one.
  bool final() const { return shown_ == kFull && (search_ || !search_stage_); }
  // The full-quality picture on screen is out of date (what it was rendered from has improved
  // since): the next call renders it again at full quality, without waiting for stillness.
  void MarkStale();
  // Forgets the measured costs (the window size or the settings changed the cost of a frame).
  void ResetCosts();

 private:
  int MotionLevel() const;

  double budget_ms_;
  std::array<double, kScales.size()> cost_ms_{};    // moving average per level, 0 = unknown
  std::array<long, kScales.size()> measured_at_{};  // records_ at each level's last measurement
  long records_ = 0;
  int shown_ = -1;
  // The full-quality picture is to be rendered again (MarkStale, or the search stage follows).
  bool stale_ = false;
  bool search_stage_ = false;  // SetSearchStage
  bool search_ = false;        // the last Next's frame runs the search stage
  int motion_level_ = -1;      // the last reduced level chosen (hysteresis)
  double last_change_s_ = -1e30;
};

// The rendered size of a `width` x `height` window at `level` (at least 16 px a side).
int LevelSize(int size, int level);

}  // namespace hdribr::viewer
