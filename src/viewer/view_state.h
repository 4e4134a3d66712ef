// The viewer's state: what the renderers are loaded with (Settings), the display mode, tone
// mapping and the overlays. Plain data, no GL: the input and the panel change it, the frame
// renderer reads it.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/scene.h"
#include "render/hdr_render.h"
#include "render/renderer.h"
#include "render/tonemap_pass.h"
#include "viewer/progressive.h"

namespace hdribr::viewer {

struct ViewerOptions;

// Where the blended values come from; kAuto is resolved once at start (ResolveHdrSource).
enum class HdrSource { kAuto, kLdr, kPrecomputed, kOnTheFly, kDirect };

// What the viewer shows; keys 1 ... 7 in this order.
enum class DisplayMode { kFinal, kDepth, kNormals, kClasses, kCount, kPointColours, kNearestPhoto };
inline constexpr int kDisplayModeCount = 7;

// --display names in key order: "final", "depth", "normals", "classes", "count", "splats",
// "nearest".
const std::vector<std::pair<std::string, DisplayMode>>& DisplayModeNames();
// --hdr names: "auto", "ldr", "precomputed", "onthefly", "direct".
const std::vector<std::pair<std::string, HdrSource>>& HdrSourceNames();
std::string DisplayModeName(DisplayMode mode);
std::string HdrSourceName(HdrSource source);
// The panel's combo items ('\0'-separated, in enum order; the HDR sources without kAuto).
const char* DisplayModeCombo();
const char* HdrSourceCombo();

// kAuto: precomputed when the workspace has an HDR photo set, else direct when it has a
// radiometric calibration (hdribr calibrate), else ldr; others unchanged.
HdrSource ResolveHdrSource(HdrSource source, const std::filesystem::path& workspace);
// The HDR render mode of a resolved HDR source (not kAuto or kLdr).
render::HdrMode HdrModeOf(HdrSource source);

// What the renderers are loaded with; a change reloads (source) or re-renders (the rest).
struct Settings {
  HdrSource source = HdrSource::kLdr;  // resolved: never kAuto
  int series = -1;                     // LDR: blend only this exposure series (-1 = all)
  render::DepthMode depth_mode = render::DepthMode::kLechelek;
  render::BlendWeights weights = render::BlendWeights::kUnstructured;
  int k_best = 0;
  float lambda = 1e-4f;
  float tolerance = 0.01f;  // occlusion tolerance, relative depth
  render::Background background = render::BlendOptions{}.background;
  bool fill = render::BlendOptions{}.fill;
  render::PhotoSampling sampling = render::BlendOptions{}.sampling;
  float outlier_scale = render::BlendOptions{}.outlier_scale;  // 0 = off
  float refine_depth = render::BlendOptions{}.refine_depth;    // 0 = off
  int max_candidates = render::kDefaultMaxCandidates;          // 0 = every active photo
  bool operator==(const Settings&) const = default;
};

struct ViewState {
  Settings settings;
  DisplayMode display = DisplayMode::kFinal;
  render::TonemapOptions tonemap;  // its exposure is set from exposure_ev at each tone map
  float exposure_ev = 0;
  bool auto_la = true;  // false: tone-map with fixed_la instead of the image's log-average
  // HDR: the camera's response at exposure_ev stops from the photos' median exposure instead
  // of Reinhard (what that camera would take).
  bool camera_curve = false;
  float fixed_la = 1;  // radiance target units
  // Frame-time budget while the view changes, ms (ProgressiveSchedule); 0 = always full quality.
  double frame_budget_ms = kDefaultFrameBudgetMs;
  bool frustums = false, help = false, panel = true;
  int current_photo = 0;  // the photo last snapped to (N, [ ])
  std::string status;     // the panel's last line
  // Change requests, consumed by FrameRenderer: tone mapping (re-runs the tone-map pass only)
  // and display mode (may change the blend mode: re-renders).
  bool tone_changed = false;
  bool display_changed = false;

  void SetDisplay(DisplayMode mode) {
    display = mode;
    display_changed = true;
  }
  void AddExposure(float ev) {
    exposure_ev += ev;
    tone_changed = true;
  }
};

// The state at start: source resolved, settings and tone mapping from the options (unset tone
// options take the source's defaults). Throws UsageError for a series the scene does not have.
ViewState InitialViewState(const ViewerOptions& options, const Scene& scene);

}  // namespace hdribr::viewer
