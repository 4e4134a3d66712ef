#include "viewer/frame_renderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

#include "io/image.h"
#include "io/radiometric_calibration.h"
#include "render/render_output.h"

namespace hdribr::viewer {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double NowS() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }

}  // namespace

void ClearWindow(int fb_width, int fb_height) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fb_width, fb_height);
  glClearColor(0.08f, 0.08f, 0.08f, 1);
  glClear(GL_COLOR_BUFFER_BIT);
}

void SaveWindow(const std::filesystem::path& png, int fb_width, int fb_height) {
  cv::Mat rgb(fb_height, fb_width, CV_8UC3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, fb_width, fb_height, GL_RGB, GL_UNSIGNED_BYTE, rgb.ptr());
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  cv::flip(bgr, bgr, 0);  // GL rows start at the bottom
  WriteImage(png, bgr);
  std::printf("window screenshot: %s\n", png.c_str());
}

FrameRenderer::FrameRenderer(const Scene& scene, const Camera& camera,
                             std::filesystem::path workspace,
                             const render::RendererOptions& options)
    : scene_(scene),
      camera_(camera),
      workspace_(std::move(workspace)),
      median_exposure_(scene.MedianRelativeExposure()),
      tonemap_pass_(shaders_),
      false_colour_(shaders_),
      frustum_pass_(shaders_),
      point_pass_(shaders_) {
  renderer_options_.max_photo_size = options.max_photo_size;
  renderer_options_.depth_cache_dir = options.depth_cache_dir;
  renderer_options_.gpu_memory_mb = options.gpu_memory_mb;
  renderer_options_.depth.silhouette_trim = options.depth.silhouette_trim;
  renderer_options_.wait_for_photos = false;
  frustum_pass_.SetLines(MakeFrustumLines(scene_, 0.15 * scene_.scene_scale));
  // The cloud's sRGB colours (BGR, 0..1); grey when it has none.
  const PointCloud& cloud = scene_.points;
  point_colours_known_ = cloud.HasColors();
  std::vector<Eigen::Vector3f> bgr(cloud.size(), Eigen::Vector3f::Constant(0.5f));
  for (size_t i = 0; point_colours_known_ && i < cloud.size(); ++i) {
    const auto& c = cloud.colors[i];
    bgr[i] = Eigen::Vector3f(c[2], c[1], c[0]) / 255.0f;
  }
  point_pass_.SetPoints(cloud, bgr);
}

FrameRenderer::~FrameRenderer() = default;

size_t FrameRenderer::photo_count() const { return BaseRenderer().scene().photos.size(); }

void FrameRenderer::Load(ViewState& state) {
  if (state.display_changed) options_dirty_ = true;  // the blend mode may change
  if (state.tone_changed) display_dirty_ = true;
  state.display_changed = state.tone_changed = false;
  const Settings& s = state.settings;
  if (loaded_ && s == loaded_settings_ && !options_dirty_) return;
  const bool reload = !loaded_ || s.source != loaded_settings_.source;
  options_dirty_ = false;
  if (reload) {
    hdr_.reset();
    ldr_.reset();
    const render::RendererOptions& ro = renderer_options_;
    const auto t0 = Clock::now();
    std::printf("loading %zu photos, computing their depth maps (%s)...\n", scene_.photos.size(),
                HdrSourceName(s.source).c_str());
    std::fflush(stdout);
    if (s.source == HdrSource::kLdr) {
      ldr_ = std::make_unique<render::Renderer>(shaders_, scene_, ro);
    } else {
      // The workspace's calibration (hdribr calibrate) when there is one, else the set's.
      const std::filesystem::path calibrated = workspace_ / kCalibFolder / kCalibResponse;
      const bool own = s.source != HdrSource::kPrecomputed && std::filesystem::exists(calibrated);
      ResponseCurve response;
      if (own) {
        response = ReadResponseCurve(calibrated);
      } else {
        if (!set_) {
          set_ = std::make_unique<render::LoadedHdrPhotoSet>(
              render::LoadHdrPhotoSet(scene_, workspace_ / render::kHdrSetFolder));
        }
        response = set_->response;
      }
      hdr_ = std::make_unique<render::HdrRenderer>(shaders_, scene_, HdrModeOf(s.source), response,
                                                   ro, own ? nullptr : set_.get());
      tonemap_pass_.SetResponse(response);
    }
    std::printf("loaded in %.1f s, GPU memory %.1f MiB\n",
                std::chrono::duration<double>(Clock::now() - t0).count(),
                BaseRenderer().gpu_bytes() / 1048576.0);
  }
  render::Renderer& r = BaseRenderer();
  r.blend_options().weights = s.weights;
  r.blend_options().k_best = s.k_best;
  r.blend_options().lambda = s.lambda;
  r.blend_options().occlusion_tolerance = s.tolerance;
  r.blend_options().background = s.background;
  r.blend_options().fill = s.fill;
  r.blend_options().sampling = s.sampling;
  r.blend_options().outlier_scale = s.outlier_scale;
  r.blend_options().refine_depth = s.refine_depth;
  r.SetMaxCandidates(s.max_candidates);
  r.blend_options().mode = state.display == DisplayMode::kNearestPhoto
                               ? render::BlendMode::kNearestPhoto
                               : render::BlendMode::kBlend;
  r.depth_pass().options().mode = s.depth_mode;
  if (ldr_) {
    if (s.series >= 0) {
      ldr_->SetActivePhotos(scene_.series[static_cast<size_t>(s.series)].photo_indices);
    } else {
      ldr_->SetAllPhotosActive();
    }
  }
  loaded_settings_ = s;
  schedule_.SetSearchStage(s.refine_depth > 0.0f);
  loaded_ = true;
  render_dirty_ = true;
  tonemap_pass_.ResetHistory();
}

FrameRenderer::Surface FrameRenderer::Surface::Create(int width, int height) {
  Surface s;
  s.target = render::RenderTarget::Create(width, height);
  s.display = gl::Texture::Create2D(GL_RGBA8, width, height);
  s.display_fb = gl::Framebuffer::Create();
  s.display_fb.AttachColor(0, s.display);
  s.composite = gl::Texture::Create2D(GL_RGBA8, width, height);
  s.composite_fb = gl::Framebuffer::Create();
  s.composite_fb.AttachColor(0, s.composite);
  s.splats = gl::Texture::Create2D(GL_RGBA32F, width, height);
  return s;
}

void FrameRenderer::Render(const ViewState& state, const Rigid3d& pose, int width, int height) {
  if (width <= 0 || height <= 0) return;  // minimised
  if (window_width_ != width || window_height_ != height) {
    surfaces_ = {};
    window_width_ = width;
    window_height_ = height;
    level_ = -1;
    schedule_.ResetCosts();
    render_dirty_ = true;
  }
  if (schedule_.budget_ms() != state.frame_budget_ms) schedule_.SetBudget(state.frame_budget_ms);
  const bool changed = render_dirty_ || !pose.rotation.isApprox(rendered_pose_.rotation, 1e-12) ||
                       !pose.translation.isApprox(rendered_pose_.translation, 1e-12);
  const int level = schedule_.Next(changed, NowS());
  double frame_ms = 0;
  bool measured = level >= 0;
  if (level >= 0) {
    const auto t0 = Clock::now();
    Surface& surface = surfaces_[static_cast<size_t>(level)];
    if (surface.target.width() == 0) {
      surface = Surface::Create(LevelSize(width, level), LevelSize(height, level));
      measured = false;  // the first frame of a size pays for its allocation
    }
    level_ = level;
    const int w = surface.target.width(), h = surface.target.height();
    // A reduced frame also blends fewer candidate photos and draws a coarser level of the
    // cloud; the depth search runs in the frames the schedule gives it.
    const int cap = loaded_settings_.max_candidates;
    const bool full = level == ProgressiveSchedule::kFull;
    render::Renderer& r = BaseRenderer();
    r.SetMaxCandidates(full || (cap > 0 && cap < kMotionMaxCandidates) ? cap
                                                                       : kMotionMaxCandidates);
    r.blend_options().refine_depth = schedule_.search() ? loaded_settings_.refine_depth : 0.0f;
    r.SetPointDetail(ProgressiveSchedule::kScales[static_cast<size_t>(level)]);
    const Camera cam = camera_.Scaled(w, h);
    if (hdr_) {
      hdr_->Render(cam, pose, surface.target);
    } else {
      ldr_->Render(cam, pose, surface.target);
    }
    if (state.display == DisplayMode::kPointColours) RenderSplats(cam, pose);
    glFinish();
    stats_.render_wall_ms = MsSince(t0);
    frame_ms = stats_.render_wall_ms;
    stats_.render_gpu = r.last_times();
    const render::FrameCandidates& c = r.last_candidates();
    stats_.candidates = static_cast<int>(c.photos.size());
    stats_.active = c.active;
    stats_.candidates_ms = c.select_ms;
    stats_.scale = static_cast<double>(w) / width;
    stats_.residency = r.residency();
    frustum_pass_.SetCandidates(c.photos);
    rendered_pose_ = pose;
    render_dirty_ = false;
    display_dirty_ = true;
  }
  stats_.budget_ms = schedule_.budget_ms();
  if (display_dirty_ && level_ >= 0) {
    const auto t0 = Clock::now();
    ToneMap(state);
    glFinish();
    stats_.tonemap_wall_ms = MsSince(t0);
    frame_ms += stats_.tonemap_wall_ms;
    display_dirty_ = false;
  }
  if (measured) schedule_.Record(level, frame_ms);
  // A full-quality picture drawn while photos were still loading (from their coarse copies), or
  // whose photos the cache moved to finer slots since (the levels the blend sampled), is drawn
  // again once they are resident.
  if (level_ == ProgressiveSchedule::kFull) {
    const int loading = BaseRenderer().PollPhotoLoads();
    if (loading > 0 || stats_.residency.pending > 0) redraw_when_loaded_ = true;
    if (loading == 0 && redraw_when_loaded_) {
      redraw_when_loaded_ = false;
      schedule_.MarkStale();
    }
  }
}

// The current surface's radiance target (or its splats, or a false-colour map) into its display.
void FrameRenderer::ToneMap(const ViewState& state) {
  Surface& surface = Current();
  const int photos = static_cast<int>(scene_.photos.size());
  switch (state.display) {
    case DisplayMode::kFinal:
    case DisplayMode::kNearestPhoto: {
      render::TonemapOptions o = state.tonemap;
      o.exposure = std::exp2(state.exposure_ev);
      if (!state.auto_la) o.fixed_log_average = state.fixed_la;
      if (state.camera_curve && has_camera_curve()) {
        o.camera_curve = true;  // relative exposure per target unit
        o.exposure = static_cast<float>(median_exposure_ * o.exposure / hdr_->target_scale());
      }
      stats_.last_la = tonemap_pass_.Apply(surface.target.color, o, surface.display);
      stats_.tonemap_gpu_ms = tonemap_pass_.last_ms();
      break;
    }
    case DisplayMode::kPointColours: {
      // The cloud's colours are display values (sRGB 8-bit): exposure only, no curve.
      render::TonemapOptions o;
      o.enabled = false;
      o.exposure = std::exp2(state.exposure_ev);
      o.gamma = 1.0f;
      tonemap_pass_.Apply(surface.splats, o, surface.display);
      stats_.tonemap_gpu_ms = tonemap_pass_.last_ms();
      break;
    }
    case DisplayMode::kDepth:
    case DisplayMode::kNormals:
    case DisplayMode::kCount: {
      const FalseColourMap map = state.display == DisplayMode::kDepth     ? FalseColourMap::kDepth
                                 : state.display == DisplayMode::kNormals ? FalseColourMap::kNormals
                                                                          : FalseColourMap::kCount;
      false_colour_.Apply(map, surface.target, photos, surface.display);
      stats_.tonemap_gpu_ms = 0;
      break;
    }
    case DisplayMode::kClasses:
      if (surface.target.depth.classes.empty()) {  // a depth pass without classes: none shown
        glClearTexImage(surface.display.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
      } else {
        false_colour_.Apply(FalseColourMap::kClasses, surface.target, photos, surface.display,
                            &surface.target.depth.classes);
      }
      stats_.tonemap_gpu_ms = 0;
      break;
  }
}

// Colour-per-point splats (the paper's Fig. 8 baseline) into the current surface's splats, for
// the tone-map pass.
void FrameRenderer::RenderSplats(const Camera& cam, const Rigid3d& pose) {
  gl::Texture& splats = Current().splats;
  const render::PointColorImages im =
      point_pass_.Render(cam, pose, splats.width(), splats.height());
  cv::Mat rgba;
  cv::cvtColor(im.color, rgba, cv::COLOR_BGR2RGBA);
  rgba.setTo(cv::Scalar(0, 0, 0, 0), im.valid == 0);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(splats.id(), 0, 0, 0, rgba.cols, rgba.rows, GL_RGBA, GL_FLOAT, rgba.ptr());
}

void FrameRenderer::Blit(int fb_width, int fb_height, bool frustums, int current_photo) {
  ClearWindow(fb_width, fb_height);
  if (level_ < 0) return;
  Surface& s = Current();
  const int w = s.display.width(), h = s.display.height();
  GLuint source = s.display_fb.id();
  if (frustums) {
    // Frustums over a copy, so that the display (the screenshot) stays the bare picture.
    glCopyImageSubData(s.display.id(), GL_TEXTURE_2D, 0, 0, 0, 0, s.composite.id(), GL_TEXTURE_2D,
                       0, 0, 0, 0, w, h, 1);
    frustum_pass_.Draw(camera_.Scaled(w, h), rendered_pose_, s.target.depth.depth, s.composite_fb,
                       current_photo);
    source = s.composite_fb.id();
  }
  // The display texture's row 0 is the image's top row; the window's row 0 is its bottom. A
  // reduced picture is magnified bilinearly.
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fb_width, fb_height);
  glBlitNamedFramebuffer(source, 0, 0, 0, w, h, 0, fb_height, fb_width, 0, GL_COLOR_BUFFER_BIT,
                         w == fb_width && h == fb_height ? GL_NEAREST : GL_LINEAR);
}

std::filesystem::path FrameRenderer::Screenshot(const std::filesystem::path& out) {
  const bool exr = LowerExtension(out) == ".exr";
  std::filesystem::path png = exr ? std::filesystem::path(out).replace_extension(".png") : out;
  std::filesystem::path exr_path = std::filesystem::path(out).replace_extension(".exr");
  const Surface& surface = Current();
  cv::Mat rgba(surface.display.height(), surface.display.width(), CV_8UC4);
  glGetTextureImage(surface.display.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(rgba.total() * rgba.elemSize()), rgba.ptr());
  cv::Mat bgra;
  cv::cvtColor(rgba, bgra, cv::COLOR_RGBA2BGRA);
  WriteImage(png, bgra);
  const render::RenderImages im = render::Renderer::Read(surface.target);
  cv::Mat linear = im.color;
  if (hdr_ && hdr_->target_scale() != 1.0) linear = im.color / hdr_->target_scale();
  render::WriteRgbaExr(exr_path, linear, im.shown());
  std::printf("screenshot: %s (tone-mapped), %s (linear)\n", png.c_str(), exr_path.c_str());
  return png;
}

}  // namespace hdribr::viewer
