// `hdribr bench hdr --capture DIR`: the three HDR render modes on a
// synthetic capture's ground-truth novel views: radiance error after a scale
// fit and frame time.
#include <spdlog/spdlog.h>

#include <unistd.h>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "cli/render_options.h"
#include "core/error.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "hdr/radiance_compare.h"
#include "io/colmap_model.h"
#include "io/exr.h"
#include "io/workspace.h"
#include "render/hdr_photo_set.h"
#include "render/hdr_render.h"

namespace hdribr::cli {
namespace {
namespace fs = std::filesystem;

struct BenchHdrOptions {
  std::string capture;
  std::string set;
  std::string response;
  int repeats = 3;
  int max_photo_size = 0;
  std::string json_path;
};

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int Run(const BenchHdrOptions& opt) {
  if (opt.repeats < 1) throw UsageError("--repeats must be at least 1");
  const fs::path capture = opt.capture;
  const Scene scene = LoadWorkspace(capture / "workspace");
  const ColmapModel novel = ReadColmapModel(capture / "gt" / "novel");
  if (novel.images.empty()) throw InputError(capture / "gt" / "novel", "no novel views");

  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  render::RendererOptions ropt;
  ropt.max_photo_size = opt.max_photo_size;
  fs::path set_folder = opt.set;
  fs::path temp;
  if (set_folder.empty()) {
    // Build the set (calibrated, like `hdribr hdr`) in a temporary folder.
    temp = fs::temp_directory_path() / ("hdribr-bench-hdr-" + std::to_string(::getpid()));
    render::HdrPhotoSetOptions hopt;
    hopt.output = temp;
    hopt.export_aligned = false;
    hopt.renderer = ropt;
    if (!opt.response.empty()) hopt.response_file = fs::path(opt.response);
    render::BuildHdrPhotoSet(shaders, scene, hopt);
    set_folder = temp;
  }
  const render::LoadedHdrPhotoSet set = render::LoadHdrPhotoSet(scene, set_folder);

  nlohmann::json modes = nlohmann::json::array();
  FILE* table = TableStream(opt.json_path);
  std::fprintf(table, "HDR modes on %zu GT novel views of %s (%s), %d repeats (median)\n",
               novel.images.size(), capture.c_str(), context.Renderer().c_str(), opt.repeats);
  std::fprintf(table, "%-12s %14s %16s %10s %10s\n", "mode", "err (global)", "err (per-chan)",
               "coverage", "frame ms");
  for (render::HdrMode mode : render::AllHdrModes()) {
    render::HdrRenderer renderer(shaders, scene, mode, set.response, ropt, &set);
    std::vector<double> errors, errors_pc, coverage, ms;
    for (const auto& [id, image] : novel.images) {
      const Camera& cam = novel.cameras.at(image.camera_id);
      const std::string stem = fs::path(image.name).stem().string();
      const cv::Mat gt = ReadExr(capture / "gt" / "novel" / "radiance" / (stem + ".exr"));
      const cv::Mat gt_valid = ReadExr(capture / "gt" / "novel" / "depth" / (stem + ".exr")) > 0;
      render::HdrFrame frame = renderer.Render(cam, image.cam_from_world, cam.width, cam.height);
      std::vector<double> times;
      for (int r = 0; r < opt.repeats; ++r) {
        frame = renderer.Render(cam, image.cam_from_world, cam.width, cam.height);
        times.push_back(frame.ms);
      }
      ms.push_back(Median(times));
      errors.push_back(MedianAbsLogRatio(frame.radiance, gt, gt_valid));
      errors_pc.push_back(MedianAbsLogRatio(frame.radiance, gt, gt_valid, true));
      cv::Mat both;
      cv::bitwise_and(gt_valid, frame.valid, both);
      coverage.push_back(cv::countNonZero(both) /
                         std::max(1.0, static_cast<double>(cv::countNonZero(gt_valid))));
    }
    std::fprintf(table, "%-12s %14.4f %16.4f %10.3f %10.1f\n", render::HdrModeName(mode).c_str(),
                 Median(errors), Median(errors_pc), Median(coverage), Median(ms));
    modes.push_back({{"mode", render::HdrModeName(mode)},
                     {"median_abs_log_ratio", Median(errors)},
                     {"median_abs_log_ratio_per_channel", Median(errors_pc)},
                     {"per_view", errors},
                     {"coverage", Median(coverage)},
                     {"frame_ms", Median(ms)}});
  }
  if (!temp.empty()) fs::remove_all(temp);
  const Camera& cam0 = novel.cameras.begin()->second;
  nlohmann::json j = {{"benchmark", "hdr"},
                      {"capture", capture.lexically_normal().string()},
                      {"renderer", context.Renderer()},
                      {"novel_views", novel.images.size()},
                      {"width", cam0.width},
                      {"height", cam0.height},
                      {"photos", scene.photos.size()},
                      {"series", scene.series.size()},
                      {"set_views", set.images.size()},
                      {"repeats", opt.repeats},
                      {"modes", modes}};
  EmitJson(opt.json_path, j);
  return 0;
}

}  // namespace

CommandRunner SetupBenchHdr(CLI::App& sub);
HDRIBR_BENCH(hdr, "HDR render modes vs GT novel views (synthetic capture): error, frame time",
             SetupBenchHdr);

CommandRunner SetupBenchHdr(CLI::App& sub) {
  auto opt = std::make_shared<BenchHdrOptions>();
  sub.add_option("--capture", opt->capture, "Synthetic capture folder (hdribr synth)")->required();
  sub.add_option("--set", opt->set,
                 "Existing HDR photo set folder (default: build one, "
                 "calibrated, in a temp dir)");
  sub.add_option("--response", opt->response, "Response file for building the set");
  sub.add_option("--repeats", opt->repeats, "Frames per view (the median is reported)")
      ->capture_default_str();
  AddMaxPhotoSizeOption(sub, opt->max_photo_size);
  sub.add_option("--json", opt->json_path, "Write the JSON here instead of stdout")
      ->check(OutputFolderCheck());
  return [opt] { return Run(*opt); };
}

}  // namespace hdribr::cli
