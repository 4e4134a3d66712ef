#include "viewer/progressive.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace hdribr::viewer {
namespace {

// A level steps up while moving only when it is expected to take this share of the budget or
// less, so that a level near the budget does not alternate with the one below.
constexpr double kStepUpShare = 0.8;
// Weight of the newest measurement in a level's moving average.
constexpr double kCostUpdate = 0.3;
// A level's cost measured more than this many frames ago is extrapolated from a newer one
// instead (the load of the machine changes, and a level once too slow would never be tried).
constexpr long kCostMaxAge = 40;

double PixelShare(int level) {
  const double s = ProgressiveSchedule::kScales[static_cast<size_t>(level)];
  return s * s;
}

}  // namespace

int LevelSize(int size, int level) {
  const double s = ProgressiveSchedule::kScales[static_cast<size_t>(level)];
  return std::max(std::min(size, 16), static_cast<int>(std::lround(size * s)));
}

ProgressiveSchedule::ProgressiveSchedule(double budget_ms) : budget_ms_(budget_ms) {}

void ProgressiveSchedule::SetBudget(double budget_ms) {
  budget_ms_ = budget_ms;
  motion_level_ = -1;
}

void ProgressiveSchedule::SetSearchStage(bool on) { search_stage_ = on; }

void ProgressiveSchedule::MarkStale() {
  if (shown_ == kFull) stale_ = true;
}

void ProgressiveSchedule::ResetCosts() {
  cost_ms_.fill(0);
  measured_at_.fill(0);
  motion_level_ = -1;
}

void ProgressiveSchedule::Record(int level, double ms) {
  if (level < 0 || level > kFull || !(ms > 0) || search_) return;
  double& c = cost_ms_[static_cast<size_t>(level)];
  const bool fresh = c > 0 && records_ - measured_at_[static_cast<size_t>(level)] <= kCostMaxAge;
  c = fresh ? (1 - kCostUpdate) * c + kCostUpdate * ms : ms;
  measured_at_[static_cast<size_t>(level)] = ++records_;
}

double ProgressiveSchedule::Predicted(int level) const {
  const auto fresh = [&](int l) {
    return cost_ms_[static_cast<size_t>(l)] > 0 &&
           records_ - measured_at_[static_cast<size_t>(l)] <= kCostMaxAge;
  };
  if (fresh(level)) return cost_ms_[static_cast<size_t>(level)];
  // The most recently measured level stands for the machine's current speed.
  int newest = -1;
  for (int l = 0; l <= kFull; ++l) {
    if (cost_ms_[static_cast<size_t>(l)] > 0 &&
        (newest < 0 ||
         measured_at_[static_cast<size_t>(l)] > measured_at_[static_cast<size_t>(newest)])) {
      newest = l;
    }
  }
  if (newest < 0) return 0;
  return cost_ms_[static_cast<size_t>(newest)] * PixelShare(level) / PixelShare(newest);
}

int ProgressiveSchedule::MotionLevel() const {
  for (int l = kFull; l > 0; --l) {
    const double limit = budget_ms_ * (motion_level_ >= 0 && l > motion_level_ ? kStepUpShare : 1);
    if (Predicted(l) <= limit) return l;
  }
  return 0;
}

int ProgressiveSchedule::Next(bool changed, double now_s) {
  if (stale_) {
    stale_ = false;
    if (!changed) {
      search_ = search_stage_;
      return kFull;  // shown_ stays kFull
    }
  }
  if (budget_ms_ <= 0) {
    if (!changed && shown_ == kFull) return -1;
    shown_ = kFull;
    search_ = search_stage_;
    return kFull;
  }
  if (changed) {
    last_change_s_ = now_s;
    motion_level_ = Predicted(kFull) > 0 ? MotionLevel() : kFirstLevel;
    shown_ = motion_level_;
    search_ = false;
    return shown_;
  }
  if (final() || now_s - last_change_s_ < kRefineAfterStillS) return -1;
  motion_level_ = -1;
  // Full size first, the search stage at once after it; a full-size picture already on screen
  // (a cheap view while moving) gets the search stage now.
  search_ = search_stage_ && shown_ == kFull;
  stale_ = search_stage_ && !search_;
  shown_ = kFull;
  return kFull;
}

}  // namespace hdribr::viewer
