// `hdribr hdr WORKSPACE`: the HDR photo set of a workspace (LEC19 sec. 5):
// aligned LDR renders per exposure series at reference viewpoints,
// Debevec-Malik calibration and merge (eq. 7), one EXR per view and the set's
// index (docs/formats.md, "HDR photo set").
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "cli/render_options.h"
#include "cli/workspace_setup.h"
#include "core/error.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "hdr/radiance_compare.h"
#include "hdr/response_curve.h"
#include "io/camera_spec.h"
#include "io/exr.h"
#include "io/radiometric_calibration.h"
#include "io/workspace.h"
#include "render/hdr_photo_set.h"

namespace hdribr::cli {
namespace {
namespace fs = std::filesystem;

struct HdrOptions {
  std::string workspace;
  std::string reference_series;
  std::vector<std::string> views;
  std::string path;
  std::string response;
  std::string calibration = "auto";  // auto, cloud (calib/ of `hdribr calibrate`) or stack
  double lambda = CalibrationOptions().lambda;
  int samples = CalibrationOptions().samples;
  bool plain_debevec = false;
  std::string out;
  double scale = 1.0;
  bool no_aligned = false;
  int max_photo_size = 0;
  double gpu_memory_mb = 0;
  render::Background background = render::BlendOptions{}.background;
  bool no_depth_cache = false;
  std::string truth;  // a synthetic capture: report errors against its ground truth
};

// Index of the series named `text`, or given by its number.
int ResolveSeries(const Scene& scene, const std::string& text) {
  for (size_t i = 0; i < scene.series.size(); ++i) {
    if (scene.series[i].name == text) return static_cast<int>(i);
  }
  try {
    size_t used = 0;
    const int i = std::stoi(text, &used);
    if (used == text.size() && i >= 0 && i < static_cast<int>(scene.series.size())) return i;
  } catch (const std::exception&) {
  }
  std::string names;
  for (const auto& s : scene.series) names += (names.empty() ? "" : ", ") + s.name;
  throw UsageError("--reference-series: no series '" + text + "' (series: " + names +
                   ", or their index)");
}

void ReportTruth(const render::HdrPhotoSet& set, const fs::path& capture) {
  const ResponseCurve response = ReadResponseCurve(set.folder / set.response_file);
  const fs::path true_response = capture / "calib" / "response.json";
  if (fs::exists(true_response)) {
    const ResponseCurve truth = ReadResponseCurve(true_response);
    std::printf(
        "response vs truth, RMS linear error over 10-245 DN: B %.4f  G "
        "%.4f  R %.4f\n",
        RmsLinearError(response, truth, 0), RmsLinearError(response, truth, 1),
        RmsLinearError(response, truth, 2));
  }
  std::vector<double> errors, errors_pc;
  for (const render::HdrSetView& v : set.views) {
    const fs::path stem = fs::path(v.view.name).replace_extension(".exr");
    const fs::path gt_file = capture / "gt" / "radiance" / stem;
    const fs::path gt_depth = capture / "gt" / "depth" / stem;
    if (!fs::exists(gt_file) || !fs::exists(gt_depth)) continue;
    const cv::Mat merged = ReadExr(set.folder / v.radiance_file);
    const cv::Mat gt = ReadExr(gt_file);
    const cv::Mat depth = ReadExr(gt_depth);
    if (gt.size() != merged.size()) continue;
    const cv::Mat mask = depth > 0;
    errors.push_back(MedianAbsLogRatio(merged, gt, mask));
    errors_pc.push_back(MedianAbsLogRatio(merged, gt, mask, true));
  }
  if (errors.empty()) {
    std::printf("no ground-truth radiance for the reference views under %s\n", capture.c_str());
    return;
  }
  std::sort(errors.begin(), errors.end());
  std::sort(errors_pc.begin(), errors_pc.end());
  std::printf(
      "merged HDR vs GT radiance (%zu views), median |log ratio|: median %.4f, "
      "worst "
      "%.4f (global scale); median %.4f, worst %.4f (per-channel scale)\n",
      errors.size(), errors[errors.size() / 2], errors.back(), errors_pc[errors_pc.size() / 2],
      errors_pc.back());
}

int Run(const HdrOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  if (!(opt.lambda > 0) || opt.samples < 1) throw UsageError("--lambda and --samples must be > 0");
  CheckOutsideInputs(opt.workspace, opt.out);
  const Scene scene = LoadWorkspace(opt.workspace);
  render::HdrPhotoSetOptions options;
  if (!opt.reference_series.empty()) {
    options.reference_series = ResolveSeries(scene, opt.reference_series);
  }
  for (const std::string& spec : opt.views) options.views.push_back(ParseCameraSpec(spec, scene));
  if (!opt.path.empty()) {
    const CameraPath path = ReadCameraPath(opt.path);
    for (int i = 0; i < path.FrameCount(); ++i) options.views.push_back(path.Frame(i));
  }
  // The response: given, the workspace's calibration from the cloud, or calibrated from the
  // aligned stacks.
  const fs::path cloud_response = fs::path(opt.workspace) / kCalibFolder / kCalibResponse;
  std::string source = "calibrated from the aligned stacks";
  if (!opt.response.empty()) {
    options.response_file = fs::path(opt.response);
    source = "given";
  } else if (opt.calibration == "cloud" && !fs::exists(cloud_response)) {
    throw InputError(cloud_response, "missing: run `hdribr calibrate " + opt.workspace + "` first");
  } else if (opt.calibration != "stack" && fs::exists(cloud_response)) {
    options.response_file = cloud_response;
    source = "from the point cloud (hdribr calibrate)";
  }
  options.calibration.lambda = opt.lambda;
  options.calibration.samples = opt.samples;
  if (opt.plain_debevec) options.calibration = PlainDebevec(options.calibration);
  options.output = opt.out;
  options.scale = opt.scale;
  options.export_aligned = !opt.no_aligned;
  options.renderer.max_photo_size = opt.max_photo_size;
  options.renderer.gpu_memory_mb = opt.gpu_memory_mb;
  options.renderer.blend.background = opt.background;
  options.renderer.depth_cache_dir = WorkspaceDepthCache(opt.workspace, opt.no_depth_cache);
  options.progress = [](int i, int n) { spdlog::info("rendered reference view {}/{}", i, n); };

  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  const render::HdrPhotoSet set = render::BuildHdrPhotoSet(shaders, scene, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "HDR photo set: %zu views x %zu series, response %s (%s), in "
      "%.1f s (%s)\n",
      set.views.size(), set.series_names.size(), source.c_str(), set.response_file.c_str(), seconds,
      context.Renderer().c_str());
  double valid = 0;
  for (const auto& v : set.views) valid += v.valid_fraction;
  std::printf("mean valid fraction %.3f; wrote %s\n", valid / set.views.size(),
              (set.folder / render::kHdrSetIndex).c_str());
  if (!opt.truth.empty()) ReportTruth(set, opt.truth);
  return 0;
}

}  // namespace

CommandRunner SetupHdr(CLI::App& sub);
HDRIBR_COMMAND(hdr, "HDR photo set: aligned per-series renders, calibration, merge (EXR)", SetupHdr,
               60);

CommandRunner SetupHdr(CLI::App& sub) {
  auto opt = std::make_shared<HdrOptions>();
  sub.add_option("workspace", opt->workspace,
                 "Workspace folder, or a folder of photos (made into a workspace beside it once)")
      ->required();
  sub.add_option("--reference-series", opt->reference_series,
                 "Series (name or index) whose photos are the reference views "
                 "(default: middle)");
  sub.add_option("--views", opt->views,
                 "Reference views instead: camera specs (photo names, pose "
                 "lines, camera files)");
  sub.add_option("--path", opt->path, "Reference views instead: the frames of a camera path");
  sub.add_option("--response", opt->response,
                 "Response curve file (calib format) instead of calibrating");
  sub.add_option("--calibration", opt->calibration,
                 "Response: auto (the workspace's calib/ when `hdribr calibrate` made one, else "
                 "stack), cloud (calib/), stack (Debevec-Malik on the aligned renders)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "cloud", "stack"}));
  sub.add_option("--lambda", opt->lambda, "Calibration smoothness weight")->capture_default_str();
  sub.add_option("--samples", opt->samples, "Calibration samples per channel")
      ->capture_default_str();
  sub.add_flag("--plain-debevec", opt->plain_debevec,
               "Calibrate as Debevec-Malik published (smoothness in z, all samples, one solve)");
  sub.add_option("--out", opt->out, "Output folder (default: WORKSPACE/hdr)");
  sub.add_option("--scale", opt->scale, "Render size relative to the views' cameras")
      ->capture_default_str();
  sub.add_flag("--no-aligned", opt->no_aligned, "Do not export the aligned LDR renders");
  AddMaxPhotoSizeOption(sub, opt->max_photo_size);
  AddGpuMemoryOption(sub, opt->gpu_memory_mb);
  AddBackgroundOption(sub, opt->background);
  AddNoDepthCacheOption(sub, opt->no_depth_cache);
  sub.add_option("--truth", opt->truth,
                 "Synthetic capture folder (hdribr synth): report errors vs "
                 "its ground truth");
  return [opt] {
    opt->workspace = WorkspaceOrPhotos(opt->workspace).string();
    return RunNamingFlags(RendererFlags(), [&] { return Run(*opt); });
  };
}

}  // namespace hdribr::cli
