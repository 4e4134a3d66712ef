// Camera-path recording (R) and playback (L, --play) in the viewer, over recorder.h.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "core/camera.h"
#include "core/rigid3.h"
#include "viewer/camera_controller.h"
#include "viewer/recorder.h"

namespace hdribr::viewer {

class PathControl {
 public:
  // `camera`: the view's intrinsics, stored with each keyframe; `record_to`: where a recorded
  // path is saved (empty = hdribr_path.json); `play`: a path to play from the start (or empty).
  PathControl(const Camera& camera, std::filesystem::path record_to,
              const std::filesystem::path& play);

  bool recording() const { return recorder_.recording(); }
  // Starts playing the --play path, if any (times in seconds, any one clock).
  void Start(double now_s);
  // Starts recording, or stops and saves the path; returns the status line ("" when started).
  std::string ToggleRecording(double now_s, const Rigid3d& cam_from_world);
  // Plays the last recorded path (else the --play one) from the start.
  void Play(double now_s);
  // While a path plays: moves `controller` to its view at `now_s`, or at `frame` / fps when
  // frame >= 0 (scripted runs).
  void Advance(double now_s, int frame, CameraController& controller);
  // While recording: adds the view (at most 30 keyframes per second).
  void Record(double now_s, const Rigid3d& cam_from_world);

 private:
  const Camera& camera_;
  std::filesystem::path record_to_;
  Recorder recorder_;
  CameraPath last_path_;
  std::unique_ptr<Player> player_;
  double play_start_s_ = -1;  // < 0: not playing
};

}  // namespace hdribr::viewer
