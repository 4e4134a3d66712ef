// The three ways to render an HDR novel view, behind one call:
//  1. precomputed: blend the workspace's HDR photo set (LEC19 sec. 5, the paper's default);
//  2. on the fly: render every exposure series from its own photos, merge per frame with
//     Debevec-Malik (LEC19 eq. 7; M renders per frame);
//  3. direct: blend linearised photos of all series in one pass (PhotoEncoding::kRadiance).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/rigid3.h"
#include "core/scene.h"
#include "gl/shader_library.h"
#include "hdr/response_curve.h"
#include "render/hdr_photo_set.h"
#include "render/renderer.h"
#include "render/tonemap_pass.h"

namespace hdribr::render {

enum class HdrMode { kPrecomputed, kOnTheFly, kDirect };

// "precomputed", "onthefly", "direct"; ParseHdrMode throws UsageError for anything else.
std::string HdrModeName(HdrMode mode);
HdrMode ParseHdrMode(const std::string& name);
std::vector<HdrMode> AllHdrModes();

// One HDR frame read back to the CPU.
struct HdrFrame {
  cv::Mat radiance;  // CV_32FC3 BGR linear radiance (merge units: exp(g) per relative exposure)
  cv::Mat valid;     // CV_8UC1, 255 = rendered from photos
  cv::Mat filled;    // CV_8UC1, 255 = the fill's (BlendOptions::fill); radiance is 0 where
                     // neither; never NaN/Inf
  double ms = 0;     // wall time of the frame, milliseconds (renders + merge + read-back)

  cv::Mat shown() const { return valid | filled; }  // 255 where radiance holds a value
};

// A render target read back as an HDR frame in radiance units (its colour / target_scale).
HdrFrame ReadHdrFrame(const RenderTarget& target, double target_scale);

class HdrRenderer {
 public:
  // Needs a current GL 4.5 context. `scene` is the workspace scene (all series). kPrecomputed
  // needs `set` (LoadHdrPhotoSet); kOnTheFly and kDirect need `response` (the set's response
  // when `set` is given and `response` is not valid). Throws UsageError when a requirement is
  // missing or the scene has a single series (kOnTheFly).
  HdrRenderer(const gl::ShaderLibrary& shaders, const Scene& scene, HdrMode mode,
              const ResponseCurve& response, RendererOptions options = {},
              const LoadedHdrPhotoSet* set = nullptr);
  ~HdrRenderer();
  HdrRenderer(const HdrRenderer&) = delete;
  HdrRenderer& operator=(const HdrRenderer&) = delete;

  // Renders and reads back a width x height frame.
  HdrFrame Render(const Camera& camera, const Rigid3d& cam_from_world, int width, int height);
  // Renders into `target` (colour rgb = radiance, a as Renderer::Render), for the tone-map pass
  // and the viewer.
  // kPrecomputed leaves the set's stored units there (radiance x radiance_scale).
  void Render(const Camera& camera, const Rigid3d& cam_from_world, RenderTarget& target);

  HdrMode mode() const;
  // Units of Render(target)'s colour per radiance unit (the set's radiance_scale in
  // kPrecomputed, else 1).
  double target_scale() const;
  Renderer& renderer();  // the underlying renderer (the set's scene in kPrecomputed)

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One view rendered in HDR and tone-mapped on the GPU (TonemapPass, Reinhard eqs. 8-12).
struct ToneMappedFrame {
  HdrFrame hdr;           // linear radiance + validity (read back)
  cv::Mat display;        // CV_8UC3 BGR tone-mapped image, black where invalid
  float log_average = 1;  // L_a used, in radiance units
};
// A fixed L_a in `options` is in radiance units (scaled to the target's units here).
ToneMappedFrame RenderToneMapped(HdrRenderer& renderer, TonemapPass& tonemap, const Camera& camera,
                                 const Rigid3d& cam_from_world, int width, int height,
                                 TonemapOptions options);

}  // namespace hdribr::render
