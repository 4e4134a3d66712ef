#include "viewer/path_control.h"

#include <cstdio>
#include <utility>

namespace hdribr::viewer {

PathControl::PathControl(const Camera& camera, std::filesystem::path record_to,
                         const std::filesystem::path& play)
    : camera_(camera), record_to_(std::move(record_to)) {
  if (!play.empty()) player_ = std::make_unique<Player>(ReadCameraPath(play));
}

void PathControl::Start(double now_s) {
  if (player_) play_start_s_ = now_s;
}

std::string PathControl::ToggleRecording(double now_s, const Rigid3d& cam_from_world) {
  if (!recorder_.recording()) {
    recorder_.Start(30);
    return "";
  }
  const View v{"frame", camera_, cam_from_world};
  last_path_ = recorder_.Stop(std::make_pair(now_s, v));
  const std::filesystem::path out =
      record_to_.empty() ? std::filesystem::path("hdribr_path.json") : record_to_;
  WriteCameraPath(out, last_path_);
  const std::string status = "path saved to " + out.string();
  std::printf("%s (%zu keyframes)\n", status.c_str(), last_path_.keyframes.size());
  return status;
}

void PathControl::Play(double now_s) {
  if (!last_path_.keyframes.empty()) player_ = std::make_unique<Player>(last_path_);
  if (player_) play_start_s_ = now_s;
}

void PathControl::Advance(double now_s, int frame, CameraController& controller) {
  if (!player_ || play_start_s_ < 0) return;
  const double t = frame >= 0 ? frame / player_->path().fps : now_s - play_start_s_;
  if (auto v = player_->At(t)) {
    controller.SetPose(v->cam_from_world);
  } else {
    play_start_s_ = -1;
  }
}

void PathControl::Record(double now_s, const Rigid3d& cam_from_world) {
  if (recorder_.recording()) recorder_.Add(now_s, {"frame", camera_, cam_from_world});
}

}  // namespace hdribr::viewer
