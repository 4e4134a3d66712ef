// Camera path recording and playback in the viewer, in the JSON camera-path format shared with
// `hdribr render --path` (io/camera_spec.h, docs/formats.md "Camera path").
#pragma once

#include <optional>

#include "io/camera_spec.h"

namespace hdribr::viewer {

// Collects keyframes while the user navigates: at most one per 1/fps seconds, times relative
// to the first one.
class Recorder {
 public:
  void Start(double fps = 30);
  bool recording() const { return recording_; }
  // Adds the view seen at `time_s` (any clock, seconds) if at least 1/fps after the previous.
  void Add(double time_s, const View& view);
  // Ends recording (keeping `last` as the final keyframe when given) and returns the path.
  CameraPath Stop(const std::optional<std::pair<double, View>>& last = std::nullopt);
  const CameraPath& path() const { return path_; }

 private:
  bool recording_ = false;
  double start_s_ = 0;
  CameraPath path_;
};

// Plays a path back in real time.
class Player {
 public:
  explicit Player(CameraPath path) : path_(std::move(path)) {}
  // The view `elapsed_s` after the start (frames at the path's fps); nullopt once past the end.
  std::optional<View> At(double elapsed_s) const;
  const CameraPath& path() const { return path_; }

 private:
  CameraPath path_;
};

}  // namespace hdribr::viewer
