// The viewer's pictures: owns the renderers (LDR, HDR, the loaded HDR photo set), the passes and
// the GL targets, and re-renders only what changed. The blended radiance stays in an RGBA32F
// target; tone-map changes re-run only the tone-map pass, camera or blend changes re-render.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "core/camera.h"
#include "core/rigid3.h"
#include "core/scene.h"
#include "gl/objects.h"
#include "gl/shader_library.h"
#include "render/hdr_photo_set.h"
#include "render/hdr_render.h"
#include "render/point_color_pass.h"
#include "render/renderer.h"
#include "render/tonemap_pass.h"
#include "viewer/false_colour_pass.h"
#include "viewer/frustum_pass.h"
#include "viewer/view_state.h"

namespace hdribr::viewer {

// Costs of the last re-render and the last tone map, for the panel (milliseconds).
struct FrameStats {
  double render_wall_ms = 0;
  render::RenderTimes render_gpu;
  double tonemap_wall_ms = 0;
  double tonemap_gpu_ms = 0;
  int candidates = 0;        // photos the last re-render blended from
  int active = 0;            // active photos they were chosen among
  double candidates_ms = 0;  // CPU time of their choice
  float last_la = 1;         // the L_a of the last tone map (radiance target units)
};

// Clears the window's framebuffer to the viewer's background (fb_* in pixels).
void ClearWindow(int fb_width, int fb_height);

// Writes the window's back buffer (picture + UI, fb_* in pixels) to a PNG and prints its path.
void SaveWindow(const std::filesystem::path& png, int fb_width, int fb_height);

class FrameRenderer {
 public:
  // Needs a current GL 4.5 context; `scene` and `camera` (the view's intrinsics) must outlive
  // it. max_photo_size: longest photo side on the GPU (0 = full size); depth_cache_dir: the
  // renderers' cache of the photos' depth maps (empty = none).
  FrameRenderer(const Scene& scene, const Camera& camera, std::filesystem::path workspace,
                int max_photo_size, std::filesystem::path depth_cache_dir);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // Consumes the state's change requests; (re)loads the renderers when the settings changed
  // (printing what it loads) and re-applies the blend options.
  void Load(ViewState& state);
  // Re-renders the radiance at `pose` when the pose, the size or the blend changed, then the
  // display when it or the tone mapping changed. Sizes in pixels; 0 = nothing to draw.
  void Render(const ViewState& state, const Rigid3d& pose, int width, int height);
  // The display (with the frustums over it when asked, the candidate photos' in their own
  // colour) into the window's framebuffer.
  void Blit(int fb_width, int fb_height, bool frustums, int current_photo);
  // Writes the display (.png, tone-mapped) and the linear radiance (.exr) next to it; returns
  // the PNG's path.
  std::filesystem::path Screenshot(const std::filesystem::path& out);
  // Forces the next Render to re-run the tone map.
  void MarkDisplayDirty() { display_dirty_ = true; }

  bool has_display() const { return !display_.empty(); }
  int width() const { return target_.width(); }
  int height() const { return target_.height(); }
  const FrameStats& stats() const { return stats_; }
  bool point_colours_known() const { return point_colours_known_; }
  // True when the loaded source has a camera response (ViewState::camera_curve can be shown).
  bool has_camera_curve() const { return hdr_ && tonemap_pass_.has_response(); }
  size_t photo_count() const;  // photos the current renderer blends from

 private:
  render::Renderer& BaseRenderer() { return hdr_ ? hdr_->renderer() : *ldr_; }
  const render::Renderer& BaseRenderer() const { return hdr_ ? hdr_->renderer() : *ldr_; }
  void RenderSplats(const Camera& cam, const Rigid3d& pose);
  void ToneMap(const ViewState& state);

  const Scene& scene_;
  const Camera& camera_;
  std::filesystem::path workspace_;
  int max_photo_size_;
  std::filesystem::path depth_cache_dir_;
  gl::ShaderLibrary shaders_;
  std::unique_ptr<render::Renderer> ldr_;
  std::unique_ptr<render::HdrRenderer> hdr_;
  std::unique_ptr<render::LoadedHdrPhotoSet> set_;
  double median_exposure_;  // relative exposure of EV 0 through the camera's response
  render::TonemapPass tonemap_pass_;
  FalseColourPass false_colour_;
  FrustumPass frustum_pass_;
  render::PointColorPass point_pass_;
  bool point_colours_known_ = true;  // false: the cloud has no colours (grey splats)
  render::RenderTarget target_;
  gl::Texture display_;  // what the screenshot saves: the picture without overlays
  gl::Framebuffer display_fb_;
  gl::Texture composite_;  // display_ + the frustums, when they are shown
  gl::Framebuffer composite_fb_;
  gl::Texture splats_;  // RGBA32F colour-per-point splats (a = covered), tone-mapped like final
  Settings loaded_settings_;
  bool loaded_ = false;
  bool options_dirty_ = false;  // display mode changed: blend mode to update
  // Dirty flags: the radiance target (camera / blend) and the display (tone mapping).
  bool render_dirty_ = true, display_dirty_ = true;
  Rigid3d rendered_pose_;
  FrameStats stats_;
};

}  // namespace hdribr::viewer
