#include "frontend/reconstruct.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "core/error.h"
#include "core/exposure_series.h"
#include "core/hash.h"
#include "frontend/colmap_cli.h"
#include "frontend/photo_folder.h"
#include "io/atomic_file.h"
#include "io/colmap_model.h"
#include "io/ply.h"
#include "io/series_json.h"

namespace hdribr {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// The registered photos' camera centres (world frame).
std::vector<Eigen::Vector3d> CameraCenters(const ColmapModel& model) {
  std::vector<Eigen::Vector3d> centers;
  for (const auto& [id, im] : model.images)
    centers.push_back(im.cam_from_world.Inverse().translation);
  return centers;
}

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

std::string FormatDuration(double s) {
  char buf[32];
  if (s < 60) {
    std::snprintf(buf, sizeof(buf), "%.0f s", s);
  } else {
    std::snprintf(buf, sizeof(buf), "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  }
  return buf;
}

// Progress lines "reconstruct [2/6] matching: 12/25 (48%), ETA 30 s", at most every 2 s.
class StageProgress {
 public:
  StageProgress(int index, int count, std::string stage)
      : index_(index), count_(count), stage_(std::move(stage)), start_(Clock::now()) {
    spdlog::info("reconstruct [{}/{}] {}", index_, count_, stage_);
  }
  void Update(long done, long total, const char* unit) {
    if (total <= 0) return;
    const auto now = Clock::now();
    if (done < total && std::chrono::duration<double>(now - last_).count() < 2.0) return;
    last_ = now;
    const double elapsed = Seconds(start_);
    std::string eta = "?";
    if (done > 0) eta = FormatDuration(elapsed * double(total - done) / double(done));
    spdlog::info("reconstruct [{}/{}] {}: {}/{} {} ({:.0f}%), ETA {}", index_, count_, stage_, done,
                 total, unit, 100.0 * double(done) / double(total), eta);
  }
  double Elapsed() const { return Seconds(start_); }

 private:
  int index_, count_;
  std::string stage_;
  Clock::time_point start_;
  Clock::time_point last_{};
};

struct Context {
  const ReconstructOptions& opt;
  fs::path colmap;
  ColmapCapabilities caps;
  fs::path logs;
  std::vector<InputPhoto> photos;
  int threads = 1;
  int call_index = 0;
};

// The dense method that runs: `auto` is COLMAP's PatchMatch where it has CUDA, else ours.
std::string DenseMode(const Context& ctx) {
  if (ctx.opt.dense != "auto") return ctx.opt.dense;
  return ctx.caps.has_cuda ? "colmap" : "cpu";
}

// Adds "--name value" when this colmap knows one of the candidate names.
void AddOption(std::vector<std::string>& args, const Context& ctx,
               const std::vector<std::string>& candidates, const std::string& value) {
  const std::string name = ctx.caps.Pick(candidates);
  if (name.empty()) {
    spdlog::debug("colmap has none of the options {}: not passed", candidates.front());
    return;
  }
  args.push_back("--" + name);
  args.push_back(value);
}

// Runs one colmap command, logged to logs/NN_<command>.log, with progress from its output.
void RunColmap(Context& ctx, StageProgress& progress, const std::vector<std::string>& args,
               long num_images, const char* unit, long offset = 0, long total = 0) {
  char prefix[16];
  std::snprintf(prefix, sizeof(prefix), "%02d_", ++ctx.call_index);
  const fs::path log = ctx.logs / (std::string(prefix) + args.front() + ".log");
  std::error_code ec;
  fs::remove(log, ec);
  const int rc = RunLogged(ctx.colmap, args, log, [&](const std::string& line) {
    if (auto p = ParseColmapProgressLine(line, num_images)) {
      progress.Update(offset + p->done, total > 0 ? total : p->total, unit);
    }
  });
  if (rc != 0) {
    spdlog::error("colmap {} failed (exit {}); last lines of {}:\n{}", args.front(), rc,
                  log.string(), LastLines(log, 12));
    throw std::runtime_error("colmap " + args.front() + " failed (exit " + std::to_string(rc) +
                             "); full log: " + log.string());
  }
}

std::string GpuFlag(const Context& ctx) { return ctx.caps.has_cuda ? "1" : "0"; }

void RunFeatures(Context& ctx, StageProgress& progress) {
  const fs::path db = ctx.opt.workspace / "database.db";
  std::error_code ec;
  for (const char* suffix : {"", "-shm", "-wal"}) fs::remove(db.string() + suffix, ec);
  const auto groups = GroupByCamera(ctx.photos);
  spdlog::info("{} photos from {} camera(s): {}", ctx.photos.size(), groups.size(), [&] {
    std::string s;
    for (const auto& g : groups) s += (s.empty() ? "" : "; ") + g.key;
    return s;
  }());
  long offset = 0;
  for (size_t g = 0; g < groups.size(); ++g) {
    const fs::path list = ctx.logs / ("images_camera" + std::to_string(g + 1) + ".txt");
    std::string text;
    for (int i : groups[g].photo_indices) text += ctx.photos[i].name + "\n";
    WriteFileAtomic(list, text);
    std::vector<std::string> args = {
        "feature_extractor",     "--database_path",   db.string(),  "--image_path",
        ctx.opt.photos.string(), "--image_list_path", list.string()};
    AddOption(args, ctx, {"ImageReader.camera_model"}, ctx.opt.camera_model);
    AddOption(args, ctx, {"ImageReader.single_camera"}, "1");
    AddOption(args, ctx, {"SiftExtraction.max_num_features", "FeatureExtraction.max_num_features"},
              std::to_string(ctx.opt.max_features));
    AddOption(args, ctx, {"SiftExtraction.max_image_size", "FeatureExtraction.max_image_size"},
              std::to_string(ctx.opt.sift_max_size));
    AddOption(args, ctx, {"SiftExtraction.use_gpu", "FeatureExtraction.use_gpu"}, GpuFlag(ctx));
    AddOption(args, ctx, {"SiftExtraction.num_threads", "FeatureExtraction.num_threads"},
              std::to_string(ctx.threads));
    // Offset the per-group counts so that progress covers all photos.
    RunColmap(ctx, progress, args, 0, "photos", offset, static_cast<long>(ctx.photos.size()));
    offset += static_cast<long>(groups[g].photo_indices.size());
  }
}

void RunMatching(Context& ctx, StageProgress& progress, const std::string& strategy,
                 const std::vector<int>& series_of) {
  const fs::path db = ctx.opt.workspace / "database.db";
  const long n = static_cast<long>(ctx.photos.size());
  std::vector<std::string> args;
  if (strategy == "exhaustive") {
    args = {"exhaustive_matcher", "--database_path", db.string()};
    AddOption(args, ctx, {"ExhaustiveMatching.block_size"}, "12");
  } else if (strategy == "sequential") {
    args = {"sequential_matcher", "--database_path", db.string()};
    AddOption(args, ctx, {"SequentialMatching.overlap"}, "10");
    AddOption(args, ctx, {"SequentialMatching.quadratic_overlap"}, "1");
    if (!ctx.opt.vocab_tree.empty()) {
      AddOption(args, ctx, {"SequentialMatching.loop_detection"}, "1");
      AddOption(args, ctx, {"SequentialMatching.vocab_tree_path"}, ctx.opt.vocab_tree.string());
    }
  } else if (strategy == "vocab_tree") {
    if (ctx.opt.vocab_tree.empty())
      throw OptionError("vocab_tree", "is needed by vocab_tree matching");
    if (!fs::exists(ctx.opt.vocab_tree))
      throw InputError(ctx.opt.vocab_tree, "vocabulary tree file does not exist");
    args = {"vocab_tree_matcher", "--database_path", db.string()};
    AddOption(args, ctx, {"VocabTreeMatching.vocab_tree_path"}, ctx.opt.vocab_tree.string());
  } else if (strategy == "pairs") {
    const auto pairs = SeriesAwarePairs(series_of, 6);
    std::string text;
    for (const auto& [a, b] : pairs) text += ctx.photos[a].name + " " + ctx.photos[b].name + "\n";
    const fs::path list = ctx.logs / "pairs.txt";
    WriteFileAtomic(list, text);
    spdlog::info("matching {} series-aware pairs (of {} possible)", pairs.size(), n * (n - 1) / 2);
    args = {"matches_importer", "--database_path", db.string(), "--match_list_path",
            list.string(),      "--match_type",    "pairs"};
  } else {
    throw UsageError("unknown matching strategy '" + strategy +
                     "' (auto, exhaustive, sequential, pairs, vocab_tree)");
  }
  AddOption(args, ctx, {"SiftMatching.use_gpu", "FeatureMatching.use_gpu"}, GpuFlag(ctx));
  AddOption(args, ctx, {"SiftMatching.num_threads", "FeatureMatching.num_threads"},
            std::to_string(ctx.threads));
  RunColmap(ctx, progress, args, n, strategy == "exhaustive" ? "blocks" : "photos");
}

// The mapper's largest model folder (most registered photos), or empty.
fs::path LargestModel(const fs::path& sfm, ColmapModel* model_out) {
  fs::path best;
  size_t best_count = 0;
  std::error_code ec;
  if (!fs::is_directory(sfm, ec)) return best;
  for (const auto& entry : fs::directory_iterator(sfm)) {
    if (!entry.is_directory() || !IsColmapModelDir(entry.path())) continue;
    ColmapModel m = ReadColmapModel(entry.path());
    if (m.images.size() > best_count) {
      best_count = m.images.size();
      best = entry.path();
      if (model_out) *model_out = std::move(m);
    }
  }
  return best;
}

void RunMapping(Context& ctx, StageProgress& progress) {
  const fs::path sfm = ctx.opt.workspace / "sfm";
  std::error_code ec;
  fs::remove_all(sfm, ec);
  fs::create_directories(sfm);
  std::vector<std::string> args = {
      "mapper",       "--database_path",       (ctx.opt.workspace / "database.db").string(),
      "--image_path", ctx.opt.photos.string(), "--output_path",
      sfm.string()};
  AddOption(args, ctx, {"Mapper.num_threads"}, std::to_string(ctx.threads));
  RunColmap(ctx, progress, args, static_cast<long>(ctx.photos.size()), "photos registered");
}

// Names of photos missing from the model, and the registered count.
std::vector<std::string> Unregistered(const Context& ctx, const ColmapModel& model) {
  std::set<std::string> registered;
  for (const auto& [id, im] : model.images) registered.insert(im.name);
  std::vector<std::string> out;
  for (const auto& p : ctx.photos) {
    if (!registered.count(p.name)) out.push_back(p.name);
  }
  return out;
}

void RunUndistortion(Context& ctx, StageProgress& progress, const fs::path& model_dir) {
  std::error_code ec;
  for (const char* sub : {"images", "sparse", "stereo"})
    fs::remove_all(ctx.opt.workspace / sub, ec);
  std::vector<std::string> args = {"image_undistorter",
                                   "--image_path",
                                   ctx.opt.photos.string(),
                                   "--input_path",
                                   model_dir.string(),
                                   "--output_path",
                                   ctx.opt.workspace.string(),
                                   "--output_type",
                                   "COLMAP"};
  AddOption(args, ctx, {"max_image_size"}, std::to_string(ctx.opt.undistort_max_size));
  if (ctx.caps.options.count("max_image_size") == 0 && ctx.opt.undistort_max_size > 0) {
    args.push_back("--max_image_size");
    args.push_back(std::to_string(ctx.opt.undistort_max_size));
  }
  RunColmap(ctx, progress, args, static_cast<long>(ctx.photos.size()), "photos");
}

void RunSeries(Context& ctx) {
  const ColmapModel model = ReadColmapModel(ctx.opt.workspace / "sparse");
  std::map<std::string, const InputPhoto*> by_name;
  for (const auto& p : ctx.photos) by_name[p.name] = &p;
  std::vector<Photo> photos;
  int missing = 0;
  for (const auto& [id, im] : model.images) {
    Photo p;
    p.id = id;
    p.name = im.name;
    p.camera_id = im.camera_id;
    auto it = by_name.find(im.name);
    if (it != by_name.end()) p.exposure = it->second->exif.exposure;
    if (!p.exposure.Complete()) ++missing;
    photos.push_back(std::move(p));
  }
  if (missing) {
    spdlog::warn(
        "{} photo(s) lack exposure time, ISO or f-number in EXIF (counted as 1); edit "
        "series.json to set them",
        missing);
  }
  const auto series = GroupByExposure(photos);
  WriteSeriesJson(ctx.opt.workspace / "series.json", series, photos);
  for (const auto& s : series) {
    spdlog::info("series {}: {} photos, relative exposure {:.4g} ({:+.2f} EV)", s.name,
                 s.photo_indices.size(), s.relative_exposure, std::log2(s.relative_exposure));
  }
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

void RunDense(Context& ctx, StageProgress& progress, ReconstructReport& report) {
  const ColmapModel model = ReadColmapModel(ctx.opt.workspace / "sparse");
  const std::vector<Eigen::Vector3d> centers = CameraCenters(model);
  const std::string mode = DenseMode(ctx);
  DenseResult dense;
  auto t0 = Clock::now();
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
    AddOption(args, ctx, {"PatchMatchStereo.geom_consistency"}, "true");
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
  report.times.push_back({"dense." + mode, Seconds(t0)});
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
  t0 = Clock::now();
  AttributeOptions ao = ctx.opt.attribute_options;
  ao.threads = ctx.threads;
  const size_t removed = RemoveOutliers(dense.cloud, dense.view_dirs, centers, ao);
  EstimateNormals(dense.cloud, dense.view_dirs, ao);
  EstimateRadii(dense.cloud, ao);
  report.times.push_back({"dense.attributes", Seconds(t0)});
  spdlog::info("clean-up: {} outliers removed, {} points with normals and radii", removed,
               dense.cloud.size());
  WritePly(ctx.opt.workspace / "points.ply", dense.cloud);
  report.num_points = dense.cloud.size();
}

bool IsInside(const fs::path& child, const fs::path& parent) {
  const fs::path c = fs::weakly_canonical(child), p = fs::weakly_canonical(parent);
  auto ci = c.begin();
  for (auto pi = p.begin(); pi != p.end(); ++pi, ++ci) {
    if (pi->empty()) continue;
    if (ci == c.end() || *ci != *pi) return false;
  }
  return true;
}

// The options a stage's output depends on, one "name=value" line each, written into its
// logs/<stage>.done marker: a resumed run redoes a finished stage (and the ones after it) when
// they changed.
std::string StageSettings(const Context& ctx, const std::string& stage,
                          const std::string& matching) {
  const ReconstructOptions& o = ctx.opt;
  std::string s;
  const auto add = [&s](const char* name, const auto& value) {
    s += fmt::format("{}={}\n", name, value);
  };
  if (stage == "features") {
    // The photo set: names and file sizes, so that added, removed or replaced photos redo it.
    Fnv1a64 photos;
    for (const auto& p : ctx.photos) {
      std::error_code ec;
      photos.AddString(p.name).Add(
          static_cast<std::uint64_t>(fs::file_size(o.photos / p.name, ec)));
    }
    add("photos", fmt::format("{} ({:016x})", ctx.photos.size(), photos.value()));
    add("camera-model", o.camera_model);
    add("max-features", o.max_features);
    add("sift-size", o.sift_max_size);
  } else if (stage == "matching") {
    add("matching", matching);
    add("vocab-tree", o.vocab_tree.string());
  } else if (stage == "undistortion") {
    add("image-size", o.undistort_max_size);
  } else if (stage == "dense") {
    const std::string mode = DenseMode(ctx);
    add("dense", mode);
    const AttributeOptions& a = o.attribute_options;
    add("outlier-neighbors", a.outlier_neighbors);
    add("outlier-stddev", a.outlier_stddev);
    add("cleanup-version", kCleanupVersion);
    add("normal-neighbors", a.normal_neighbors);
    add("radius-neighbors", a.radius_neighbors);
    const DenseOptions& d = o.dense_options;
    if (mode == "cpu" || mode == "sweep") {
      add("dense-version", kDenseVersion);
      add("dense-size", d.max_size > 0 ? std::to_string(d.max_size) : "auto");
      add("dense-neighbors", d.num_neighbors);
      add("fusion-consistency", d.consistency);
      add("fusion-min-consistent", d.min_consistent);
      add("fusion-single-ncc", d.single_agreement_ncc);
      add("fusion-max-normal-error", d.max_normal_error);
    }
    if (mode == "sweep") {
      add("dense-depths", d.num_depths);
      add("sweep-window-radius", d.window_radius);
      add("sweep-min-ncc", d.min_ncc);
    } else if (mode == "cpu") {
      const PatchMatchOptions& p = d.patch_match;
      add("window-radius", p.window_radius);
      add("window-step", p.window_step);
      add("sigma-color", p.sigma_color);
      add("dense-levels", p.num_levels);
      add("coarse-iterations", p.coarse_iterations);
      add("dense-iterations", p.iterations);
      add("dense-geom-iterations", p.geom_iterations);
      add("geom-weight", p.geom_weight);
      add("geom-max-error", p.geom_max_error);
      add("best-views", p.best_views);
      add("dense-min-ncc", p.min_ncc);
      add("min-texture", p.min_texture);
      add("seed-radius", p.seed_radius);
      add("coarse-fill", p.coarse_fill);
    }
  }
  return s;
}

// "name old -> new" for each setting that differs between two StageSettings texts.
std::string ChangedSettings(const std::string& before, const std::string& now) {
  const auto parse = [](const std::string& text) {
    std::map<std::string, std::string> m;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
      const size_t eq = line.find('=');
      if (eq != std::string::npos) m[line.substr(0, eq)] = line.substr(eq + 1);
    }
    return m;
  };
  const auto a = parse(before), b = parse(now);
  std::set<std::string> names;
  for (const auto& [k, v] : a) names.insert(k);
  for (const auto& [k, v] : b) names.insert(k);
  std::string out;
  for (const auto& name : names) {
    const auto ia = a.find(name), ib = b.find(name);
    const std::string va = ia == a.end() ? "(none)" : ia->second;
    const std::string vb = ib == b.end() ? "(none)" : ib->second;
    if (va != vb) out += (out.empty() ? "" : ", ") + name + " " + va + " -> " + vb;
  }
  return out;
}

}  // namespace

const std::vector<std::string>& ReconstructStages() {
  static const std::vector<std::string> stages = {"features",     "matching", "mapping",
                                                  "undistortion", "series",   "dense"};
  return stages;
}

std::string ChooseMatching(int num_photos, int num_series, bool have_vocab_tree) {
  if (num_photos <= 50) return "exhaustive";
  if (have_vocab_tree) return "vocab_tree";
  if (num_series > 1) return "pairs";
  return "sequential";
}

namespace {

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

// Refuses option values that COLMAP or the dense stage would fail on only minutes later.
void CheckOptions(const ReconstructOptions& opt) {
  if (opt.max_features < 1) throw OptionError("max_features", "must be >= 1");
  if (opt.sift_max_size < 16) throw OptionError("sift_max_size", "must be >= 16");
  if (opt.undistort_max_size != -1 && opt.undistort_max_size < 16) {
    throw OptionError("undistort_max_size", "must be -1 (as shot) or >= 16");
  }
  const DenseOptions& d = opt.dense_options;
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
  if (opt.threads < 0) throw OptionError("threads", "must be >= 0 (0 = all cores)");
  const auto one_of = [](const std::string& value, std::initializer_list<const char*> names) {
    return std::any_of(names.begin(), names.end(), [&](const char* n) { return value == n; });
  };
  if (!one_of(opt.dense, {"auto", "cpu", "sweep", "colmap", "none"})) {
    throw OptionError("dense", "must be auto, cpu, sweep, colmap or none, got '" + opt.dense + "'");
  }
  if (!one_of(opt.matching, {"auto", "exhaustive", "sequential", "pairs", "vocab_tree"})) {
    throw OptionError(
        "matching",
        "must be auto, exhaustive, sequential, pairs or vocab_tree, got '" + opt.matching + "'");
  }
  if (opt.matching == "vocab_tree" && opt.vocab_tree.empty()) {
    throw OptionError("vocab_tree", "is needed by vocab_tree matching");
  }
}

}  // namespace

ReconstructReport Reconstruct(const ReconstructOptions& opt) {
  CheckOptions(opt);
  ReconstructReport report;
  Context ctx{opt, {}, {}, opt.workspace / "logs", {}, 1, 0};
  ctx.photos = ListPhotos(opt.photos);
  if (IsInside(opt.workspace, opt.photos)) {
    throw InputError(opt.workspace, "the workspace must not be inside the photo folder (" +
                                        opt.photos.string() + " is never modified)");
  }
  const auto exe = FindExecutable(opt.colmap);
  if (!exe) {
    throw InputError(opt.colmap,
                     "COLMAP executable not found in PATH (install colmap or name the "
                     "executable)");
  }
  ctx.colmap = *exe;
  ctx.caps = ProbeColmap(ctx.colmap);
  if (ctx.caps.version.empty() || ctx.caps.options.empty()) {
    throw InputError(ctx.colmap,
                     "does not look like a COLMAP executable (no version banner or "
                     "options in its help output)");
  }
  ctx.threads = opt.threads > 0
                    ? opt.threads
                    : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  spdlog::info("COLMAP {} ({} CUDA) at {}", ctx.caps.version,
               ctx.caps.has_cuda ? "with" : "without", ctx.colmap.string());
  report.num_photos = static_cast<int>(ctx.photos.size());
  fs::create_directories(ctx.logs);

  // Exposure series from EXIF (used by series-aware matching and series.json).
  std::vector<Photo> all;
  for (const auto& p : ctx.photos) {
    Photo ph;
    ph.name = p.name;
    ph.exposure = p.exif.exposure;
    all.push_back(ph);
  }
  const auto all_series = GroupByExposure(all);
  std::vector<int> series_of;
  for (const auto& p : all) series_of.push_back(p.series_id);
  const std::string matching =
      opt.matching == "auto"
          ? ChooseMatching(report.num_photos, static_cast<int>(all_series.size()),
                           !opt.vocab_tree.empty())
          : opt.matching;

  const auto& stages = ReconstructStages();
  bool rerun = opt.force;
  ColmapModel sparse_model;
  fs::path model_dir;
  for (size_t s = 0; s < stages.size(); ++s) {
    const std::string& stage = stages[s];
    const fs::path marker = ctx.logs / (stage + ".done");
    const std::string settings = StageSettings(ctx, stage, matching);
    if (!rerun && fs::exists(marker)) {
      const std::string before = ReadFileToString(marker);
      // An empty marker records no settings (stages without options, older workspaces).
      if (before.empty() || before == settings) {
        spdlog::info("reconstruct [{}/{}] {}: done before, skipped (--force to redo)", s + 1,
                     stages.size(), stage);
        if (stage == "mapping") model_dir = LargestModel(opt.workspace / "sfm", &sparse_model);
        continue;
      }
      spdlog::info("reconstruct [{}/{}] {}: redone, its options changed: {}", s + 1, stages.size(),
                   stage, ChangedSettings(before, settings));
    }
    rerun = true;  // every later stage depends on this one
    std::error_code ec;
    fs::remove(marker, ec);
    StageProgress progress(static_cast<int>(s + 1), static_cast<int>(stages.size()),
                           stage == "matching" ? stage + " (" + matching + ")" : stage);
    if (stage == "features") {
      RunFeatures(ctx, progress);
    } else if (stage == "matching") {
      RunMatching(ctx, progress, matching, series_of);
    } else if (stage == "mapping") {
      RunMapping(ctx, progress);
      model_dir = LargestModel(opt.workspace / "sfm", &sparse_model);
    } else if (stage == "undistortion") {
      if (model_dir.empty()) {
        throw InputError(opt.photos,
                         "COLMAP could not register the photos (no model); check "
                         "overlap and texture, see " +
                             ctx.logs.string());
      }
      RunUndistortion(ctx, progress, model_dir);
    } else if (stage == "series") {
      RunSeries(ctx);
    } else if (stage == "dense") {
      RunDense(ctx, progress, report);
    }
    report.times.push_back({stage, progress.Elapsed()});
    WriteFileAtomic(marker, settings);
    if (stage == "mapping") {
      const auto missing = Unregistered(ctx, sparse_model);
      spdlog::info("registered {}/{} photos", sparse_model.images.size(), ctx.photos.size());
      if (!missing.empty()) {
        std::string names;
        for (const auto& m : missing) names += " " + m;
        spdlog::warn("{} photo(s) not registered:{}", missing.size(), names);
        spdlog::warn(
            "hint: these share too few features with the others: take photos with more "
            "overlap (about 60%) and texture, or try exhaustive matching");
      }
    }
  }
  if (model_dir.empty()) model_dir = LargestModel(opt.workspace / "sfm", &sparse_model);
  report.num_registered = static_cast<int>(sparse_model.images.size());
  report.unregistered = Unregistered(ctx, sparse_model);
  if (report.num_points == 0 && fs::exists(opt.workspace / "points.ply")) {
    report.num_points = ReadPly(opt.workspace / "points.ply").size();
  }
  return report;
}

}  // namespace hdribr
