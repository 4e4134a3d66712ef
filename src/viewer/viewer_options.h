// Options of `hdribr view` (the CLI fills them; the viewer's parts read them).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "render/renderer.h"
#include "viewer/view_state.h"

namespace hdribr::viewer {

struct ViewerOptions {
  std::filesystem::path workspace;
  std::string camera;  // initial view (camera spec, io/camera_spec.h); empty = first photo
  int width = 0;       // window size; 0 = the initial camera's size (at most 1280 wide)
  int height = 0;
  HdrSource source = HdrSource::kAuto;
  int series = -1;  // LDR: blend only this exposure series (-1 = all photos)
  // Depth mode (renderer.depth.mode), blend options (renderer.blend: weights, k_best, lambda,
  // occlusion_tolerance, background), max_candidates, max_photo_size and depth_cache_dir; the
  // rest is the renderer's defaults.
  render::RendererOptions renderer;
  // Tone mapping; unset = the source's default (Reinhard on with gamma 2.2 for HDR, off with
  // gamma 1 for LDR photos, whose values are already display-encoded).
  std::optional<bool> tonemap;
  // HDR: show the radiance through the camera's response instead (TonemapOptions::camera_curve).
  bool camera_curve = false;
  float exposure_ev = 0;
  // Frame-time budget while the view changes, ms (0 = every frame at full quality); unset =
  // kDefaultFrameBudgetMs, or 0 for scripted runs (frames > 0).
  std::optional<double> frame_budget_ms;
  float key = 0.18f;
  std::optional<float> gamma;
  // Scripted / headless use: exit after `frames` frames (0 = interactive), writing the last
  // frame's tone-mapped image to `screenshot` (.png; an .exr gets the linear radiance).
  int frames = 0;
  std::filesystem::path screenshot;
  // Scripted: the whole window (picture + UI) of the last frame, PNG (docs screenshots).
  std::filesystem::path window_screenshot;
  DisplayMode display = DisplayMode::kFinal;  // at start (keys 1-7)
  bool show_help = false;                     // open the help overlay at start
  bool show_frustums = false;                 // draw the input camera frustums at start
  bool hide_panel = false;                    // start without the control panel (U toggles it)
  std::filesystem::path play;                 // camera path to play back from the start
  std::filesystem::path record;  // where the R key (or --frames with --record) saves the path
  // Measures exposure-change vs camera-move frame costs and prints them (then exits).
  bool benchmark = false;
  bool hidden = false;  // invisible window (tests)
  // Soak run: this many frames alternating a camera orbit step and an exposure step, then one
  // line with resident memory and GL object counts after the warm-up and at the end.
  int soak_frames = 0;
};

}  // namespace hdribr::viewer
