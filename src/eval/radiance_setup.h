// The response and per-photo exposures that radiance evaluations render and re-expose with.
#pragma once

#include <optional>
#include <string>

#include "core/scene.h"
#include "gl/shader_library.h"
#include "hdr/response_curve.h"
#include "render/renderer.h"

namespace hdribr::eval {

class RadianceSetup {
 public:
  // `response` when given (the workspace's calib/, whose exposures `scene` already carries),
  // else a calibration from the point cloud made now (render/cloud_calibration.h), whose
  // exposures a copy of the scene carries. Needs a current GL 4.5 context; keeps a reference
  // to `scene`.
  RadianceSetup(const Scene& scene, const gl::ShaderLibrary& shaders,
                const std::optional<ResponseCurve>& response,
                const render::RendererOptions& renderer);
  RadianceSetup(const RadianceSetup&) = delete;
  RadianceSetup& operator=(const RadianceSetup&) = delete;

  // The scene to render (with the calibrated exposures).
  const Scene& scene() const { return calibrated_ ? *calibrated_ : original_; }
  const ResponseCurve& response() const { return response_; }
  const std::string& source() const { return source_; }  // where the response came from
  // `options` set to blend radiance with this response.
  render::RendererOptions RendererOptionsFor(render::RendererOptions options) const;
  // 8-bit image of rendered radiance (CV_32FC3 BGR) exposed at `relative_exposure`.
  cv::Mat Expose(const cv::Mat& radiance, double relative_exposure) const;

 private:
  const Scene& original_;
  std::optional<Scene> calibrated_;
  ResponseCurve response_;
  std::string source_;
};

}  // namespace hdribr::eval
