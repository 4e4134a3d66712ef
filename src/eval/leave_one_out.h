// The evaluation driver behind `hdribr eval` (needs OpenGL): leave-one-out re-renders of the
// photos and ground-truth novel views of synthetic captures, each scored for hdribr's blending
// and two baselines on the same pixels.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"
#include "eval/report.h"
#include "gl/shader_library.h"
#include "hdr/response_curve.h"
#include "render/renderer.h"

namespace hdribr::eval {

struct EvalOptions {
  // Leave-one-out: the held-out photos (names); empty = every photo of the chosen series.
  std::vector<std::string> photos;
  // Series name (series.json) or index; empty = the middle series (darkest first); "all" (with
  // leave-one-out and no photos given) = every photo of every series: with several exposures,
  // each rendered in radiance from every other photo and re-exposed at its own exposure
  // (HDR-NeRF's LDR-OE protocol), else from the other photos of its series.
  std::string series;
  // The response of the re-exposure (the workspace's calib/response.json); absent = calibrated
  // from the point cloud when needed (render/cloud_calibration.h).
  std::optional<ResponseCurve> response;
  // Renders and comparisons at the photo (or GT view) size times this factor (0, 1].
  double size_scale = 0.5;
  // Synthetic capture folder: evaluate its GT novel views instead of leave-one-out. The
  // workspace must share the capture's world frame (e.g. CAPTURE/workspace).
  std::filesystem::path gt_capture;
  // Output folder for eval.csv, eval.json and views/*.png; empty = write nothing.
  std::filesystem::path out_dir;
  bool baselines = true;  // nearest-photo texturing and colour-per-point splats
  // Colour of the points for the colour-per-point baseline: "photos" (sampled from the photos
  // that see each point, the held-out photo excluded) or "cloud" (the cloud's own colours).
  std::string point_colors = "photos";
  float point_color_tolerance = 0.01f;  // relative depth agreement for a photo to see a point
  // Depth the blend is also scored with, beside the splat depth pass: "gt" adds "gt_depth",
  // hdribr's blend on the ground-truth depth of the view and of every photo (synthetic
  // captures only); "auto" adds it when the workspace's cameras are a capture's ground truth
  // (FindGtCapture); "splat" never.
  std::string depth_source = "auto";
  render::RendererOptions renderer;
};

// Runs the evaluation (a current GL 4.5 context needed). Throws UsageError for unknown photo
// or series names, an empty selection or bad options; InputError for unreadable files.
EvalReport RunEvaluation(const Scene& scene, const gl::ShaderLibrary& shaders,
                         const EvalOptions& options);

// Index into scene.series of a series given by name or index; empty = the middle one.
int ResolveSeries(const Scene& scene, const std::string& name_or_index);

}  // namespace hdribr::eval
