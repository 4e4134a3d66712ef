// The viewer's pictures: owns the renderers (LDR, HDR, the loaded HDR photo set), the passes and
// the GL targets, and re-renders only what changed. The blended radiance stays in an RGBA32F
// target; tone-map changes re-run only the tone-map pass, camera or blend changes re-render.
#pragma once

#include <array>
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
#include "viewer/progressive.h"
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
  double scale = 1;          // rendered size / window size of the picture on screen (per axis)
  double budget_ms = 0;      // frame-time budget while moving (0 = every frame full quality)
  render::PhotoResidency residency;  // the photos' GPU memory after the last re-render
};

// Clears the window's framebuffer to the viewer's background (fb_* in pixels).
void ClearWindow(int fb_width, int fb_height);

// Writes the window's back buffer (picture + UI, fb_* in pixels) to a PNG and prints its path.
void SaveWindow(const std::filesystem::path& png, int fb_width, int fb_height);

class FrameRenderer {
 public:
  // Needs a current GL 4.5 context; `scene` and `camera` (the view's intrinsics) must outlive
  // it. From `options`: max_photo_size, depth_cache_dir, gpu_memory_mb and the depth pass's
  // silhouette_trim; photos beyond the
  // budget are loaded without waiting (coarse copies meanwhile), and the full-quality picture
  // is rendered again once they have arrived.
  FrameRenderer(const Scene& scene, const Camera& camera, std::filesystem::path workspace,
                const render::RendererOptions& options);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // Consumes the state's change requests; (re)loads the renderers when the settings changed
  // (printing what it loads) and re-applies the blend options.
  void Load(ViewState& state);
  // Re-renders the radiance at `pose` when the pose, the size or the blend changed, then the
  // display when it or the tone mapping changed. With a frame budget (state.frame_budget_ms),
  // a change renders a reduced size that fits it and the full size follows once the view is
  // still, then the depth search (ProgressiveSchedule). Sizes in pixels; 0 = nothing to draw.
  void Render(const ViewState& state, const Rigid3d& pose, int width, int height);
  // True when the picture on screen is at full quality.
  bool full_quality() const { return level_ == ProgressiveSchedule::kFull; }
  // True when it is also final: rendered with every photo it needed resident at the level it
  // samples, and with the photo-consistent depth search when that is on.
  bool settled() const {
    return schedule_.final() && stats_.residency.pending == 0 && !redraw_when_loaded_;
  }
  // The display (with the frustums over it when asked, the candidate photos' in their own
  // colour) into the window's framebuffer.
  void Blit(int fb_width, int fb_height, bool frustums, int current_photo);
  // Writes the display (.png, tone-mapped) and the linear radiance (.exr) next to it; returns
  // the PNG's path.
  std::filesystem::path Screenshot(const std::filesystem::path& out);
  // Forces the next Render to re-run the tone map.
  void MarkDisplayDirty() { display_dirty_ = true; }

  bool has_display() const { return level_ >= 0; }
  // The window size the pictures are rendered for.
  int width() const { return window_width_; }
  int height() const { return window_height_; }
  const FrameStats& stats() const { return stats_; }
  bool point_colours_known() const { return point_colours_known_; }
  // True when the loaded source has a camera response (ViewState::camera_curve can be shown).
  bool has_camera_curve() const { return hdr_ && tonemap_pass_.has_response(); }
  size_t photo_count() const;  // photos the current renderer blends from

 private:
  render::Renderer& BaseRenderer() { return hdr_ ? hdr_->renderer() : *ldr_; }
  const render::Renderer& BaseRenderer() const { return hdr_ ? hdr_->renderer() : *ldr_; }
  // The GL images of one rendered size: the radiance target, the display (the picture without
  // overlays, what the screenshot saves), the display with the frustums, the splats (RGBA32F
  // colour-per-point, a = covered, tone-mapped like the final picture).
  struct Surface {
    render::RenderTarget target;
    gl::Texture display;
    gl::Framebuffer display_fb;
    gl::Texture composite;
    gl::Framebuffer composite_fb;
    gl::Texture splats;
    static Surface Create(int width, int height);
  };
  Surface& Current() { return surfaces_[static_cast<size_t>(level_)]; }
  void RenderSplats(const Camera& cam, const Rigid3d& pose);
  void ToneMap(const ViewState& state);

  const Scene& scene_;
  const Camera& camera_;
  std::filesystem::path workspace_;
  render::RendererOptions renderer_options_;  // what the renderers are loaded with
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
  // One surface per level of the schedule, made when first rendered, for the window's size.
  std::array<Surface, ProgressiveSchedule::kScales.size()> surfaces_;
  int window_width_ = 0, window_height_ = 0;
  int level_ = -1;  // the level of the picture on screen
  ProgressiveSchedule schedule_;
  bool redraw_when_loaded_ = false;  // the full-quality picture waits for photo loads
  Settings loaded_settings_;
  bool loaded_ = false;
  bool options_dirty_ = false;  // display mode changed: blend mode to update
  // Dirty flags: the radiance target (camera / blend) and the display (tone mapping).
  bool render_dirty_ = true, display_dirty_ = true;
  Rigid3d rendered_pose_;
  FrameStats stats_;
};

}  // namespace hdribr::viewer
