// `hdribr view WORKSPACE`: the interactive viewer (src/viewer), also scriptable for tests and
// headless use (--frames N --screenshot FILE).
#include <cmath>
#include <memory>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "cli/render_options.h"
#include "cli/workspace_setup.h"
#include "core/error.h"
#include "io/workspace.h"
#include "render/renderer.h"
#include "viewer/app.h"
#include "viewer/view_state.h"

namespace hdribr::cli {

CommandRunner SetupView(CLI::App& sub);
HDRIBR_COMMAND(view, "Interactive viewer: walk around the capture, live exposure", SetupView, 70);

CommandRunner SetupView(CLI::App& sub) {
  auto opt = std::make_shared<viewer::ViewerOptions>();
  auto tonemap = std::make_shared<std::string>("auto");
  auto gamma = std::make_shared<float>(0.0f);
  auto no_depth_cache = std::make_shared<bool>(false);
  sub.add_option("workspace", opt->workspace,
                 "Workspace folder, or a folder of photos (made into a workspace beside it once)")
      ->required();
  sub.add_option("--camera", opt->camera,
                 "Initial view: photo name, \"QW QX QY QZ TX TY TZ [CAMERA_ID]\" or camera file");
  sub.add_option("--width", opt->width, "Window width (default: the camera's, <= 1280)");
  sub.add_option("--height", opt->height, "Window height");
  sub.add_option("--hdr", opt->source, "Source: auto, ldr, precomputed, onthefly, direct")
      ->transform(NamesTo(EnumMap(viewer::HdrSourceNames())))
      ->default_str("auto");
  sub.add_option("--series", opt->series, "LDR: blend only this exposure series (-1 = all)")
      ->capture_default_str();
  AddRendererOptions(sub, opt->renderer, *no_depth_cache);
  sub.add_option("--tonemap", *tonemap,
                 "Tone mapping: auto (Reinhard on for HDR), on, off, camera (HDR: the camera's "
                 "response, EV 0 = the median photo's exposure)")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "on", "off", "camera"}));
  sub.add_option("--exposure", opt->exposure_ev, "Exposure in EV (stops)")->default_val(0);
  sub.add_option("--key", opt->key, "Reinhard key")->default_val(0.18);
  sub.add_option("--gamma", *gamma, "Display gamma (default 2.2 for HDR, 1 for LDR)");
  sub.add_option("--frame-budget", opt->frame_budget_ms,
                 "Frame time while the view moves, ms: smaller pictures and fewer photos until the "
                 "view stops, then full quality (0 = always full; default 100, 0 with --frames)")
      ->check(CLI::Range(0.0, 10000.0));
  sub.add_option("--frames", opt->frames, "Scripted: exit after N frames (0 = interactive)")
      ->default_val(0)
      ->check(kAtLeastZero);
  sub.add_option("--screenshot", opt->screenshot,
                 "Scripted: write the last frame (.png tone-mapped + .exr linear)")
      ->check(OutputFolderCheck())
      ->check(ExtensionCheck({".png", ".exr"}));
  sub.add_option("--window-screenshot", opt->window_screenshot,
                 "Scripted: write the whole window (picture + UI) of the last frame (.png/.jpg)")
      ->check(OutputFolderCheck())
      ->check(ExtensionCheck({".png", ".jpg", ".jpeg"}));
  sub.add_option("--display", opt->display,
                 "Display mode: final, depth, normals, classes, count, splats, nearest")
      ->transform(NamesTo(EnumMap(viewer::DisplayModeNames())))
      ->default_str("final");
  sub.add_flag("--help-overlay", opt->show_help, "Open the key help overlay at start");
  sub.add_flag("--frustums", opt->show_frustums, "Draw the input camera frustums at start");
  sub.add_flag("--hide-panel", opt->hide_panel, "Start without the control panel (U shows it)");
  sub.add_option("--play", opt->play, "Play this camera path (JSON) from the start");
  sub.add_option("--record", opt->record, "Where R saves the recorded path (hdribr_path.json)")
      ->check(OutputFolderCheck());
  sub.add_flag("--benchmark", opt->benchmark,
               "Print the cost of an exposure change vs a camera move, then exit");
  sub.add_flag("--hidden", opt->hidden, "Invisible window (tests)");
  sub.add_option("--soak", opt->soak_frames, "Soak: N frames of camera and exposure steps")
      ->check(kAtLeastZero)
      ->group("");
  return [opt, tonemap, gamma, no_depth_cache] {
    opt->workspace = WorkspaceOrPhotos(opt->workspace);
    if (*tonemap == "camera") {
      opt->camera_curve = true;
    } else if (*tonemap != "auto") {
      opt->tonemap = *tonemap == "on";
    }
    if (*gamma != 0) {
      if (!(*gamma >= 0.1f && *gamma <= 10)) throw UsageError("--gamma must be in [0.1, 10]");
      opt->gamma = *gamma;
    }
    if (!(opt->key > 0) || !std::isfinite(opt->key) || !std::isfinite(opt->exposure_ev)) {
      throw UsageError("--key must be finite and > 0, --exposure finite");
    }
    CheckBlendOptions(opt->renderer.blend);
    opt->renderer.depth_cache_dir = WorkspaceDepthCache(opt->workspace, *no_depth_cache);
    if ((!opt->screenshot.empty() || !opt->window_screenshot.empty()) && opt->frames == 0) {
      opt->frames = 3;
    }
    if (opt->benchmark && opt->frames == 0) opt->frames = 2;
    for (const auto& out : {opt->screenshot, opt->window_screenshot, opt->record}) {
      CheckOutsideInputs(opt->workspace, out);
    }
    FlagNames flags = RendererFlags();
    flags.emplace("series", "--series");
    return RunNamingFlags(flags, [&] { return viewer::RunViewer(*opt); });
  };
}

}  // namespace hdribr::cli
