#include "viewer/recorder.h"

#include <cmath>

namespace hdribr::viewer {

void Recorder::Start(double fps) {
  recording_ = true;
  path_ = CameraPath{};
  path_.fps = fps > 0 ? fps : 30;
}

void Recorder::Add(double time_s, const View& view) {
  if (!recording_) return;
  if (path_.keyframes.empty()) {
    start_s_ = time_s;
  } else if (time_s - start_s_ - path_.times_s.back() < 1.0 / path_.fps) {
    return;
  }
  path_.times_s.push_back(time_s - start_s_);
  path_.keyframes.push_back(view);
}

CameraPath Recorder::Stop(const std::optional<std::pair<double, View>>& last) {
  if (recording_ && last && !path_.keyframes.empty() &&
      last->first - start_s_ > path_.times_s.back()) {
    path_.times_s.push_back(last->first - start_s_);
    path_.keyframes.push_back(last->second);
  } else if (recording_ && last && path_.keyframes.empty()) {
    start_s_ = last->first;
    path_.times_s.push_back(0);
    path_.keyframes.push_back(last->second);
  }
  recording_ = false;
  return path_;
}

std::optional<View> Player::At(double elapsed_s) const {
  const int frames = path_.FrameCount();
  if (frames <= 0 || elapsed_s < 0) return std::nullopt;
  const int i = static_cast<int>(std::floor(elapsed_s * path_.fps));
  if (i >= frames) return std::nullopt;
  return path_.Frame(i);
}

}  // namespace hdribr::viewer
