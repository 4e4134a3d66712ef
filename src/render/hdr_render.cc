#include "render/hdr_render.h"

#include <chrono>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "hdr/debevec.h"
#include "hdr/exposure_stack.h"

namespace hdribr::render {

std::string HdrModeName(HdrMode mode) {
  switch (mode) {
    case HdrMode::kPrecomputed:
      return "precomputed";
    case HdrMode::kOnTheFly:
      return "onthefly";
    case HdrMode::kDirect:
      return "direct";
  }
  return "?";
}

HdrMode ParseHdrMode(const std::string& name) {
  for (HdrMode m : AllHdrModes()) {
    if (HdrModeName(m) == name) return m;
  }
  throw UsageError("unknown HDR mode '" + name + "' (precomputed, onthefly, direct)");
}

std::vector<HdrMode> AllHdrModes() {
  return {HdrMode::kPrecomputed, HdrMode::kOnTheFly, HdrMode::kDirect};
}

struct HdrRenderer::Impl {
  HdrMode mode;
  ResponseCurve response;
  std::vector<std::vector<int>> series_photos;  // kOnTheFly
  std::vector<double> series_exposures;
  std::unique_ptr<Renderer> renderer;
  double output_scale = 1.0;  // kPrecomputed: 1 / the set's radiance_scale

  // kOnTheFly: every series rendered from its own photos, merged with eq. 7.
  // The series' renders are not filled: Render() fills the merge where none of them renders.
  HdrFrame MergeSeries(const Camera& camera, const Rigid3d& cam_from_world, RenderTarget& target) {
    ExposureStack stack;
    stack.times = series_exposures;
    const bool fill = renderer->blend_options().fill;
    renderer->blend_options().fill = false;
    for (const std::vector<int>& photos : series_photos) {
      renderer->SetActivePhotos(photos);
      renderer->Render(camera, cam_from_world, target);
      RenderImages r = Renderer::Read(target);
      cv::Mat bgr8;
      r.color.convertTo(bgr8, CV_8UC3, 255.0);
      stack.images.push_back(bgr8);
      stack.masks.push_back(r.valid);
    }
    renderer->SetAllPhotosActive();
    renderer->blend_options().fill = fill;
    HdrFrame frame;
    frame.radiance = MergeDebevec(stack, response, &frame.valid);
    return frame;
  }
};

HdrRenderer::HdrRenderer(const gl::ShaderLibrary& shaders, const Scene& scene, HdrMode mode,
                         const ResponseCurve& response, RendererOptions options,
                         const LoadedHdrPhotoSet* set)
    : impl_(std::make_unique<Impl>()) {
  impl_->mode = mode;
  impl_->response = response;
  if (!impl_->response.IsValid() && set) impl_->response = set->response;
  options.photo_images.clear();
  switch (mode) {
    case HdrMode::kPrecomputed:
      if (!set) throw UsageError("HDR mode 'precomputed' needs an HDR photo set (`hdribr hdr`)");
      options.blend.encoding = PhotoEncoding::kDisplay;
      options.photo_images = set->images;
      impl_->output_scale = 1.0 / set->index.radiance_scale;
      impl_->renderer = std::make_unique<Renderer>(shaders, set->scene, std::move(options));
      return;
    case HdrMode::kOnTheFly:
      if (!impl_->response.IsValid()) {
        throw UsageError("HDR mode 'onthefly' needs a valid response curve");
      }
      if (scene.series.size() < 2) {
        throw UsageError("HDR mode 'onthefly' needs at least two exposure series, the scene has " +
                         std::to_string(scene.series.size()));
      }
      for (const ExposureSeries& s : scene.series) {
        impl_->series_photos.push_back(s.photo_indices);
        impl_->series_exposures.push_back(s.relative_exposure);
      }
      options.blend.encoding = PhotoEncoding::kDisplay;
      impl_->renderer = std::make_unique<Renderer>(shaders, scene, std::move(options));
      return;
    case HdrMode::kDirect:
      if (!impl_->response.IsValid()) {
        throw UsageError("HDR mode 'direct' needs a valid response curve");
      }
      options.blend.encoding = PhotoEncoding::kRadiance;
      options.response = impl_->response;
      impl_->renderer = std::make_unique<Renderer>(shaders, scene, std::move(options));
      return;
  }
}

HdrRenderer::~HdrRenderer() = default;

HdrFrame ReadHdrFrame(const RenderTarget& target, double target_scale) {
  RenderImages r = Renderer::Read(target);
  HdrFrame frame;
  frame.radiance = r.color;
  frame.valid = r.valid;
  frame.filled = r.filled;
  cv::patchNaNs(frame.radiance, 0.0);
  // Nothing non-finite or negative leaves, and pixels neither valid nor filled are 0.
  cv::max(frame.radiance, 0.0, frame.radiance);
  cv::min(frame.radiance, 3.0e38, frame.radiance);
  if (target_scale != 1.0) frame.radiance *= 1.0 / target_scale;
  frame.radiance.setTo(cv::Scalar::all(0), (frame.valid | frame.filled) == 0);
  return frame;
}

HdrFrame HdrRenderer::Render(const Camera& camera, const Rigid3d& cam_from_world, int width,
                             int height) {
  const auto start = std::chrono::steady_clock::now();
  RenderTarget target = RenderTarget::Create(width, height);
  Render(camera, cam_from_world, target);
  HdrFrame frame = ReadHdrFrame(target, target_scale());
  frame.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return frame;
}

void HdrRenderer::Render(const Camera& camera, const Rigid3d& cam_from_world,
                         RenderTarget& target) {
  if (impl_->mode != HdrMode::kOnTheFly) {
    impl_->renderer->Render(camera, cam_from_world, target);
    return;
  }
  HdrFrame frame = impl_->MergeSeries(camera, cam_from_world, target);
  cv::patchNaNs(frame.radiance, 0.0);
  // Upload: RGB order, alpha = validity (the renderer's colour target layout).
  cv::Mat rgba;
  cv::cvtColor(frame.radiance, rgba, cv::COLOR_BGR2RGBA);
  for (int y = 0; y < rgba.rows; ++y) {
    const uint8_t* v = frame.valid.ptr<uint8_t>(y);
    cv::Vec4f* p = rgba.ptr<cv::Vec4f>(y);
    for (int x = 0; x < rgba.cols; ++x) {
      if (v[x]) {
        p[x][3] = 1.0f;
      } else {
        p[x] = cv::Vec4f(0, 0, 0, 0);
      }
    }
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(target.color.id(), 0, 0, 0, rgba.cols, rgba.rows, GL_RGBA, GL_FLOAT,
                      rgba.data);
  if (impl_->renderer->blend_options().fill) impl_->renderer->Fill(target);
}

HdrMode HdrRenderer::mode() const { return impl_->mode; }

double HdrRenderer::target_scale() const { return 1.0 / impl_->output_scale; }

ToneMappedFrame RenderToneMapped(HdrRenderer& renderer, TonemapPass& tonemap, const Camera& camera,
                                 const Rigid3d& cam_from_world, int width, int height,
                                 TonemapOptions options) {
  const auto start = std::chrono::steady_clock::now();
  const double scale = renderer.target_scale();
  if (options.fixed_log_average) {
    options.fixed_log_average = static_cast<float>(*options.fixed_log_average * scale);
  }
  RenderTarget target = RenderTarget::Create(width, height);
  renderer.Render(camera, cam_from_world, target);
  gl::Texture display = gl::Texture::Create2D(GL_RGBA8, width, height);
  ToneMappedFrame out;
  out.log_average = static_cast<float>(tonemap.Apply(target.color, options, display) / scale);
  cv::Mat rgba(height, width, CV_8UC4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(display.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(rgba.total() * 4), rgba.data);
  cv::cvtColor(rgba, out.display, cv::COLOR_RGBA2BGR);
  out.hdr = ReadHdrFrame(target, scale);
  out.hdr.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

Renderer& HdrRenderer::renderer() { return *impl_->renderer; }

}  // namespace hdribr::render
