#include "frontend/dense_stage.h"

#include <spdlog/spdlog.h>

#include <map>
#include <stdexcept>

#include "core/error.h"
#include "frontend/point_attributes.h"
#include "io/ply.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

// The registered photos' camera centres (world frame).
std::vector<Eigen::Vector3d> CameraCenters(const ColmapModel& model) {
  std::vector<Eigen::Vector3d> centers;
  for (const auto& [id, im] : model.images)
    centers.push_back(im.cam_from_world.Inverse().translation);
  return centers;
}

// Refuses PatchMatch parameters the depth maps cannot be computed with.
void CheckPatchMatchOptions(const PatchMatchOptions& p) {
  if (p.window_radius < 1 || p.window_radius > 10) {
    throw OptionError("dense_options.patch_match.window_radius", "must be in [1, 10]");
  }
  if (p.window_step < 1 || p.window_step > p.window_radius) {
    throw OptionError("dense_options.patch_match.window_step", "must be in [1, window_radius]");
  }
  if (!(p.sigma_color > 0)) {
    throw OptionError("dense_options.patch_match.sigma_color", "must be > 0");
  }
  if (p.num_levels < 1 || p.num_levels > 6) {
    throw OptionError("dense_options.patch_match.num_levels", "must be in [1, 6]");
  }
  if (p.coarse_iterations < 1) {
    throw OptionError("dense_options.patch_match.coarse_iterations", "must be >= 1");
  }
  if (p.iterations < 0) throw OptionError("dense_options.patch_match.iterations", "must be >= 0");
  if (p.geom_iterations < 0) {
    throw OptionError("dense_options.patch_match.geom_iterations", "must be >= 0");
  }
  if (!(p.geom_weight >= 0) || !(p.geom_max_error > 0)) {
    throw OptionError("dense_options.patch_match.geom_weight",
                      "and geom_max_error must be >= 0 and > 0");
  }
  if (p.best_views < 0) throw OptionError("dense_options.patch_match.best_views", "must be >= 0");
  if (!(p.min_ncc >= -1 && p.min_ncc <= 1)) {
    throw OptionError("dense_options.patch_match.min_ncc", "must be in [-1, 1]");
  }
  if (!(p.min_texture >= 0)) {
    throw OptionError("dense_options.patch_match.min_texture", "must be >= 0");
  }
  if (p.seed_radius < 0) throw OptionError("dense_options.patch_match.seed_radius", "must be >= 0");
}

// Fewest points the attribute stage (kNN normals and radii) can work with.
constexpr size_t kMinPoints = 16;

// The sparse model's points, each oriented toward the photos of its track.
DenseResult SparseCloud(const ColmapModel& model) {
  DenseResult dense;
  std::map<int, Eigen::Vector3d> centers;
  for (const auto& [id, im] : model.images) centers[id] = im.cam_from_world.Inverse().translation;
  for (const auto& [pid, pt] : model.points3d) {
    Eigen::Vector3d dir = Eigen::Vector3d::Zero();
    for (const auto& el : pt.track) {
      auto it = centers.find(el.image_id);
      if (it != centers.end()) dir += (it->second - pt.xyz).normalized();
    }
    dense.cloud.positions.push_back(pt.xyz.cast<float>());
    dense.cloud.colors.push_back(pt.color);
    dense.view_dirs.push_back(dir.norm() > 0 ? Eigen::Vector3f(dir.normalized().cast<float>())
                                             : Eigen::Vector3f::Zero());
  }
  return dense;
}

}  // namespace

void RunDense(StageContext& ctx, StageProgress& progress, ReconstructReport& report) {
  const ColmapModel model = ReadColmapModel(ctx.opt.workspace / "sparse");
  const std::vector<Eigen::Vector3d> centers = CameraCenters(model);
  const std::string mode = DenseMode(ctx);
  DenseResult dense;
  auto t0 = StageClock::now();
  if (mode == "cpu" || mode == "sweep") {
    DenseOptions o = ctx.opt.dense_options;
    o.threads = ctx.threads;
    o.method = mode == "cpu" ? DenseMethod::kPatchMatch : DenseMethod::kSweep;
    dense = DensifyCpu(model, ctx.opt.workspace / "images", o,
                       [&](int done, int total) { progress.Update(done, total, "depth maps"); });
    spdlog::info("CPU multi-view stereo ({}): {} depth maps of largest side {} px, {} fused points",
                 mode == "cpu" ? "PatchMatch" : "plane sweep", dense.num_depth_maps,
                 dense.depth_map_size, dense.cloud.size());
  } else if (mode == "colmap") {
    if (!ctx.caps.has_cuda) throw OptionError("dense", "colmap needs a COLMAP built with CUDA");
    const long n = static_cast<long>(model.images.size());
    std::vector<std::string> args = {"patch_match_stereo", "--workspace_path",
                                     ctx.opt.workspace.string(), "--workspace_format", "COLMAP"};
    AddColmapOption(args, ctx, {"PatchMatchStereo.geom_consistency"}, "true");
    RunColmap(ctx, progress, args, n, "photos");
    const fs::path fused = ctx.opt.workspace / "fused.ply";
    RunColmap(
        ctx, progress,
        {"stereo_fusion", "--workspace_path", ctx.opt.workspace.string(), "--workspace_format",
         "COLMAP", "--input_type", "geometric", "--output_path", fused.string()},
        n, "photos");
    dense.cloud = ReadPly(fused);
    dense.cloud.normals.clear();
    dense.view_dirs = ViewDirsFromCameras(dense.cloud, centers);
  } else if (mode == "none") {
    dense = SparseCloud(model);
  } else {
    throw OptionError("dense", "must be auto, cpu, sweep, colmap or none, got '" + mode + "'");
  }
  report.times.push_back({"dense." + mode, SecondsSince(t0)});
  const size_t dense_points = dense.cloud.size();
  if (mode != "none" && dense_points < model.points3d.size()) {
    // Multi-view stereo found (almost) nothing, e.g. on textureless walls: the sparse points
    // still place what they can, and the background shows the rest.
    spdlog::warn(
        "dense stage ({}) found only {} points, fewer than the {} sparse points (photos may lack "
        "texture or overlap): the workspace keeps the sparse points",
        mode, dense_points, model.points3d.size());
    dense = SparseCloud(model);
  }
  if (dense.cloud.size() < kMinPoints) {
    throw std::runtime_error("the dense stage found " + std::to_string(dense_points) +
                             " points and the sparse model has " +
                             std::to_string(model.points3d.size()) + ", fewer than the " +
                             std::to_string(kMinPoints) +
                             " a workspace needs; photos may lack texture or overlap");
  }
  t0 = StageClock::now();
  AttributeOptions ao = ctx.opt.attribute_options;
  ao.threads = ctx.threads;
  const size_t removed = RemoveOutliers(dense.cloud, dense.view_dirs, centers, ao);
  EstimateNormals(dense.cloud, dense.view_dirs, ao);
  EstimateRadii(dense.cloud, ao);
  report.times.push_back({"dense.attributes", SecondsSince(t0)});
  spdlog::info("clean-up: {} outliers removed, {} points with normals and radii", removed,
               dense.cloud.size());
  WritePly(ctx.opt.workspace / "points.ply", dense.cloud);
  report.num_points = dense.cloud.size();
}

std::string DenseMode(const StageContext& ctx) {
  if (ctx.opt.dense != "auto") return ctx.opt.dense;
  return ctx.caps.has_cuda ? "colmap" : "cpu";
}

void CheckDenseOptions(const DenseOptions& d) {
  if (d.max_size != 0 && d.max_size < 16) {
    throw OptionError("dense_options.max_size", "must be 0 (from the photo count) or >= 16");
  }
  if (d.num_depths < 2) throw OptionError("dense_options.num_depths", "must be >= 2");
  if (d.num_neighbors < 1) throw OptionError("dense_options.num_neighbors", "must be >= 1");
  if (!(d.single_agreement_ncc >= -1)) {
    throw OptionError("dense_options.single_agreement_ncc", "must be >= -1 (> 1: never)");
  }
  if (!(d.max_normal_error > 0 && d.max_normal_error <= 180)) {
    throw OptionError("dense_options.max_normal_error", "must be in (0, 180]");
  }
  CheckPatchMatchOptions(d.patch_match);
}

}  // namespace hdribr
