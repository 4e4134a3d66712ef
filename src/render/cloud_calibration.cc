#include "render/cloud_calibration.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "io/image.h"
#include "render/photo_depth_maps.h"
#include "render/readback.h"

namespace hdribr::render {
namespace {

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ln of the EXIF relative exposure; NaN when the photo has no exposure field at all.
double PriorLogExposure(const Photo& photo) {
  const Exposure& e = photo.exposure;
  if (!e.time_s && !e.iso && !e.f_number) return std::numeric_limits<double>::quiet_NaN();
  return std::log(e.Relative());
}

}  // namespace

CloudCalibrationResult CalibrateFromCloud(const gl::ShaderLibrary& shaders, const Scene& scene,
                                          const CloudCalibrationOptions& options) {
  CloudCalibrationResult result;
  if (scene.photos.size() < 2) {
    throw UsageError("radiometric calibration needs at least two photos (the workspace has " +
                     std::to_string(scene.photos.size()) + ")");
  }
  if (scene.points.empty()) throw UsageError("the workspace has no points to calibrate from");
  auto t0 = std::chrono::steady_clock::now();
  DepthPass pass(shaders, options.depth);
  pass.SetPoints(scene.points);
  const PhotoDepthMaps maps(scene, pass, 1.0, options.depth_cache_dir);
  std::vector<MultiViewPhoto> photos(scene.photos.size());
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    const Photo& photo = scene.photos[i];
    MultiViewPhoto& p = photos[i];
    const cv::Size size = maps.layer_size(static_cast<int>(i));
    const cv::Mat depth = ReadTextureLayerR32F(maps.depth(), static_cast<int>(i));
    const double s = std::min(1.0, double(options.max_size) / std::max(size.width, size.height));
    const cv::Size out(std::max(1, static_cast<int>(std::lround(size.width * s))),
                       std::max(1, static_cast<int>(std::lround(size.height * s))));
    cv::resize(depth(cv::Rect({0, 0}, size)), p.depth, out, 0, 0, cv::INTER_NEAREST);
    const cv::Mat image = ReadImage(photo.image_path);
    cv::resize(image, p.image, out, 0, 0, cv::INTER_AREA);
    p.camera = scene.CameraOf(photo);
    p.cam_from_world = photo.cam_from_world;
    result.prior_log_exposure.push_back(PriorLogExposure(photo));
  }
  result.depth_seconds = Since(t0);

  t0 = std::chrono::steady_clock::now();
  const std::vector<MultiViewSample> samples =
      GatherMultiViewSamples(photos, scene.points.positions, options.gather);
  result.samples = static_cast<int>(samples.size());
  result.gather_seconds = Since(t0);
  t0 = std::chrono::steady_clock::now();
  result.calibration = CalibrateMultiView(samples, result.prior_log_exposure, options.solve);
  result.solve_seconds = Since(t0);
  spdlog::info(
      "radiometric calibration: {} samples from {} photos ({:.2f} s depth maps, {:.2f} s "
      "gathering, {:.2f} s solve), residual {:.4f}",
      result.samples, photos.size(), result.depth_seconds, result.gather_seconds,
      result.solve_seconds, result.calibration.stats.residual_rms);
  return result;
}

RadiometricCalibration ToWorkspaceCalibration(const Scene& scene,
                                              const CloudCalibrationResult& result) {
  RadiometricCalibration c;
  const MultiViewCalibration& m = result.calibration;
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    PhotoExposureCalibration e;
    e.exif_relative = scene.photos[i].exposure.Relative();
    e.relative = m.relative_exposure[i];
    e.calibrated = m.calibrated[i];
    c.photos[scene.photos[i].name] = e;
  }
  c.samples = m.stats.samples_used;
  c.residual_rms = m.stats.residual_rms;
  c.exponent_from_exif = m.stats.exponent_from_prior;
  return c;
}

}  // namespace hdribr::render
