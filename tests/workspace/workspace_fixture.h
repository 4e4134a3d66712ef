// A small hdribr workspace made in code: 2 cameras, 4 photos in 2 exposure series, 200 points.
#pragma once

#include <filesystem>

namespace hdribr::test {

struct FixtureOptions {
  bool write_series_json = true;
  bool write_points_ply = true;
  bool distorted_camera = false;
};

// Writes sparse/ (TEXT), images/*.jpg (with EXIF), points.ply and series.json under dir.
void MakeWorkspace(const std::filesystem::path& dir, const FixtureOptions& options = {});

}  // namespace hdribr::test
