// `hdribr view`: the interactive viewer (GLFW window, OpenGL 4.5, Dear ImGui). The blended
// radiance stays in an RGBA32F target; exposure / key / gamma changes re-run only the tone-map
// pass, camera or blend changes re-render (issue 7).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace hdribr::viewer {

struct ViewerOptions {
  std::filesystem::path workspace;
  std::string camera;  // initial view (camera spec, io/camera_spec.h); empty = first photo
  int width = 0;       // window size; 0 = the initial camera's size (at most 1280 wide)
  int height = 0;
  // HDR source: "auto" (precomputed when <workspace>/hdr exists, else ldr), "ldr",
  // "precomputed", "onthefly", "direct".
  std::string hdr = "auto";
  int series = -1;  // LDR: blend only this exposure series (-1 = all photos)
  std::string depth_mode = "lechelek";
  std::string weights = "ulr";  // blending weights: "ulr" or "paper"
  int k_best = 0;
  float lambda = 1e-4f;
  float tolerance = 0.01f;
  int max_photo_size = 0;
  // Tone mapping; unset = the mode's default (Reinhard on with gamma 2.2 for HDR, off with
  // gamma 1 for LDR photos, whose values are already display-encoded).
  std::optional<bool> tonemap;
  float exposure_ev = 0;
  float key = 0.18f;
  std::optional<float> gamma;
  // Scripted / headless use: exit after `frames` frames (0 = interactive), writing the last
  // frame's tone-mapped image to `screenshot` (.png; an .exr gets the linear radiance).
  int frames = 0;
  std::filesystem::path screenshot;
  // Scripted: the whole window (picture + UI) of the last frame, PNG (docs screenshots).
  std::filesystem::path window_screenshot;
  // Display mode at start: final, depth, normals, classes, count, splats, nearest (keys 1-7).
  std::string display = "final";
  bool show_help = false;        // open the help overlay at start
  bool show_frustums = false;    // draw the input camera frustums at start
  bool hide_panel = false;       // start without the control panel (U toggles it)
  std::filesystem::path play;    // camera path to play back from the start
  std::filesystem::path record;  // where the R key (or --frames with --record) saves the path
  // Measures exposure-change vs camera-move frame costs and prints them (then exits).
  bool benchmark = false;
  bool hidden = false;  // invisible window (tests)
};

// Runs the viewer; returns the process exit code. Throws std::runtime_error when no window can
// be made, InputError / UsageError for bad input.
int RunViewer(const ViewerOptions& options);

// True when a display server is reachable and a GL 4.5 window can be created.
bool CanOpenWindow();

}  // namespace hdribr::viewer
