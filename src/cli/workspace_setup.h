// Workspace preparation shared by subcommands: the radiometric calibration from the point cloud
// (`calibrate`), and a folder of photos turned into a workspace (`view PHOTOS/`, `hdr PHOTOS/`).
#pragma once

#include <filesystem>

#include "io/radiometric_calibration.h"
#include "render/cloud_calibration.h"

namespace hdribr::cli {

// What CalibrateWorkspace found and wrote.
struct WorkspaceCalibration {
  render::CloudCalibrationResult result;
  RadiometricCalibration calibration;
  std::filesystem::path response_file, exposures_file;
};

// Calibrates the workspace at `workspace` from its point cloud (its own headless GL context)
// and writes WORKSPACE/calib/. Throws UsageError when the photos cannot constrain a calibration.
WorkspaceCalibration CalibrateWorkspace(const std::filesystem::path& workspace,
                                        const render::CloudCalibrationOptions& options);

// `arg` when it is a workspace; when it is a folder of photos instead, the workspace beside it
// (PHOTOS-hdribr), made by `reconstruct` (resumed if interrupted) and calibrated from its cloud
// when its photos have several exposures, once: later calls reuse it. Says what it does.
std::filesystem::path WorkspaceOrPhotos(const std::filesystem::path& arg);

}  // namespace hdribr::cli
