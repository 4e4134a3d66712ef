#include "render/blend_options.h"

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace hdribr::render {

std::string BlendWeightsName(BlendWeights weights) {
  return weights == BlendWeights::kUnstructured ? "ulr" : "paper";
}

BlendWeights ParseBlendWeights(const std::string& name) {
  for (BlendWeights w : kAllBlendWeights) {
    if (BlendWeightsName(w) == name) return w;
  }
  throw UsageError("unknown blending weights '" + name + "' (paper, ulr)");
}

std::string BackgroundName(Background background) {
  switch (background) {
    case Background::kInfinity:
      return "infinity";
    case Background::kSphere:
      return "sphere";
    case Background::kPlane:
      return "plane";
    case Background::kNone:
      break;
  }
  return "none";
}

Background ParseBackground(const std::string& name) {
  for (Background b : kAllBackgrounds) {
    if (BackgroundName(b) == name) return b;
  }
  throw UsageError("unknown background '" + name + "' (none, infinity, sphere, plane)");
}

std::string PhotoSamplingName(PhotoSampling sampling) {
  return sampling == PhotoSampling::kCubic ? "cubic" : "linear";
}

PhotoSampling ParsePhotoSampling(const std::string& name) {
  for (PhotoSampling s : kAllPhotoSamplings) {
    if (PhotoSamplingName(s) == name) return s;
  }
  throw UsageError("unknown photo sampling '" + name + "' (linear, cubic)");
}

std::vector<BlendOptionProblem> BlendOptionProblems(const BlendOptions& options) {
  std::vector<BlendOptionProblem> problems;
  if (options.k_best < 0 || options.k_best > kMaxKBest) {
    problems.push_back({"k_best", "must be in [0, " + std::to_string(kMaxKBest) +
                                      "] (0 = the default), got " +
                                      std::to_string(options.k_best)});
  }
  if (!(options.lambda >= 0.0f && options.lambda < 1.0f)) {
    problems.push_back({"lambda", "must be in [0, 1), got " + std::to_string(options.lambda)});
  }
  if (!(options.occlusion_tolerance > 0.0f && options.occlusion_tolerance < 1.0f)) {
    problems.push_back({"occlusion_tolerance",
                        "must be in (0, 1), got " + std::to_string(options.occlusion_tolerance)});
  }
  if (!(options.filter >= 0.0f && options.filter <= kMaxFilter)) {
    std::ostringstream problem;
    problem << "must be in [0, " << kMaxFilter << "] (0 = off), got " << options.filter;
    problems.push_back({"filter", problem.str()});
  }
  if (!(options.outlier_scale >= 0.0f && std::isfinite(options.outlier_scale))) {
    std::ostringstream problem;
    problem << "must be finite and >= 0 (0 = off), got " << options.outlier_scale;
    problems.push_back({"outlier_scale", problem.str()});
  }
  if (!(options.refine_depth >= 0.0f && options.refine_depth <= kMaxRefineDepth)) {
    std::ostringstream problem;
    problem << "must be in [0, " << kMaxRefineDepth << "] (0 = off), got " << options.refine_depth;
    problems.push_back({"refine_depth", problem.str()});
  }
  return problems;
}

void ValidateBlendOptions(const BlendOptions& options) {
  const std::vector<BlendOptionProblem> problems = BlendOptionProblems(options);
  if (!problems.empty()) {
    throw OptionError(problems[0].field, problems[0].problem);
  }
}

bool BlendRanksPhotos(const BlendOptions& options, int photos) {
  if (options.mode == BlendMode::kNearestPhoto) return false;
  if (options.weights == BlendWeights::kUnstructured) return true;
  return options.k_best > 0 && options.k_best < photos;
}

int RankedPhotosPerPixel(const BlendOptions& options) {
  if (options.mode == BlendMode::kNearestPhoto) return 1;
  if (options.weights == BlendWeights::kUnstructured) {
    return (options.k_best > 0 ? options.k_best : kDefaultUnstructuredK) + 1;
  }
  return options.k_best;
}

}  // namespace hdribr::render
