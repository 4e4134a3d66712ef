// Grouping photos into exposure series (photos shot at one fixed exposure).
#pragma once

#include <string>
#include <vector>

#include "core/photo.h"

namespace hdribr {

struct ExposureSeries {
  int id = -1;
  std::string name;                // "series0", or as given in series.json
  double relative_exposure = 1;    // Exposure::Relative() shared by its photos
  std::vector<int> photo_indices;  // indices into Scene::photos
};

// Groups photos whose relative exposure agrees within tolerance_ev stops (default 1/6 EV),
// ordered from darkest to brightest; sets Photo::series_id.
std::vector<ExposureSeries> GroupByExposure(std::vector<Photo>& photos,
                                            double tolerance_ev = 1.0 / 6.0);

}  // namespace hdribr
