#include "frontend/colmap_stages.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <stdexcept>

#include "core/error.h"
#include "core/exposure_series.h"
#include "io/atomic_file.h"
#include "io/series_json.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

// COLMAP's use_gpu value.
std::string GpuFlag(const StageContext& ctx) { return ctx.caps.has_cuda ? "1" : "0"; }

}  // namespace

void AddColmapOption(std::vector<std::string>& args, const StageContext& ctx,
                     const std::vector<std::string>& candidates, const std::string& value) {
  const std::string name = ctx.caps.Pick(candidates);
  if (name.empty()) {
    spdlog::debug("colmap has none of the options {}: not passed", candidates.front());
    return;
  }
  args.push_back("--" + name);
  args.push_back(value);
}

void RunColmap(StageContext& ctx, StageProgress& progress, const std::vector<std::string>& args,
               long num_images, const char* unit, long offset, long total) {
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

void RunFeatures(StageContext& ctx, StageProgress& progress) {
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
    AddColmapOption(args, ctx, {"ImageReader.camera_model"}, ctx.opt.camera_model);
    AddColmapOption(args, ctx, {"ImageReader.single_camera"}, "1");
    AddColmapOption(args, ctx,
                    {"SiftExtraction.max_num_features", "FeatureExtraction.max_num_features"},
                    std::to_string(ctx.opt.max_features));
    AddColmapOption(args, ctx,
                    {"SiftExtraction.max_image_size", "FeatureExtraction.max_image_size"},
                    std::to_string(ctx.opt.sift_max_size));
    AddColmapOption(args, ctx, {"SiftExtraction.use_gpu", "FeatureExtraction.use_gpu"},
                    GpuFlag(ctx));
    AddColmapOption(args, ctx, {"SiftExtraction.num_threads", "FeatureExtraction.num_threads"},
                    std::to_string(ctx.threads));
    // Offset the per-group counts so that progress covers all photos.
    RunColmap(ctx, progress, args, 0, "photos", offset, static_cast<long>(ctx.photos.size()));
    offset += static_cast<long>(groups[g].photo_indices.size());
  }
}

void RunMatching(StageContext& ctx, StageProgress& progress, const std::string& strategy,
                 const std::vector<int>& series_of) {
  const fs::path db = ctx.opt.workspace / "database.db";
  const long n = static_cast<long>(ctx.photos.size());
  std::vector<std::string> args;
  if (strategy == "exhaustive") {
    args = {"exhaustive_matcher", "--database_path", db.string()};
    AddColmapOption(args, ctx, {"ExhaustiveMatching.block_size"}, "12");
  } else if (strategy == "sequential") {
    args = {"sequential_matcher", "--database_path", db.string()};
    AddColmapOption(args, ctx, {"SequentialMatching.overlap"}, "10");
    AddColmapOption(args, ctx, {"SequentialMatching.quadratic_overlap"}, "1");
    if (!ctx.opt.vocab_tree.empty()) {
      AddColmapOption(args, ctx, {"SequentialMatching.loop_detection"}, "1");
      AddColmapOption(args, ctx, {"SequentialMatching.vocab_tree_path"},
                      ctx.opt.vocab_tree.string());
    }
  } else if (strategy == "vocab_tree") {
    if (ctx.opt.vocab_tree.empty())
      throw OptionError("vocab_tree", "is needed by vocab_tree matching");
    if (!fs::exists(ctx.opt.vocab_tree))
      throw InputError(ctx.opt.vocab_tree, "vocabulary tree file does not exist");
    args = {"vocab_tree_matcher", "--database_path", db.string()};
    AddColmapOption(args, ctx, {"VocabTreeMatching.vocab_tree_path"}, ctx.opt.vocab_tree.string());
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
  AddColmapOption(args, ctx, {"SiftMatching.use_gpu", "FeatureMatching.use_gpu"}, GpuFlag(ctx));
  AddColmapOption(args, ctx, {"SiftMatching.num_threads", "FeatureMatching.num_threads"},
                  std::to_string(ctx.threads));
  RunColmap(ctx, progress, args, n, strategy == "exhaustive" ? "blocks" : "photos");
}

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

void RunMapping(StageContext& ctx, StageProgress& progress) {
  const fs::path sfm = ctx.opt.workspace / "sfm";
  std::error_code ec;
  fs::remove_all(sfm, ec);
  fs::create_directories(sfm);
  std::vector<std::string> args = {
      "mapper",       "--database_path",       (ctx.opt.workspace / "database.db").string(),
      "--image_path", ctx.opt.photos.string(), "--output_path",
      sfm.string()};
  AddColmapOption(args, ctx, {"Mapper.num_threads"}, std::to_string(ctx.threads));
  RunColmap(ctx, progress, args, static_cast<long>(ctx.photos.size()), "photos registered");
}

std::vector<std::string> Unregistered(const StageContext& ctx, const ColmapModel& model) {
  std::set<std::string> registered;
  for (const auto& [id, im] : model.images) registered.insert(im.name);
  std::vector<std::string> out;
  for (const auto& p : ctx.photos) {
    if (!registered.count(p.name)) out.push_back(p.name);
  }
  return out;
}

void RunUndistortion(StageContext& ctx, StageProgress& progress, const fs::path& model_dir) {
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
  AddColmapOption(args, ctx, {"max_image_size"}, std::to_string(ctx.opt.undistort_max_size));
  if (ctx.caps.options.count("max_image_size") == 0 && ctx.opt.undistort_max_size > 0) {
    args.push_back("--max_image_size");
    args.push_back(std::to_string(ctx.opt.undistort_max_size));
  }
  RunColmap(ctx, progress, args, static_cast<long>(ctx.photos.size()), "photos");
}

void RunSeries(StageContext& ctx) {
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

}  // namespace hdribr
