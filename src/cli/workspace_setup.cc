#include "cli/workspace_setup.h"

#include <spdlog/spdlog.h>

#include "core/error.h"
#include "frontend/photo_folder.h"
#include "frontend/reconstruct.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "hdr/response_curve.h"
#include "io/workspace.h"

namespace hdribr::cli {
namespace fs = std::filesystem;

WorkspaceCalibration CalibrateWorkspace(const fs::path& workspace,
                                        const render::CloudCalibrationOptions& options) {
  const Scene scene = LoadWorkspace(workspace);
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  WorkspaceCalibration out;
  out.result = render::CalibrateFromCloud(shaders, scene, options);
  out.calibration = render::ToWorkspaceCalibration(scene, out.result);
  const fs::path dir = workspace / kCalibFolder;
  fs::create_directories(dir);
  out.response_file = dir / out.calibration.response_file;
  out.exposures_file = dir / kCalibExposures;
  WriteResponseCurve(out.response_file, out.result.calibration.response);
  WriteRadiometricCalibration(out.exposures_file, out.calibration);
  return out;
}

fs::path WorkspaceOrPhotos(const fs::path& arg) {
  try {
    DetectWorkspace(arg);
    return arg;
  } catch (const InputError& not_workspace) {
    // A folder of photos instead, else the workspace's own error.
    try {
      ListPhotos(arg);
    } catch (const InputError&) {
      throw not_workspace;
    }
  }
  const fs::path folder = fs::absolute(arg).lexically_normal();
  const fs::path name =
      folder.filename().empty() ? folder.parent_path().filename() : folder.filename();
  const fs::path base = folder.filename().empty() ? folder.parent_path() : folder;
  const fs::path workspace = base.parent_path() / (name.string() + "-hdribr");
  spdlog::info("{} is a folder of photos: its workspace is {} (made once, reused after)",
               arg.string(), workspace.string());
  ReconstructOptions ro;
  ro.photos = folder;
  ro.workspace = workspace;
  Reconstruct(ro);  // resumes: finished stages are skipped
  if (!fs::exists(workspace / kCalibFolder / kCalibExposures)) {
    const Scene scene = LoadWorkspace(workspace);
    if (scene.series.size() >= 2) {
      try {
        const WorkspaceCalibration c = CalibrateWorkspace(workspace, {});
        spdlog::info("calibrated the response and the exposures of {} photos into {}",
                     c.calibration.photos.size(), (workspace / kCalibFolder).string());
      } catch (const UsageError& e) {
        spdlog::warn("no radiometric calibration: {}", e.what());
      }
    }
  }
  return workspace;
}

}  // namespace hdribr::cli
