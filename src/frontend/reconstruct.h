// `hdribr reconstruct`: photos -> calibrated, undistorted workspace with a dense oriented cloud.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "frontend/dense_mvs.h"
#include "frontend/point_attributes.h"

namespace hdribr {

struct ReconstructOptions {
  std::filesystem::path photos;
  std::filesystem::path workspace;
  bool force = false;                // rerun finished stages
  std::string colmap = "colmap";     // executable name or path
  std::string matching = "auto";     // auto, exhaustive, sequential, pairs, vocab_tree
  std::filesystem::path vocab_tree;  // vocabulary tree file (enables vocab_tree in auto)
  int max_features = 2048;           // SIFT features per photo (COLMAP's default is 8192)
  int sift_max_size = 1600;          // photos are downscaled to this for SIFT only
  std::string camera_model = "SIMPLE_RADIAL";
  int undistort_max_size = -1;  // largest side of the workspace images (-1: as shot)
  // auto (COLMAP if it has CUDA, else cpu), cpu (PatchMatch), sweep (plane sweep), colmap, none
  std::string dense = "auto";
  DenseOptions dense_options;  // its method follows `dense`
  AttributeOptions attribute_options;
  int threads = 0;  // 0: hardware concurrency

  // Throws OptionError naming the first field that COLMAP or the dense stage would fail on
  // only minutes later.
  void Check() const;
};

// Seconds spent in each stage that ran (skipped stages are absent).
struct StageTime {
  std::string stage;
  double seconds = 0;
};

struct ReconstructReport {
  int num_photos = 0;
  int num_registered = 0;
  std::vector<std::string> unregistered;
  size_t num_points = 0;
  std::vector<StageTime> times;
};

// The stages in order (names used for the logs/<stage>.done markers and progress lines).
const std::vector<std::string>& ReconstructStages();

// Matching strategy chosen for `auto`: exhaustive up to 50 photos; above, vocab_tree when a
// vocabulary file is given, pairs (series-aware shooting order) when several exposure series,
// else sequential.
std::string ChooseMatching(int num_photos, int num_series, bool have_vocab_tree);

// Runs the stages that have not finished yet (all with force). Throws InputError for bad input,
// std::runtime_error when colmap fails (its last lines are logged first).
ReconstructReport Reconstruct(const ReconstructOptions& options);

}  // namespace hdribr
