// `hdribr reconstruct PHOTOS WORKSPACE`: photos -> calibrated workspace with a dense cloud.
#include <spdlog/spdlog.h>

#include <memory>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "frontend/reconstruct.h"

namespace hdribr::cli {
namespace {

int Run(const ReconstructOptions& opt) {
  const ReconstructReport report = Reconstruct(opt);
  std::string times;
  for (const auto& t : report.times) times += fmt::format(" {} {:.1f}s", t.stage, t.seconds);
  spdlog::info("registered {}/{} photos, {} points in {}", report.num_registered, report.num_photos,
               report.num_points, opt.workspace.string());
  if (!times.empty()) spdlog::info("stage times:{}", times);
  return 0;
}

}  // namespace

CommandRunner SetupReconstruct(CLI::App& sub);
HDRIBR_COMMAND(reconstruct, "Calibrate photos with COLMAP and build a dense oriented cloud",
               SetupReconstruct, 10);

CommandRunner SetupReconstruct(CLI::App& sub) {
  auto opt = std::make_shared<ReconstructOptions>();
  sub.add_option("photos", opt->photos, "Folder of photos (never modified)")->required();
  sub.add_option("workspace", opt->workspace, "Output workspace folder")->required();
  sub.add_flag("--force", opt->force, "Redo stages that finished before");
  sub.add_option("--colmap", opt->colmap, "COLMAP executable")->capture_default_str();
  sub.add_option("--matching", opt->matching,
                 "auto, exhaustive, sequential, pairs (series-aware shooting order), vocab_tree")
      ->capture_default_str();
  sub.add_option("--vocab-tree", opt->vocab_tree, "COLMAP vocabulary tree file");
  sub.add_option("--max-features", opt->max_features, "SIFT features per photo")
      ->capture_default_str();
  sub.add_option("--sift-size", opt->sift_max_size, "Largest photo side used for SIFT")
      ->capture_default_str();
  sub.add_option("--camera-model", opt->camera_model, "COLMAP camera model (SIMPLE_RADIAL, OPENCV)")
      ->capture_default_str();
  sub.add_option("--image-size", opt->undistort_max_size,
                 "Largest side of the workspace's undistorted photos (-1: as shot)")
      ->capture_default_str();
  sub.add_option("--dense", opt->dense,
                 "auto (COLMAP with CUDA, else cpu), cpu (PatchMatch stereo), sweep (plane sweep), "
                 "colmap, none")
      ->capture_default_str();
  sub.add_option("--dense-size", opt->dense_options.max_size,
                 "Largest side of the CPU depth maps (0: from the photo count, 48 photos of "
                 "400x300 in all, at least 400)")
      ->capture_default_str();
  sub.add_option("--dense-depths", opt->dense_options.num_depths,
                 "Planes swept per depth map (sweep)")
      ->capture_default_str();
  sub.add_option("--dense-levels", opt->dense_options.patch_match.num_levels,
                 "PatchMatch pyramid levels (coarse to fine)")
      ->capture_default_str();
  sub.add_option("--dense-iterations", opt->dense_options.patch_match.iterations,
                 "PatchMatch iterations per finer level")
      ->capture_default_str();
  sub.add_option("--dense-geom-iterations", opt->dense_options.patch_match.geom_iterations,
                 "PatchMatch iterations with geometric consistency (0: none)")
      ->capture_default_str();
  sub.add_option("--dense-min-ncc", opt->dense_options.patch_match.min_ncc,
                 "PatchMatch: NCC needed to keep a depth")
      ->capture_default_str();
  sub.add_option("--fusion-single-ncc", opt->dense_options.single_agreement_ncc,
                 "NCC from which a depth needs one agreeing map instead of two (> 1: never)")
      ->capture_default_str();
  sub.add_option("--dense-neighbors", opt->dense_options.num_neighbors,
                 "Source photos per depth map")
      ->capture_default_str();
  sub.add_option("--threads", opt->threads, "Threads (0: all cores)")->capture_default_str();
  return [opt] { return RunNamingFlags(ReconstructFlags(), [&] { return Run(*opt); }); };
}

}  // namespace hdribr::cli
