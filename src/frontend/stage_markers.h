// The resume markers of the reconstruction's stages: logs/<stage>.done holds the settings its
// output depends on, one "name=value" line each, so that a resumed run redoes a finished stage
// (and the ones after it) when one changed.
#pragma once

#include <string>
#include <vector>

#include "frontend/photo_folder.h"
#include "frontend/reconstruct.h"

namespace hdribr {

// What the settings are read from.
struct StageInputs {
  const ReconstructOptions& options;
  const std::vector<InputPhoto>& photos;
  std::string matching;    // the matching strategy that runs (`auto` resolved)
  std::string dense_mode;  // the dense method that runs (DenseMode)
};

// The settings text of `stage` ("" for a stage without settings).
std::string StageSettings(const StageInputs& inputs, const std::string& stage);

// Whether a marker's text lets its stage be skipped with the settings `now`: it records them,
// or it is empty (a marker of a stage without settings, or of an older workspace).
bool MarkerCurrent(const std::string& marker, const std::string& now);

// "name old -> new" for each setting that differs between two settings texts, ", "-separated;
// "(none)" for a setting one of them lacks.
std::string ChangedSettings(const std::string& before, const std::string& now);

}  // namespace hdribr
