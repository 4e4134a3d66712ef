// `hdribr render WORKSPACE --camera SPEC --out FILE.png|FILE.exr` and `--path PATH.json
// --out-dir DIR`: offline image-based rendering of new views (Lechelek et al. 2019, sec. 4).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "cli/render_options.h"
#include "core/error.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "hdr/re_expose.h"
#include "hdr/response_curve.h"
#include "io/camera_spec.h"
#include "io/false_colour.h"
#include "io/image.h"
#include "io/radiometric_calibration.h"
#include "io/workspace.h"
#include "render/hdr_photo_set.h"
#include "render/hdr_render.h"
#include "render/render_output.h"
#include "render/renderer.h"
#include "render/tonemap_pass.h"

namespace hdribr::cli {
namespace {

struct RenderCliOptions {
  std::string workspace;
  std::string camera;
  std::string path;
  std::string out;
  std::string out_dir;
  std::string format = "png";
  std::string size;
  std::string debug;
  std::vector<std::string> exclude;
  render::RendererOptions renderer;  // depth mode, blend options, photo size
  bool no_depth_cache = false;
  // HDR: render mode and Reinhard tone mapping of the PNG output.
  std::optional<render::HdrMode> hdr_mode;  // unset = LDR rendering
  std::string hdr_mode_name = "auto";       // --hdr-mode: auto, ldr or an HdrMode name
  std::string hdr_set;                      // default WORKSPACE/hdr
  std::string response;                     // default: the HDR set's response.json
  double exposure_ev = 0;
  double key = 0.18;
  double gamma = 2.2;
  double log_average = 0;  // 0 = computed per image on the GPU
  // PNG through the camera's response instead of Reinhard: at this photo's exposure, or at this
  // exposure time (with the photos' median ISO and aperture).
  std::string as_photo;
  double exposure_time = 0;
  bool camera_curve = false;  // PNG through the response at the photos' median exposure
};

// --hdr-mode auto: radiance of every photo (direct) when the workspace has a radiometric
// calibration (hdribr calibrate) and its photos more than one exposure, else display blending.
std::optional<render::HdrMode> AutoHdrMode(const std::filesystem::path& workspace) {
  const std::filesystem::path file = workspace / kCalibFolder / kCalibExposures;
  if (!std::filesystem::exists(file)) return std::nullopt;
  double lo = HUGE_VAL, hi = 0;
  for (const auto& [name, e] : ReadRadiometricCalibration(file).photos) {
    lo = std::min(lo, e.exif_relative);
    hi = std::max(hi, e.exif_relative);
  }
  // Exposures differ when they are more than the series grouping's 1/6 EV apart.
  if (!(hi > 0) || std::log2(hi / lo) <= 1.0 / 6.0) return std::nullopt;
  return render::HdrMode::kDirect;
}

// Relative exposure (Exposure::Relative() units) of the camera-curve output: --as-photo's
// photo, or --exposure-time with the median ISO / 100 / N^2 of the photos that have EXIF.
double ReExposure(const RenderCliOptions& opt, const Scene& scene) {
  if (!opt.as_photo.empty()) {
    const int i = scene.FindPhoto(opt.as_photo);
    if (i < 0) throw UsageError("--as-photo: no photo named '" + opt.as_photo + "'");
    return scene.RelativeExposureOf(scene.photos[static_cast<size_t>(i)]);
  }
  if (opt.exposure_time > 0) return opt.exposure_time * scene.ExposureGain();
  return scene.MedianRelativeExposure();
}

// The blended colour as an 8-bit BGRA PNG image: value x 255 rounded (clamped), alpha 255 where
// valid, everything 0 where invalid. Helper for display encodings of 8-bit photos.
cv::Mat ToPng(const cv::Mat& color, const cv::Mat& valid) {
  cv::Mat bgr8;
  color.convertTo(bgr8, CV_8UC3, 255.0);  // saturate_cast rounds and clamps
  cv::Mat out;
  cv::cvtColor(bgr8, out, cv::COLOR_BGR2BGRA);
  out.setTo(cv::Scalar(0, 0, 0, 0), valid == 0);
  return out;
}

// Which debug image --debug asks for.
struct DebugRequest {
  enum Kind { kNone, kCount, kWeight, kDepth, kNormal } kind = kNone;
  int photo = -1;
};

DebugRequest ParseDebug(const std::string& s, const Scene& scene) {
  DebugRequest d;
  if (s.empty()) return d;
  if (s == "count") {
    d.kind = DebugRequest::kCount;
  } else if (s == "depth") {
    d.kind = DebugRequest::kDepth;
  } else if (s == "normal") {
    d.kind = DebugRequest::kNormal;
  } else if (s.rfind("weight:", 0) == 0) {
    d.kind = DebugRequest::kWeight;
    d.photo = scene.FindPhoto(s.substr(7));
    if (d.photo < 0) throw UsageError("--debug " + s + ": no photo named '" + s.substr(7) + "'");
  } else {
    throw UsageError("--debug must be count, weight:PHOTO, depth or normal, got '" + s + "'");
  }
  return d;
}

// Writes the requested image: the colour (or a debug map) as PNG or EXR by extension.
void WriteOutput(const std::filesystem::path& out, const render::RenderImages& im,
                 const DebugRequest& debug, int photo_count) {
  const bool exr = LowerExtension(out) == ".exr";
  const cv::Mat depth_valid = im.depth > 0;
  switch (debug.kind) {
    case DebugRequest::kNone:
      if (exr) {
        render::WriteRgbaExr(out, im.color, im.shown());
      } else {
        WriteImage(out, ToPng(im.color, im.shown()));
      }
      return;
    case DebugRequest::kCount:
      if (exr) {
        render::WriteRgbaExr(
            out,
            [&] {
              cv::Mat c;
              cv::merge(std::vector<cv::Mat>{im.count, im.count, im.count}, c);
              return c;
            }(),
            depth_valid);
      } else {
        WriteImage(out, FalseColour(im.count, 0, std::max(1, photo_count), depth_valid));
      }
      return;
    case DebugRequest::kWeight:
      if (exr) {
        cv::Mat c;
        cv::merge(std::vector<cv::Mat>{im.weight, im.weight, im.weight}, c);
        render::WriteRgbaExr(out, c, im.valid);
      } else {
        WriteImage(out, FalseColour(im.weight, 0, 1, im.valid));
      }
      return;
    case DebugRequest::kDepth: {
      double lo = 0, hi = 0;
      cv::minMaxLoc(im.depth, &lo, &hi, nullptr, nullptr, depth_valid);
      if (exr) {
        cv::Mat c;
        cv::merge(std::vector<cv::Mat>{im.depth, im.depth, im.depth}, c);
        render::WriteRgbaExr(out, c, depth_valid);
      } else {
        WriteImage(out, FalseColour(-im.depth, -hi, -lo, depth_valid));  // near = red
      }
      return;
    }
    case DebugRequest::kNormal: {
      // Camera-space normal (x, y, z) stored as R, G, B; PNG maps [-1, 1] to [0, 255].
      cv::Mat bgr;
      cv::cvtColor(im.normal, bgr, cv::COLOR_RGB2BGR);
      if (exr) {
        render::WriteRgbaExr(out, bgr, depth_valid);
      } else {
        cv::Mat png;
        bgr.convertTo(png, CV_8UC3, 127.5, 127.5);
        png.setTo(cv::Scalar(0, 0, 0), depth_valid == 0);
        WriteImage(out, png);
      }
      return;
    }
  }
}

// File-name-safe version of a view name ("sub/a.jpg" -> "sub_a").
std::string SafeStem(const std::string& name) {
  std::string s = std::filesystem::path(name).replace_extension().string();
  for (char& c : s) {
    if (c == '/' || c == '\\' || c == ' ' || c == ':') c = '_';
  }
  return s.empty() ? "view" : s;
}

// HDR rendering: `--hdr-mode precomputed|onthefly|direct`; PNG = tone-mapped on the GPU
// (Reinhard 2002, --exposure/--key/--gamma/--log-average), EXR = linear radiance + alpha.
// `active`: the photos left after --exclude (direct blends them alone).
int RunHdr(const RenderCliOptions& opt, const Scene& scene, const std::vector<View>& views,
           const std::vector<int>& active) {
  const render::HdrMode mode = *opt.hdr_mode;
  if (!opt.debug.empty()) throw UsageError("--debug is not available with --hdr-mode");
  // The other modes render series (onthefly) or the HDR set's photos (precomputed), not the
  // workspace's photos one by one.
  if (!opt.exclude.empty() && mode != render::HdrMode::kDirect) {
    throw UsageError("--exclude needs --hdr-mode direct (or ldr), got --hdr-mode " +
                     render::HdrModeName(mode));
  }
  const std::filesystem::path set_dir =
      opt.hdr_set.empty() ? std::filesystem::path(opt.workspace) / render::kHdrSetFolder
                          : std::filesystem::path(opt.hdr_set);
  std::optional<render::LoadedHdrPhotoSet> set;
  ResponseCurve response;
  // The response: given, else the workspace's calibration (hdribr calibrate), else the set's.
  const std::filesystem::path calibrated =
      std::filesystem::path(opt.workspace) / kCalibFolder / kCalibResponse;
  std::string response_file = opt.response;
  if (response_file.empty() && std::filesystem::exists(calibrated)) {
    response_file = calibrated.string();
  }
  if (!response_file.empty()) response = ReadResponseCurve(response_file);
  if (mode == render::HdrMode::kPrecomputed || response_file.empty()) {
    set = render::LoadHdrPhotoSet(scene, set_dir);  // InputError naming hdr_set.json if absent
  }
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  render::HdrRenderer renderer(shaders, scene, mode, response, opt.renderer, set ? &*set : nullptr);
  if (!opt.exclude.empty()) renderer.renderer().SetActivePhotos(active);
  const bool camera_curve = opt.camera_curve || !opt.as_photo.empty() || opt.exposure_time > 0;
  const double re_exposure = camera_curve ? ReExposure(opt, scene) : 0.0;
  const ResponseCurve& curve = set && response_file.empty() ? set->response : response;
  render::TonemapPass tonemap(shaders);
  render::TonemapOptions tm;
  tm.key = static_cast<float>(opt.key);
  tm.gamma = static_cast<float>(opt.gamma);
  tm.exposure = static_cast<float>(std::exp2(opt.exposure_ev));
  if (opt.log_average > 0) tm.fixed_log_average = static_cast<float>(opt.log_average);
  std::printf("HDR mode %s, %zu photos, %zu points (%s)\n", render::HdrModeName(mode).c_str(),
              scene.photos.size(), scene.points.size(), context.Renderer().c_str());
  if (!opt.out_dir.empty()) std::filesystem::create_directories(opt.out_dir);
  for (const View& view : views) {
    const cv::Size size =
        opt.size.empty() ? cv::Size(view.camera.width, view.camera.height) : ParseSize(opt.size);
    const std::filesystem::path out = opt.out.empty() ? std::filesystem::path(opt.out_dir) /
                                                            (SafeStem(view.name) + "." + opt.format)
                                                      : std::filesystem::path(opt.out);
    const render::ToneMappedFrame f = render::RenderToneMapped(
        renderer, tonemap, view.camera, view.cam_from_world, size.width, size.height, tm);
    if (LowerExtension(out) == ".exr") {
      render::WriteRgbaExr(out, f.hdr.radiance, f.hdr.shown());
    } else {
      cv::Mat bgra;
      cv::cvtColor(
          camera_curve ? ExposeThroughResponse(f.hdr.radiance, curve, re_exposure) : f.display,
          bgra, cv::COLOR_BGR2BGRA);
      std::vector<cv::Mat> ch;
      cv::split(bgra, ch);
      ch[3] = f.hdr.shown();
      cv::merge(ch, bgra);
      WriteImage(out, bgra);
    }
    const int valid = cv::countNonZero(f.hdr.valid);
    if (valid == 0) spdlog::warn("view {}: the image is all invalid", view.name);
    const double pixels = size.width * size.height;
    std::printf("view %s  %dx%d  valid %.2f%%  filled %.2f%%  L_a %.4g  %.1f ms -> %s\n",
                view.name.c_str(), size.width, size.height, 100.0 * valid / pixels,
                100.0 * cv::countNonZero(f.hdr.filled) / pixels, f.log_average, f.hdr.ms,
                out.c_str());
  }
  return 0;
}

int Run(const RenderCliOptions& opt) {
  if (opt.camera.empty() == opt.path.empty()) {
    throw UsageError(
        "render: give either --camera SPEC (with --out) or --path PATH (with --out-dir)");
  }
  if (!opt.camera.empty() && opt.out.empty()) throw UsageError("render: --camera needs --out");
  if (!opt.path.empty() && opt.out_dir.empty()) throw UsageError("render: --path needs --out-dir");
  CheckBlendOptions(opt.renderer.blend);
  if (!(opt.key > 0) || !(opt.gamma > 0) || !(opt.log_average >= 0) ||
      !std::isfinite(opt.exposure_ev) || !std::isfinite(opt.key) || !std::isfinite(opt.gamma) ||
      !std::isfinite(opt.log_average)) {
    throw UsageError(
        "--key and --gamma must be finite and > 0, --log-average >= 0, --exposure "
        "finite");
  }

  CheckOutsideInputs(opt.workspace, opt.out);
  CheckOutsideInputs(opt.workspace, opt.out_dir);
  const Scene scene = LoadWorkspace(opt.workspace);
  if (scene.photos.empty()) throw InputError(opt.workspace, "the workspace has no photos");
  const DebugRequest debug = ParseDebug(opt.debug, scene);
  std::vector<View> views;
  if (!opt.camera.empty()) {
    views.push_back(ParseCameraSpec(opt.camera, scene));
  } else {
    const CameraPath path = ReadCameraPath(opt.path);
    for (int i = 0; i < path.FrameCount(); ++i) views.push_back(path.Frame(i));
  }
  std::vector<bool> excluded(scene.photos.size(), false);
  for (const std::string& name : opt.exclude) {
    const int i = scene.FindPhoto(name);
    if (i < 0) throw UsageError("--exclude: no photo named '" + name + "'");
    excluded[static_cast<size_t>(i)] = true;
  }
  std::vector<int> active;
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    if (!excluded[i]) active.push_back(static_cast<int>(i));
  }
  if (active.empty()) spdlog::warn("every photo is excluded: the output is all invalid");
  if (opt.hdr_mode) return RunHdr(opt, scene, views, active);

  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  render::RendererOptions ro = opt.renderer;
  ro.blend.debug_photo = debug.photo;
  render::Renderer renderer(shaders, scene, ro);
  renderer.SetActivePhotos(active);
  std::printf("%zu photos (%zu active), %zu points, GPU memory %.1f MiB (%s)\n",
              scene.photos.size(), active.size(), scene.points.size(),
              renderer.gpu_bytes() / 1048576.0, context.Renderer().c_str());

  if (!opt.out_dir.empty()) std::filesystem::create_directories(opt.out_dir);
  for (const View& view : views) {
    const cv::Size size =
        opt.size.empty() ? cv::Size(view.camera.width, view.camera.height) : ParseSize(opt.size);
    const render::RenderImages im =
        renderer.RenderToImages(view.camera, view.cam_from_world, size.width, size.height);
    const std::filesystem::path out = opt.out.empty() ? std::filesystem::path(opt.out_dir) /
                                                            (SafeStem(view.name) + "." + opt.format)
                                                      : std::filesystem::path(opt.out);
    WriteOutput(out, im, debug, static_cast<int>(active.size()));
    const int valid = cv::countNonZero(im.valid);
    const double mean_count = valid ? cv::mean(im.count, im.valid)[0] : 0.0;
    if (valid == 0) {
      spdlog::warn("view {}: no pixel sees a surface seen by a photo: the image is all invalid",
                   view.name);
    }
    const render::FrameCandidates& candidates = renderer.last_candidates();
    std::printf(
        "view %s  %dx%d  valid %.2f%%  filled %.2f%%  mean photos/pixel %.2f  candidates %zu of "
        "%d  depth %.1f ms  blend %.1f ms  fill %.1f ms  -> %s\n",
        view.name.c_str(), size.width, size.height, 100.0 * valid / (size.width * size.height),
        100.0 * cv::countNonZero(im.filled) / (size.width * size.height), mean_count,
        candidates.photos.size(), candidates.active, renderer.last_times().depth_ms,
        renderer.last_times().blend_ms, renderer.last_times().fill_ms, out.c_str());
    if (debug.kind != DebugRequest::kNone) {
      std::string names;
      for (int k : candidates.photos) names += " " + scene.photos[static_cast<size_t>(k)].name;
      std::printf("candidates (%zu, chosen in %.2f ms):%s\n", candidates.photos.size(),
                  candidates.select_ms, names.c_str());
    }
  }
  return 0;
}

}  // namespace

CommandRunner SetupRender(CLI::App& sub);
HDRIBR_COMMAND(render, "Render new views by blending the photos (PNG / EXR)", SetupRender, 40);

CommandRunner SetupRender(CLI::App& sub) {
  auto opt = std::make_shared<RenderCliOptions>();
  sub.add_option("workspace", opt->workspace, "Workspace folder")->required();
  auto* camera = sub.add_option(
      "--camera", opt->camera,
      "View: a photo name, \"QW QX QY QZ TX TY TZ [CAMERA_ID [NAME]]\" or a camera file (.json)");
  auto* path = sub.add_option("--path", opt->path, "Camera path (JSON, docs/formats.md)");
  camera->excludes(path);
  sub.add_option("--out", opt->out, "Output image (.png: 8-bit + alpha; .exr: float RGBA)")
      ->check(OutputFolderCheck())
      ->check(ExtensionCheck({".png", ".exr"}));
  sub.add_option("--out-dir", opt->out_dir, "Output folder for --path (frame_NNNN.FORMAT)");
  sub.add_option("--format", opt->format, "Frame format for --path")
      ->check(CLI::IsMember({"png", "exr"}));
  sub.add_option("--size", opt->size, "Output size WxH (default: the camera's)")
      ->check(SizeCheck());
  sub.add_option("--debug", opt->debug,
                 "Write a debug map instead of the colour: count, weight:PHOTO, depth, normal");
  sub.add_option("--exclude", opt->exclude, "Photos left out (names)");
  AddRendererOptions(sub, opt->renderer, opt->no_depth_cache);
  sub.add_option("--mode", opt->renderer.blend.mode,
                 "blend (the paper) or nearest (single nearest photo)")
      ->transform(NamesTo(std::map<std::string, render::BlendMode>{
          {"blend", render::BlendMode::kBlend}, {"nearest", render::BlendMode::kNearestPhoto}}))
      ->default_str("blend");
  sub.add_option("--hdr-mode", opt->hdr_mode_name,
                 "auto (direct, through the camera's response, when the workspace is calibrated "
                 "and its photos have several exposures; else ldr), ldr (display values), "
                 "precomputed (HDR photo set), onthefly or direct")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "ldr", "precomputed", "onthefly", "direct"}));
  // Options of HDR renders only: an LDR render refuses them rather than ignore them.
  const std::vector<const CLI::Option*> hdr_only = {
      sub.add_option("--hdr-set", opt->hdr_set, "HDR photo set folder (default WORKSPACE/hdr)"),
      sub.add_option("--response", opt->response,
                     "Response curve for onthefly/direct (default: the HDR set's)"),
      sub.add_option("--exposure", opt->exposure_ev, "Tone mapping: exposure in EV (x 2^EV)")
          ->capture_default_str(),
      sub.add_option("--key", opt->key, "Tone mapping: Reinhard key k")->capture_default_str(),
      sub.add_option("--gamma", opt->gamma, "Tone mapping: display gamma")->capture_default_str(),
      sub.add_option("--log-average", opt->log_average,
                     "Tone mapping: fixed log-average luminance L_a (0 = per image, on the GPU)")
          ->capture_default_str(),
      sub.add_option("--as-photo", opt->as_photo,
                     "PNG through the camera's response at this photo's exposure (not Reinhard)"),
      sub.add_option("--exposure-time", opt->exposure_time,
                     "PNG through the camera's response at this exposure time in seconds")};
  return [opt, hdr_only] {
    const bool want_ldr =
        !opt->debug.empty() || opt->renderer.blend.mode != render::BlendMode::kBlend;
    if (opt->hdr_mode_name == "auto") {
      if (!want_ldr) opt->hdr_mode = AutoHdrMode(opt->workspace);
      bool reinhard = false;
      for (const CLI::Option* o : hdr_only) {
        const std::string n = o->get_name();
        reinhard |= o->count() > 0 && n != "--as-photo" && n != "--exposure-time" &&
                    n != "--response" && n != "--hdr-set";
      }
      if (opt->hdr_mode) {
        opt->camera_curve = !reinhard;
        spdlog::info(
            "calibrated workspace with several exposures: rendering the radiance of every photo "
            "(--hdr-mode direct){} (--hdr-mode ldr blends display values)",
            opt->camera_curve ? ", through the camera's response at the median photo's exposure"
                              : "");
      }
    } else if (opt->hdr_mode_name != "ldr") {
      opt->hdr_mode = render::ParseHdrMode(opt->hdr_mode_name);
    }
    if (!opt->as_photo.empty() && opt->exposure_time != 0) {
      throw UsageError("give --as-photo or --exposure-time, not both");
    }
    if (!(opt->exposure_time >= 0) || !std::isfinite(opt->exposure_time)) {
      throw UsageError("--exposure-time must be a positive number of seconds");
    }
    for (const CLI::Option* o : hdr_only) {
      if (o->count() > 0 && !opt->hdr_mode) {
        throw UsageError(o->get_name() + " applies to HDR renders: add --hdr-mode MODE");
      }
    }
    opt->renderer.depth_cache_dir = WorkspaceDepthCache(opt->workspace, opt->no_depth_cache);
    return RunNamingFlags(RendererFlags(), [&] { return Run(*opt); });
  };
}

}  // namespace hdribr::cli
