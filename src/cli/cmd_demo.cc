// `hdribr demo [--out DIR] [--reconstruct]`: the README's first command. Makes the default
// synthetic capture, its workspace (GT geometry, or the real front end), the HDR photo set, then
// opens the viewer when a display is present, else renders a short tone-mapped orbit.
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "core/error.h"
#include "frontend/reconstruct.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "io/camera_spec.h"
#include "io/image.h"
#include "io/workspace.h"
#include "render/hdr_photo_set.h"
#include "render/hdr_render.h"
#include "render/render_output.h"
#include "render/tonemap_pass.h"
#include "synth/capture.h"
#include "viewer/app.h"
#include "viewer/orbit.h"

namespace hdribr::cli {
namespace {

namespace fs = std::filesystem;

struct DemoOptions {
  std::string out = "hdribr-demo";
  bool reconstruct = false;
  bool headless = false;
  int frames = 24;
  int threads = 0;
  // The synthetic capture (a smaller one makes a quick demo, and the integration test).
  std::string size = "640x480";
  int series = 3;
  int views = 16;
};

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Stage 1: the synthetic capture (reused when present: WriteCapture renames a complete capture
// into place, so an existing folder with a workspace is complete).
fs::path MakeCapture(const fs::path& out, const synth::CaptureOptions& co) {
  const fs::path capture = out / "capture";
  if (fs::exists(capture / "workspace" / "series.json")) {
    std::printf("[1/4] capture: reusing %s\n", capture.c_str());
    // Say so when it was made with other options: they are not applied to a reused capture.
    std::ifstream in(capture / "gt" / "capture.json");
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (j.is_object() && (j.value("series", 0) != co.series || j.value("views", 0) != co.views ||
                          j.value("width", 0) != co.width || j.value("height", 0) != co.height)) {
      std::printf("      (made with %d series x %d views, %dx%d; remove it to apply the options)\n",
                  j.value("series", 0), j.value("views", 0), j.value("width", 0),
                  j.value("height", 0));
    }
    return capture;
  }
  if (fs::exists(capture) && !fs::is_empty(capture)) {
    throw InputError(capture, "exists but is not a complete capture: remove it and run again");
  }
  std::printf("[1/4] capture: rendering the default synthetic scene into %s ...\n",
              capture.c_str());
  std::fflush(stdout);
  const synth::CaptureSummary s = synth::WriteCapture(co, capture);
  std::printf("      %d photos, %zu points, %.1f s\n", s.photos, s.points, s.total_seconds);
  return capture;
}

// Stage 2: the workspace: the capture's own (GT cameras and points) or the front end's.
fs::path MakeWorkspace(const fs::path& out, const fs::path& capture, bool reconstruct,
                       int threads) {
  if (!reconstruct) {
    std::printf("[2/4] workspace: %s (ground-truth cameras and points)\n",
                (capture / "workspace").c_str());
    return capture / "workspace";
  }
  const fs::path workspace = out / "reconstructed";
  std::printf("[2/4] workspace: reconstructing %s with COLMAP + dense MVS into %s ...\n",
              (capture / "photos").c_str(), workspace.c_str());
  std::fflush(stdout);
  ReconstructOptions ro;
  ro.photos = capture / "photos";
  ro.workspace = workspace;
  ro.threads = threads;
  const ReconstructReport r = Reconstruct(ro);
  std::printf("      %d/%d photos registered, %zu points\n", r.num_registered, r.num_photos,
              r.num_points);
  return workspace;
}

// Stage 3: the HDR photo set (reused when its index exists).
void MakeHdrSet(const fs::path& workspace) {
  const fs::path set = workspace / render::kHdrSetFolder;
  if (fs::exists(set / render::kHdrSetIndex)) {
    std::printf("[3/4] HDR photo set: reusing %s\n", set.c_str());
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::printf("[3/4] HDR photo set: calibrating the response and merging into %s ...\n",
              set.c_str());
  std::fflush(stdout);
  const Scene scene = LoadWorkspace(workspace);
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  render::HdrPhotoSetOptions ho;
  ho.progress = [](int i, int n) {
    std::printf("      view %d/%d\r", i, n);  // i counts from 1
    std::fflush(stdout);
  };
  const render::HdrPhotoSet s = render::BuildHdrPhotoSet(shaders, scene, ho);
  std::printf("\n      %zu views, %zu series, %.1f s\n", s.views.size(), s.series_names.size(),
              Since(t0));
}

// Stage 4 without a display: a tone-mapped orbit, PNG + EXR per frame, and its camera path.
void RenderOrbit(const fs::path& workspace, const fs::path& out_dir, int frames) {
  const auto t0 = std::chrono::steady_clock::now();
  const Scene scene = LoadWorkspace(workspace);
  const CameraPath path = viewer::OrbitPath(scene, frames);
  std::printf("[4/4] no display: rendering a %d-frame orbit into %s ...\n", frames,
              out_dir.c_str());
  std::fflush(stdout);
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  const render::LoadedHdrPhotoSet set =
      render::LoadHdrPhotoSet(scene, workspace / render::kHdrSetFolder);
  render::HdrRenderer renderer(shaders, scene, render::HdrMode::kPrecomputed, set.response, {},
                               &set);
  render::TonemapPass tonemap(shaders);
  fs::create_directories(out_dir);
  // Frames of an earlier, longer orbit would look like part of this one.
  for (const fs::directory_entry& e : fs::directory_iterator(out_dir)) {
    const std::string name = e.path().filename().string();
    const std::string ext = e.path().extension().string();
    if (name.starts_with("frame_") && (ext == ".png" || ext == ".exr")) fs::remove(e.path());
  }
  WriteCameraPath(out_dir / "path.json", path);
  // One L_a for the whole orbit (that of the first frame), so that frames do not flicker.
  std::optional<float> fixed_la;
  for (int i = 0; i < path.FrameCount(); ++i) {
    const View v = path.Frame(i);
    render::TonemapOptions to;
    to.fixed_log_average = fixed_la;
    const render::ToneMappedFrame f = render::RenderToneMapped(
        renderer, tonemap, v.camera, v.cam_from_world, v.camera.width, v.camera.height, to);
    if (!fixed_la) fixed_la = f.log_average;
    WriteImage(out_dir / (v.name + ".png"), f.display);
    render::WriteRgbaExr(out_dir / (v.name + ".exr"), f.hdr.radiance, f.hdr.shown());
    std::printf("      %s  %.0f ms\r", v.name.c_str(), f.hdr.ms);
    std::fflush(stdout);
  }
  std::printf("\n      %.1f s\n", Since(t0));
}

int Run(const DemoOptions& opt) {
  if (opt.frames < 1) throw UsageError("--frames must be >= 1");
  synth::CaptureOptions co;
  const cv::Size size = ParseSize(opt.size);
  co.width = size.width;
  co.height = size.height;
  co.series = opt.series;
  co.views = opt.views;
  co.threads = opt.threads;
  if (opt.series < 2) throw UsageError("--series must be >= 2 (the HDR set merges exposures)");
  if (opt.views < 2) throw UsageError("--views must be >= 2");
  synth::PlanCapture(co);  // the capture's own option checks, before any folder is made
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path out = fs::absolute(opt.out);
  fs::create_directories(out);
  const fs::path capture = MakeCapture(out, co);
  const fs::path workspace = MakeWorkspace(out, capture, opt.reconstruct, opt.threads);
  MakeHdrSet(workspace);
  if (!opt.headless && viewer::CanOpenWindow()) {
    std::printf("[4/4] opening the viewer (H for help) on %s\n", workspace.c_str());
    viewer::ViewerOptions vo;
    vo.workspace = workspace;
    return viewer::RunViewer(vo);
  }
  const fs::path orbit = out / "orbit";
  RenderOrbit(workspace, orbit, opt.frames);
  std::printf(
      "demo done in %.0f s.\n"
      "  capture:   %s\n"
      "  workspace: %s (HDR photo set in %s)\n"
      "  orbit:     %s/frame_NNNN.png (tone-mapped), .exr (linear radiance), path.json\n"
      "  view it:   hdribr view %s   (needs a display)\n",
      Since(t0), capture.c_str(), workspace.c_str(), (workspace / "hdr").c_str(), orbit.c_str(),
      workspace.c_str());
  return 0;
}

}  // namespace

CommandRunner SetupDemo(CLI::App& sub);
HDRIBR_COMMAND(demo, "One command: synthetic capture -> workspace -> HDR set -> viewer/orbit",
               SetupDemo, 5);

CommandRunner SetupDemo(CLI::App& sub) {
  auto opt = std::make_shared<DemoOptions>();
  sub.add_option("--out", opt->out, "Output folder (reused when it holds a complete capture)")
      ->default_val("hdribr-demo");
  sub.add_flag("--reconstruct", opt->reconstruct,
               "Build the workspace with the real front end (COLMAP + MVS) instead of GT geometry");
  sub.add_flag("--headless", opt->headless, "Render the orbit even when a display is present");
  sub.add_option("--frames", opt->frames, "Frames of the headless orbit")->default_val(24);
  sub.add_option("--threads", opt->threads, "Threads for the capture (0 = all cores)")
      ->default_val(0);
  sub.add_option("--size", opt->size, "Size of the synthetic photos, WxH")
      ->default_val("640x480")
      ->check(SizeCheck());
  sub.add_option("--series", opt->series, "Exposure series of the capture")->default_val(3);
  sub.add_option("--views", opt->views, "Views per series")->default_val(16);
  return [opt] {
    FlagNames flags = CaptureFlags();
    flags.insert(ReconstructFlags().begin(), ReconstructFlags().end());
    return RunNamingFlags(flags, [&] { return Run(*opt); });
  };
}

}  // namespace hdribr::cli
