#include "frontend/stage_progress.h"

#include <spdlog/spdlog.h>

#include <cstdio>

namespace hdribr {

double SecondsSince(StageClock::time_point since) {
  return std::chrono::duration<double>(StageClock::now() - since).count();
}

std::string FormatDuration(double s) {
  char buf[32];
  if (s < 60) {
    std::snprintf(buf, sizeof(buf), "%.0f s", s);
  } else {
    std::snprintf(buf, sizeof(buf), "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  }
  return buf;
}

StageProgress::StageProgress(int index, int count, std::string stage)
    : index_(index), count_(count), stage_(std::move(stage)), start_(StageClock::now()) {
  spdlog::info("reconstruct [{}/{}] {}", index_, count_, stage_);
}

void StageProgress::Update(long done, long total, const char* unit) {
  if (total <= 0) return;
  const auto now = StageClock::now();
  if (done < total && std::chrono::duration<double>(now - last_).count() < 2.0) return;
  last_ = now;
  const double elapsed = SecondsSince(start_);
  std::string eta = "?";
  if (done > 0) eta = FormatDuration(elapsed * double(total - done) / double(done));
  spdlog::info("reconstruct [{}/{}] {}: {}/{} {} ({:.0f}%), ETA {}", index_, count_, stage_, done,
               total, unit, 100.0 * double(done) / double(total), eta);
}

}  // namespace hdribr
