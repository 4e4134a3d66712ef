// Ground-truth synthetic captures: hand-held exposure series of a synthetic scene, with the
// true cameras, depth, radiance, points and camera response (datasets/README.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"
#include "synth/camera_response.h"
#include "synth/ray_tracer.h"
#include "synth/scene_layouts.h"
#include "synth/synth_scene.h"

namespace hdribr::synth {

struct CaptureOptions {
  std::string scene = "default";
  int series = 3;  // exposure series
  int views = 16;  // views per series
  int width = 640;
  int height = 480;
  std::uint64_t seed = 1;
  int novel_views = 8;   // ground-truth test views (gt/novel/)
  double ev_step = 2.0;  // stops between consecutive series
  // "series": one fixed exposure per series; "auto": every photo metered on its own view (mean
  // log luminance), biased by its series' offset (auto-exposure bracketing), recorded in EXIF
  // rounded to 1/3 stop as cameras do.
  std::string exposure = "series";
  // Standard deviation of ln(true exposure time / EXIF exposure time), drawn per photo.
  double exif_error = 0;
  int jpeg_quality = 95;
  int threads = 0;  // 0 = hardware concurrency
  // End of the camera response's linear toe (SyntheticResponse::toe; 0 = pure power law).
  double toe = SyntheticResponse{}.toe;
};

// One planned photo or novel view.
struct PlannedView {
  std::string name;            // file name: "s0_v03.jpg" (photos) or "novel_02" (novel views)
  int image_id = 0;            // COLMAP image id (1-based)
  int series = -1;             // -1 for novel views
  double exposure_time_s = 0;  // the true exposure time the photo was exposed with
  double exif_time_s = 0;      // the exposure time written to its EXIF
  Rigid3d cam_from_world;
};

struct CapturePlan {
  CaptureOptions options;
  SynthScene scene;
  Camera camera;  // PINHOLE, id 1, shared by every view
  SyntheticResponse response;
  double iso = 100;
  double f_number = 4.0;
  double focal_mm = 0;              // for a sensor 6.4 mm wide
  std::vector<PlannedView> photos;  // series-major: series 0 (darkest) views 0..N-1, series 1, ...
  std::vector<PlannedView> novel;
};

// Cameras, exposures and names of a capture (cheap; no rendering). Throws UsageError for
// invalid options (unknown scene, non-positive counts or sizes).
CapturePlan PlanCapture(const CaptureOptions& options);

struct CaptureSummary {
  int photos = 0;
  int novel = 0;
  size_t points = 0;
  double radiance_p001 = 0;  // 0.1st percentile of the luminance over the input views
  double radiance_p999 = 0;  // 99.9th percentile
  double render_seconds = 0;
  double total_seconds = 0;
};

// Renders and writes a whole capture to `out`, which must not exist or be empty. Written into a
// temporary sibling folder and renamed at the end: no partial output on failure.
CaptureSummary WriteCapture(const CaptureOptions& options, const std::filesystem::path& out);

// Preview picture of the first photo's viewpoint: the view exposed at every series' exposure
// time (through the true response, without noise), side by side, then its depth map; 8-bit BGR.
cv::Mat MakePreview(const CapturePlan& plan);

}  // namespace hdribr::synth
