// Loading a workspace folder into a Scene, and checking it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/scene.h"

namespace hdribr {

// Layouts recognised (docs/formats.md):
//  - hdribr workspace: sparse/ (COLMAP model, or sparse/0/), images/, points.ply, series.json
//  - COLMAP dense workspace: images/, sparse/, fused.ply (output of image_undistorter+fusion)
//  - a bare COLMAP model folder (cameras/images/points3D), points from points3D, images/ beside.
struct WorkspaceLayout {
  std::filesystem::path root;
  std::filesystem::path sparse_dir;
  std::filesystem::path images_dir;
  std::filesystem::path points_ply;   // empty when the sparse points are used
  std::filesystem::path series_json;  // empty when absent
  std::string kind;                   // "hdribr", "colmap-dense", "colmap-sparse"
};

// Finds the layout of a workspace folder; throws InputError if it is none of the above.
WorkspaceLayout DetectWorkspace(const std::filesystem::path& root);

// Throws UsageError when `out`, a file or folder about to be written, lies inside an input
// folder of the workspace at `root` (its photos or its COLMAP model), where the next load or
// reconstruction would take it for input.
void CheckOutsideInputs(const std::filesystem::path& root, const std::filesystem::path& out);

struct LoadOptions {
  bool read_exif = true;  // fill exposure from the photos' EXIF when no series.json says it
};

// Loads cameras, photos (with exposure and series), points; calls Scene::UpdateDerived().
// Cameras with distortion are refused with a message to run `colmap image_undistorter`, unless
// their distortion is zero. Throws InputError on bad input.
Scene LoadWorkspace(const std::filesystem::path& root, const LoadOptions& options = {});

// One line per problem found: missing photos, a photo not of its camera's shape, NaN poses,
// no points, ... Empty when the scene is sound.
std::vector<std::string> ValidateScene(const Scene& scene);

}  // namespace hdribr
