// Progress lines of the reconstruction's stages on the log.
#pragma once

#include <chrono>
#include <string>

namespace hdribr {

using StageClock = std::chrono::steady_clock;

// Seconds since `since`.
double SecondsSince(StageClock::time_point since);

// "12 s", or "2m05s" from a minute on.
std::string FormatDuration(double seconds);

// Progress lines "reconstruct [2/6] matching: 12/25 (48%), ETA 30 s", at most every 2 s.
class StageProgress {
 public:
  StageProgress(int index, int count, std::string stage);
  void Update(long done, long total, const char* unit);
  double Elapsed() const { return SecondsSince(start_); }

 private:
  int index_, count_;
  std::string stage_;
  StageClock::time_point start_;
  StageClock::time_point last_{};
};

}  // namespace hdribr
