#include "eval/radiance_setup.h"

#include <spdlog/spdlog.h>

#include "hdr/re_expose.h"
#include "render/cloud_calibration.h"

namespace hdribr::eval {

RadianceSetup::RadianceSetup(const Scene& scene, const gl::ShaderLibrary& shaders,
                             const std::optional<ResponseCurve>& response,
                             const render::RendererOptions& renderer)
    : original_(scene) {
  if (response) {
    response_ = *response;
    source_ = "the workspace's calib/ (hdribr calibrate)";
    return;
  }
  spdlog::info(
      "no calib/ in the workspace: calibrating from the point cloud (`hdribr calibrate` keeps "
      "the result)");
  render::CloudCalibrationOptions co;
  co.depth = renderer.depth;
  co.depth_cache_dir = renderer.depth_cache_dir;
  const render::CloudCalibrationResult c = render::CalibrateFromCloud(shaders, scene, co);
  calibrated_ = scene;
  for (size_t i = 0; i < calibrated_->photos.size(); ++i) {
    calibrated_->photos[i].calibrated_exposure = c.calibration.relative_exposure[i];
  }
  response_ = c.calibration.response;
  source_ = "calibrated from the point cloud";
}

render::RendererOptions RadianceSetup::RendererOptionsFor(render::RendererOptions options) const {
  options.response = response_;
  options.blend.encoding = render::PhotoEncoding::kRadiance;
  return options;
}

cv::Mat RadianceSetup::Expose(const cv::Mat& radiance, double relative_exposure) const {
  return ExposeThroughResponse(radiance, response_, relative_exposure);
}

}  // namespace hdribr::eval
