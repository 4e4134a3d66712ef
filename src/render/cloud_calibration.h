// Radiometric calibration of a workspace from its point cloud: every point seen by several
// photos is a Debevec-Malik sample of one radiance at several exposures
// (hdr/multiview_calibration.h); which photos see it comes from their depth maps (the depth
// pass, so the occlusion test is the renderer's own).
#pragma once

#include <filesystem>
#include <vector>

#include "core/scene.h"
#include "gl/shader_library.h"
#include "hdr/multiview_calibration.h"
#include "io/radiometric_calibration.h"
#include "render/depth_pass.h"

namespace hdribr::render {

struct CloudCalibrationOptions {
  GatherOptions gather;
  MultiViewOptions solve;
  DepthPassOptions depth;
  int max_size = 1024;  // photos and depth maps are used at this longest side at most (pixels)
  std::filesystem::path depth_cache_dir;  // the photos' depth-map cache; empty = none
};

struct CloudCalibrationResult {
  MultiViewCalibration calibration;
  std::vector<double> prior_log_exposure;  // ln EXIF relative exposure, NaN without EXIF
  int samples = 0;                         // gathered samples
  double depth_seconds = 0, gather_seconds = 0, solve_seconds = 0;
};

// Gathers samples from every photo and solves the response and the photos' exposures, with
// the EXIF exposures as the prior. Needs a current GL 4.5 context. Throws UsageError when the
// photos cannot constrain a calibration (one photo, no overlap, all saturated), InputError for
// an unreadable photo.
CloudCalibrationResult CalibrateFromCloud(const gl::ShaderLibrary& shaders, const Scene& scene,
                                          const CloudCalibrationOptions& options = {});

// The workspace's calib/exposures.json content of a result.
RadiometricCalibration ToWorkspaceCalibration(const Scene& scene,
                                              const CloudCalibrationResult& result);

}  // namespace hdribr::render
