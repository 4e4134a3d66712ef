// `hdribr depth WORKSPACE (--photo NAME | --camera FILE)`: the splat depth pass for one view,
// written as a camera-z EXR plus a false-colour PNG beside it (for inspection).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "cli/render_options.h"
#include "core/error.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "io/atomic_file.h"
#include "io/camera_spec.h"
#include "io/exr.h"
#include "io/false_colour.h"
#include "io/image.h"
#include "io/workspace.h"
#include "render/depth_pass.h"
#include "render/readback.h"

namespace hdribr::cli {
namespace {

struct DepthOptions {
  std::string workspace;
  std::string photo;
  std::string camera_file;
  render::DepthPassOptions pass;  // mode and raster
  std::string size;
  std::string out;
};

// Depth as a turbo colour map between the 1st and 99th percentiles of the valid depths
// (near = red end), invalid pixels black.
cv::Mat DepthFalseColour(const cv::Mat& depth) {
  std::vector<float> values;
  for (auto it = depth.begin<float>(); it != depth.end<float>(); ++it) {
    if (*it > 0) values.push_back(*it);
  }
  if (values.empty()) return cv::Mat(depth.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  std::sort(values.begin(), values.end());
  const float lo = values[values.size() / 100];
  const float hi = std::max(values[values.size() * 99 / 100], lo * 1.0001f);
  return FalseColour(-depth, -hi, -lo, depth > 0);
}

int Run(const DepthOptions& opt) {
  const render::DepthMode mode = opt.pass.mode;
  const std::filesystem::path out = opt.out;
  CheckOutsideInputs(opt.workspace, out);
  const Scene scene = LoadWorkspace(opt.workspace);
  Camera camera;
  Rigid3d cam_from_world;
  std::string view_name;
  if (!opt.photo.empty()) {
    const int i = scene.FindPhoto(opt.photo);
    if (i < 0) throw InputError(opt.workspace, "no photo named '" + opt.photo + "'");
    camera = scene.CameraOf(scene.photos[static_cast<size_t>(i)]);
    cam_from_world = scene.photos[static_cast<size_t>(i)].cam_from_world;
    view_name = opt.photo;
  } else {
    const View view = ReadCameraFile(opt.camera_file);
    camera = view.camera;
    cam_from_world = view.cam_from_world;
    view_name = opt.camera_file;
  }
  const cv::Size size =
      opt.size.empty() ? cv::Size(camera.width, camera.height) : ParseSize(opt.size);
  if (scene.points.empty()) spdlog::warn("the workspace has no points: the depth is empty");

  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  render::DepthPass pass(shaders, opt.pass);
  pass.SetPoints(scene.points);
  render::DepthTarget target = render::DepthTarget::Create(size.width, size.height);
  pass.Process(camera, cam_from_world, target);
  const render::DepthImages images = render::ReadDepthTarget(target);

  std::filesystem::path png = out;
  png.replace_extension(".png");
  WriteExr(out, images.depth, ExrPixel::kFloat, "Z");
  WriteImage(png, DepthFalseColour(images.depth));

  double lo = 0, hi = 0;
  cv::minMaxLoc(images.depth, nullptr, &hi);
  cv::Mat masked = images.depth.clone();
  masked.setTo(std::numeric_limits<float>::max(), images.depth <= 0);
  cv::minMaxLoc(masked, &lo);
  const int valid = cv::countNonZero(images.valid);
  std::printf("view %s  mode %s  %dx%d  %zu points (%s)\n", view_name.c_str(),
              render::DepthModeName(mode).c_str(), size.width, size.height, scene.points.size(),
              context.Renderer().c_str());
  std::printf("valid %.2f%% of pixels, depth %.4g .. %.4g\n",
              100.0 * valid / (size.width * size.height), valid ? lo : 0.0, valid ? hi : 0.0);
  std::printf("wrote %s and %s\n", out.c_str(), png.c_str());
  return 0;
}

}  // namespace

CommandRunner SetupDepth(CLI::App& sub);
HDRIBR_COMMAND(depth, "Depth map of one view by the splat depth pass (EXR + false-colour PNG)",
               SetupDepth, 30);

CommandRunner SetupDepth(CLI::App& sub) {
  auto opt = std::make_shared<DepthOptions>();
  sub.add_option("workspace", opt->workspace, "Workspace folder")->required();
  auto* photo = sub.add_option("--photo", opt->photo, "View of this photo (COLMAP image name)");
  auto* camera =
      sub.add_option("--camera", opt->camera_file, "Camera file (JSON, docs/formats.md)");
  photo->excludes(camera);
  AddPointRasterOption(sub, opt->pass.raster);
  AddDepthModeOption(sub, opt->pass.mode, "--mode");
  AddSilhouetteTrimOption(sub, opt->pass.silhouette_trim);
  sub.add_option("--size", opt->size, "Output size WxH (default: the camera's)")
      ->check(SizeCheck());
  sub.add_option("--out", opt->out, "Output depth EXR (camera z, channel Z, 0 = invalid)")
      ->required()
      ->check(OutputFolderCheck())
      ->check(ExtensionCheck({".exr"}));
  return [opt, photo, camera] {
    if (photo->count() == 0 && camera->count() == 0) {
      throw UsageError("depth: give --photo NAME or --camera FILE");
    }
    return Run(*opt);
  };
}

}  // namespace hdribr::cli
