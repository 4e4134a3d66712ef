// The reconstruction's COLMAP stages (features, matching, mapping, undistortion) and the
// exposure series, each run by `Reconstruct` in turn.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "frontend/colmap_cli.h"
#include "frontend/photo_folder.h"
#include "frontend/reconstruct.h"
#include "frontend/stage_progress.h"
#include "io/colmap_model.h"

namespace hdribr {

// What every stage reads: the options, the colmap executable and what it offers, the log
// folder, the photos, and the count of colmap calls so far (numbering their logs).
struct StageContext {
  const ReconstructOptions& opt;
  std::filesystem::path colmap;
  ColmapCapabilities caps;
  std::filesystem::path logs;
  std::vector<InputPhoto> photos;
  int threads = 1;
  int call_index = 0;
};

// Adds "--name value" when this colmap knows one of the candidate names.
void AddColmapOption(std::vector<std::string>& args, const StageContext& ctx,
                     const std::vector<std::string>& candidates, const std::string& value);

// Runs one colmap command, logged to logs/NN_<command>.log, with progress from its output
// (`offset` + its count out of `total`, or out of its own total when 0). Throws
// std::runtime_error when it fails, after logging its last lines.
void RunColmap(StageContext& ctx, StageProgress& progress, const std::vector<std::string>& args,
               long num_images, const char* unit, long offset = 0, long total = 0);

// SIFT features of every photo into workspace/database.db, one colmap call per camera.
void RunFeatures(StageContext& ctx, StageProgress& progress);
// Feature matching by `strategy` (exhaustive, sequential, pairs, vocab_tree); `series_of`
// holds each photo's exposure series (pairs).
void RunMatching(StageContext& ctx, StageProgress& progress, const std::string& strategy,
                 const std::vector<int>& series_of);
// Incremental mapping into workspace/sfm.
void RunMapping(StageContext& ctx, StageProgress& progress);
// The mapper's largest model folder (most registered photos), or empty; its model into
// `model_out` when given.
std::filesystem::path LargestModel(const std::filesystem::path& sfm, ColmapModel* model_out);
// Names of the photos missing from the model.
std::vector<std::string> Unregistered(const StageContext& ctx, const ColmapModel& model);
// Undistorted images and model of `model_dir` into workspace/images and workspace/sparse.
void RunUndistortion(StageContext& ctx, StageProgress& progress,
                     const std::filesystem::path& model_dir);
// workspace/series.json: the registered photos grouped by exposure.
void RunSeries(StageContext& ctx);

}  // namespace hdribr
