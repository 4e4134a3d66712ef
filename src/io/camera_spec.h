// Views for rendering: camera specs on the command line, camera files (JSON) and camera paths
// (JSON, written by the viewer's recorder and read by `hdribr render --path`). Formats in
// docs/formats.md ("Camera file", "Camera path").
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"
#include "core/scene.h"

namespace hdribr {

// A pinhole camera and its pose (COLMAP conventions).
struct View {
  std::string name;  // photo name, file stem or "frame_0001": used for output file names
  Camera camera;
  Rigid3d cam_from_world;
};

// SPEC is one of: the name of a photo of the scene; an images.txt-style line
// "QW QX QY QZ TX TY TZ [CAMERA_ID [NAME]]" (intrinsics of CAMERA_ID, default the first
// photo's camera); the path of a camera file (.json). Throws UsageError/InputError with the
// problem (unknown photo, unknown camera id, bad numbers, non-unit quaternion, bad file).
View ParseCameraSpec(const std::string& spec, const Scene& scene);

// Camera file: {"width","height","fx","fy","cx","cy","cam_from_world":{"qvec","tvec"}}.
View ReadCameraFile(const std::filesystem::path& path);
void WriteCameraFile(const std::filesystem::path& path, const View& view);  // atomic

// A camera path: keyframes at times (seconds), played back at `fps` (poses interpolated:
// slerp for rotation, linear for centre; intrinsics of the first keyframe).
struct CameraPath {
  double fps = 30;
  std::vector<double> times_s;  // increasing, one per keyframe
  std::vector<View> keyframes;

  double duration_s() const { return times_s.empty() ? 0.0 : times_s.back() - times_s.front(); }
  // Number of frames at fps over the duration (at least 1 for a non-empty path).
  int FrameCount() const;
  // The view at frame i (name "frame_%04d").
  View Frame(int i) const;
};

// {"format": "hdribr-camera-path", "version": 1, "fps": F, "keyframes": [{"time": s, camera
// file fields...}]}. Throws InputError naming the file on any problem.
CameraPath ReadCameraPath(const std::filesystem::path& path);
void WriteCameraPath(const std::filesystem::path& path, const CameraPath& path_data);  // atomic

}  // namespace hdribr
