#include "frontend/reconstruct.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <thread>

#include "core/error.h"
#include "core/exposure_series.h"
#include "frontend/colmap_stages.h"
#include "frontend/dense_stage.h"
#include "frontend/stage_markers.h"
#include "io/atomic_file.h"
#include "io/ply.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

// Whether `child` is `parent` or inside it.
bool IsInside(const fs::path& child, const fs::path& parent) {
  const fs::path c = fs::weakly_canonical(child), p = fs::weakly_canonical(parent);
  auto ci = c.begin();
  for (auto pi = p.begin(); pi != p.end(); ++pi, ++ci) {
    if (pi->empty()) continue;
    if (ci == c.end() || *ci != *pi) return false;
  }
  return true;
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

void ReconstructOptions::Check() const {
  const ReconstructOptions& opt = *this;
  if (opt.max_features < 1) throw OptionError("max_features", "must be >= 1");
  if (opt.sift_max_size < 16) throw OptionError("sift_max_size", "must be >= 16");
  if (opt.undistort_max_size != -1 && opt.undistort_max_size < 16) {
    throw OptionError("undistort_max_size", "must be -1 (as shot) or >= 16");
  }
  CheckDenseOptions(opt.dense_options);
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

ReconstructReport Reconstruct(const ReconstructOptions& opt) {
  opt.Check();
  ReconstructReport report;
  StageContext ctx{opt, {}, {}, opt.workspace / "logs", {}, 1, 0};
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

  const StageInputs inputs{opt, ctx.photos, matching, DenseMode(ctx)};
  const auto& stages = ReconstructStages();
  bool rerun = opt.force;
  ColmapModel sparse_model;
  fs::path model_dir;
  for (size_t s = 0; s < stages.size(); ++s) {
    const std::string& stage = stages[s];
    const fs::path marker = ctx.logs / (stage + ".done");
    const std::string settings = StageSettings(inputs, stage);
    if (!rerun && fs::exists(marker)) {
      const std::string before = ReadFileToString(marker);
      if (MarkerCurrent(before, settings)) {
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
