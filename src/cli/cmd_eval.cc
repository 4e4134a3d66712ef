// `hdribr eval WORKSPACE (--leave-one-out | --gt CAPTURE)`: image quality of the renderer and
// of two baselines (nearest-photo texturing, colour-per-point splats) on the same pixels;
// `hdribr eval WORKSPACE --cameras GT_MODEL [--gt-points PLY]`: accuracy of the workspace's
// cameras (and of its dense cloud).
#include <spdlog/spdlog.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "cli/render_options.h"
#include "core/error.h"
#include "eval/camera_accuracy.h"
#include "eval/cloud_accuracy.h"
#include "eval/hdr_novel.h"
#include "eval/leave_one_out.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "io/atomic_file.h"
#include "io/colmap_model.h"
#include "io/ply.h"
#include "io/radiometric_calibration.h"
#include "io/workspace.h"
#include "render/renderer.h"

namespace hdribr::cli {
namespace {

struct EvalCliOptions {
  std::string workspace;
  bool leave_one_out = false;
  std::string gt;
  std::string cameras;    // a ground-truth COLMAP model of the same photos
  std::string gt_points;  // a ground-truth point cloud in that model's frame
  double cloud_tolerance = 0.01;
  std::vector<std::string> photos;
  std::string series;
  std::string out;
  double size_scale = 0.5;
  bool no_baselines = false;
  std::string point_colors = "photos";
  std::string depth_source = "auto";
  render::RendererOptions renderer;  // depth mode, blend options, photo size
  bool no_depth_cache = false;
};

int RunCameras(const EvalCliOptions& opt) {
  const WorkspaceLayout layout = DetectWorkspace(opt.workspace);
  const ColmapModel reconstruction = ReadColmapModel(layout.sparse_dir);
  const ColmapModel gt = ReadColmapCameras(opt.cameras);
  // Every input is read before anything is printed.
  PointCloud dense, gt_points;
  if (!opt.gt_points.empty()) {
    if (layout.points_ply.empty()) {
      throw InputError(layout.root, "has no dense point cloud to score (points.ply)");
    }
    gt_points = ReadPly(opt.gt_points);
    if (gt_points.size() == 0) throw InputError(opt.gt_points, "has no points");
    dense = ReadPly(layout.points_ply);
    if (dense.size() == 0) throw InputError(layout.points_ply, "has no points");
  }
  const eval::CameraAccuracy cameras = eval::CompareCameras(reconstruction, gt);
  std::printf("%s", eval::FormatCameraAccuracy(cameras).c_str());
  if (opt.gt_points.empty()) return 0;
  Bounds bounds;
  for (const auto& p : gt_points.positions) bounds.Extend(p.cast<double>());
  const eval::CloudAccuracy cloud = eval::CompareClouds(
      dense, cameras.alignment.dst_from_src, gt_points, opt.cloud_tolerance * bounds.Diagonal());
  std::printf("%s", eval::FormatCloudAccuracy(cloud).c_str());
  return 0;
}

int Run(const EvalCliOptions& opt) {
  eval::EvalOptions options;
  options.photos = opt.photos;
  options.series = opt.series;
  options.size_scale = opt.size_scale;
  options.gt_capture = opt.gt;
  options.out_dir = opt.out;
  options.baselines = !opt.no_baselines;
  options.point_colors = opt.point_colors;
  options.depth_source = opt.depth_source;
  options.renderer = opt.renderer;
  options.renderer.depth_cache_dir = WorkspaceDepthCache(opt.workspace, opt.no_depth_cache);
  CheckBlendOptions(options.renderer.blend);
  if (!(opt.size_scale > 0.0 && opt.size_scale <= 1.0)) {
    throw UsageError("--size-scale must be in (0, 1], got " + std::to_string(opt.size_scale));
  }
  if (opt.series == "all" && !opt.gt.empty()) {
    throw UsageError("--series all applies to --leave-one-out only");
  }
  if (!opt.gt.empty() && !opt.photos.empty()) {
    throw UsageError("--photos applies to --leave-one-out only");
  }
  CheckOutsideInputs(opt.workspace, opt.out);
  const Scene scene = LoadWorkspace(opt.workspace);
  const std::filesystem::path response =
      std::filesystem::path(opt.workspace) / kCalibFolder / kCalibResponse;
  if (std::filesystem::exists(response)) options.response = ReadResponseCurve(response);
  if (!opt.no_baselines && opt.point_colors == "cloud" && !scene.points.HasColors()) {
    throw UsageError("--point-colors cloud: the point cloud has no colours");
  }
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  const eval::EvalReport report = eval::RunEvaluation(scene, shaders, options);
  std::printf("%s of %s, series %s, %zu views (%s)\n", report.kind.c_str(), opt.workspace.c_str(),
              report.series.c_str(), report.views.size(), context.Renderer().c_str());
  std::printf("%s", eval::FormatMeanTable(report).c_str());
  std::printf("%s", eval::FormatDepthLine(report).c_str());
  if (!opt.out.empty()) {
    std::printf("wrote %s/eval.csv, eval.json and views/*.png\n", opt.out.c_str());
  }
  // A capture with several exposures: HDR-NeRF's figures at the same GT views.
  if (!opt.gt.empty() && scene.series.size() >= 2) {
    const eval::HdrNovelReport hdr = eval::RunHdrNovelEvaluation(scene, shaders, options);
    std::printf("%s", eval::FormatHdrNovelTable(hdr).c_str());
    if (!opt.out.empty()) {
      WriteFileAtomic(std::filesystem::path(opt.out) / "eval_hdr.json",
                      eval::FormatHdrNovelJson(hdr));
    }
  }
  return 0;
}

}  // namespace

CommandRunner SetupEval(CLI::App& sub);
HDRIBR_COMMAND(eval, "Leave-one-out and ground-truth image quality, with baselines", SetupEval, 50);

CommandRunner SetupEval(CLI::App& sub) {
  auto opt = std::make_shared<EvalCliOptions>();
  sub.add_option("workspace", opt->workspace, "Workspace folder")->required();
  auto* loo = sub.add_flag("--leave-one-out", opt->leave_one_out,
                           "Re-render each chosen photo from the other photos of its series");
  auto* gt =
      sub.add_option("--gt", opt->gt, "Synthetic capture folder: score its GT novel views instead");
  auto* cameras = sub.add_option("--cameras", opt->cameras,
                                 "Ground-truth COLMAP model of the same photos: score the "
                                 "workspace's cameras (similarity-aligned centres, rotations)");
  auto* gt_points = sub.add_option("--gt-points", opt->gt_points,
                                   "Ground-truth point cloud (PLY) in the --cameras model's frame: "
                                   "also score the workspace's dense cloud (accuracy, "
                                   "completeness)");
  sub.add_option("--cloud-tolerance", opt->cloud_tolerance,
                 "Distance within which a point counts as matched, as a share of the diagonal "
                 "of the ground-truth cloud's bounding box")
      ->default_val(0.01)
      ->check(CLI::Range(1e-6, 1.0));
  loo->excludes(gt);
  cameras->excludes(loo)->excludes(gt);
  gt_points->needs(cameras);
  sub.add_option("--photos", opt->photos, "Held-out photos (default: all of the series)")
      ->expected(1, -1);
  sub.add_option("--series", opt->series,
                 "Exposure series: name, index or all (default: the middle one)");
  sub.add_option("--out", opt->out, "Output folder for eval.csv, eval.json, views/*.png");
  sub.add_option("--size-scale", opt->size_scale, "Render size relative to the views' (0, 1]")
      ->default_val(0.5);
  sub.add_flag("--no-baselines", opt->no_baselines, "Score hdribr only");
  sub.add_option("--point-colors", opt->point_colors,
                 "Colours of the colour-per-point baseline: photos or cloud")
      ->default_val("photos")
      ->check(CLI::IsMember({"photos", "cloud"}));
  sub.add_option("--depth-source", opt->depth_source,
                 "Also score the blend on ground-truth depth (method gt_depth): gt, auto (when "
                 "the workspace is a synthetic capture's own) or splat (never)")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "gt", "splat"}));
  AddRendererOptions(sub, opt->renderer, opt->no_depth_cache);
  return [opt, loo, gt, cameras] {
    if (cameras->count() > 0) return RunCameras(*opt);
    if (loo->count() == 0 && gt->count() == 0) {
      throw UsageError("eval: give --leave-one-out, --gt CAPTURE_DIR or --cameras GT_MODEL");
    }
    return RunNamingFlags(RendererFlags(), [&] { return Run(*opt); });
  };
}

}  // namespace hdribr::cli
