// Reinhard et al. 2002 global tone mapping on the GPU (LEC19 sec. 5, equations 8-12), with the
// log-average luminance computed by a GPU reduction. Agrees with hdr/tonemap.h (the CPU
// reference) within 1e-3.
#pragma once

#include <memory>
#include <optional>

#include "gl/objects.h"
#include "gl/shader_library.h"
#include "hdr/response_curve.h"

namespace hdribr::render {

struct TonemapOptions {
  bool enabled = true;    // false: display = clamp(exposure * C)^(1/gamma), no Reinhard curve
  float key = 0.18f;      // eq. 10
  float exposure = 1.0f;  // linear multiplier (2^EV) before gamma, eq. 12
  float gamma = 2.2f;     // eq. 12
  float epsilon = 1e-6f;  // inside the log of the log-average
  std::optional<float> fixed_log_average;  // use this L_a instead of the GPU reduction
  // Temporal smoothing of L_a across frames: L_a = mix(previous, current, 1 - smoothing);
  // 0 = none (offline renders), ~0.9 in the viewer against flicker.
  float smoothing = 0.0f;
  // The camera's response (TonemapPass::SetResponse) at `exposure` (relative exposure per
  // radiance unit) instead of Reinhard: the picture that camera would take; key, gamma and L_a
  // unused.
  bool camera_curve = false;
};

class TonemapPass {
 public:
  // Needs a current GL 4.5 context.
  explicit TonemapPass(const gl::ShaderLibrary& shaders);
  ~TonemapPass();
  TonemapPass(const TonemapPass&) = delete;
  TonemapPass& operator=(const TonemapPass&) = delete;

  // Log-average luminance exp(mean(log(eps + L))) over pixels with alpha > 0 of an RGBA32F
  // texture (the renderer's colour target: rgb linear, a = valid); 1 when none is valid.
  float LogAverage(const gl::Texture& hdr, float epsilon = 1e-6f);

  // Tone-maps `hdr` (RGBA32F) into `display` (RGBA8, or RGBA16F/RGBA32F for exact comparisons;
  // same size; invalid pixels get alpha 0 and colour 0). Returns the L_a used.
  float Apply(const gl::Texture& hdr, const TonemapOptions& options, gl::Texture& display);

  // The response of TonemapOptions::camera_curve. Throws UsageError for an invalid curve.
  void SetResponse(const ResponseCurve& response);
  bool has_response() const;

  // Forgets the smoothed L_a (next Apply starts afresh).
  void ResetHistory();
  // GPU time of the last Apply (reduction + mapping), milliseconds.
  double last_ms() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hdribr::render
