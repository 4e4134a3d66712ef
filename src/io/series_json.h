// series.json: the user-editable grouping of photos into exposure series (docs/formats.md).
#pragma once

#include <filesystem>
#include <vector>

#include "core/exposure_series.h"
#include "core/photo.h"

namespace hdribr {

// Reads series.json and assigns Photo::series_id by photo name. Throws InputError naming the
// file for bad JSON, unknown photo names, or photos listed twice.
std::vector<ExposureSeries> ReadSeriesJson(const std::filesystem::path& path,
                                           std::vector<Photo>& photos);
// Writes the grouping (names, relative exposure, exposure fields of each photo) atomically.
void WriteSeriesJson(const std::filesystem::path& path, const std::vector<ExposureSeries>& series,
                     const std::vector<Photo>& photos);

}  // namespace hdribr
