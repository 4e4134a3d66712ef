// The image-based renderer (Lechelek et al. 2019, sec. 4): depth pass of the new view, then
// the blend pass over the photos on the GPU. This is the API the CLI, eval, HDR and the viewer
// share; the passes themselves live in depth_pass.h, blend_pass.h, photo_textures.h.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/rigid3.h"
#include "core/scene.h"
#include "gl/objects.h"
#include "gl/shader_library.h"
#include "hdr/response_curve.h"
#include "render/blend_options.h"
#include "render/depth_pass.h"
#include "render/photo_cache.h"

namespace hdribr::render {

// RendererOptions::max_candidates by default: measured to cost no quality
// (docs/decisions/0010).
inline constexpr int kDefaultMaxCandidates = 16;

struct RendererOptions {
  DepthPassOptions depth;
  BlendOptions blend;
  int max_photo_size = 0;          // longest side of photos on the GPU; 0 = full size
  double photo_depth_scale = 1.0;  // size of the per-photo depth maps relative to the photos
  // Folder caching the photos' depth maps across runs (io/depth_map_cache.h); empty = none.
  std::filesystem::path depth_cache_dir;
  // Most candidate photos per frame (core/photo_candidates.h): each Render() blends only the
  // active photos that can matter for its view, at most this many; 0 = every active photo.
  int max_candidates = kDefaultMaxCandidates;
  // Photo pixels to use instead of the files on disk (an HDR photo set, CV_32FC3 BGR, one per
  // scene photo in scene order); empty = read scene.photos[i].image_path.
  std::vector<cv::Mat> photo_images;
  // Needed by PhotoEncoding::kRadiance.
  std::optional<ResponseCurve> response;
  // The photos' depth maps to use instead of the depth pass's (CV_32FC1 camera z, 0 = none,
  // one per scene photo in scene order): a perfect-depth reference; empty = the depth pass.
  std::vector<cv::Mat> photo_depths;
  // GPU memory budget of the photo textures and depth maps, MiB (render/photo_cache.h): when
  // everything fits, every photo stays resident; otherwise the photos go through a cache
  // (coarse copies of all, full size for the frames' candidates). 0 = from the device
  // (GpuBudgetBytes), kDefaultGpuMemoryMb where it reports nothing.
  double gpu_memory_mb = 0;
  // With a cache: each Render() waits until its candidate photos are resident at full size
  // (offline renders, never coarse); false renders at once with the coarse copies of the
  // photos still loading (interactive views).
  bool wait_for_photos = true;
};

// The view's depth given instead of the depth pass's, both of the target's size.
struct GivenDepth {
  cv::Mat depth;   // CV_32FC1 camera z, 0 = none
  cv::Mat normal;  // CV_32FC3 camera-space unit normal (x, y, z)
};

// Per-frame GPU timings in milliseconds (GL timestamp queries).
struct RenderTimes {
  double depth_ms = 0;
  double blend_ms = 0;
  double fill_ms = 0;  // FillPass (0 with BlendOptions::fill off)
};

// The photos the newest Render() blended from.
struct FrameCandidates {
  std::vector<int> photos;  // indices into scene.photos, in the order of the active photos
  int active = 0;           // active photos they were chosen among
  double select_ms = 0;     // CPU time of the choice (0 without a cap)
};

// CPU read-back of one rendered view. Rows top to bottom; colours BGR like the rest of the code.
struct RenderImages {
  cv::Mat color;   // CV_32FC3, blended value (see PhotoEncoding), or the fill's where filled; 0
                   // where neither; never NaN
  cv::Mat valid;   // CV_8UC1, 255 where depth is valid and at least one photo contributed
  cv::Mat filled;  // CV_8UC1, 255 where the colour is the fill's (BlendOptions::fill)
  cv::Mat depth;   // CV_32FC1 camera z, 0 = no depth
  cv::Mat normal;  // CV_32FC3 camera-space normal (x, y, z)
  cv::Mat count;   // CV_32FC1 number of contributing photos
  cv::Mat weight;  // CV_32FC1 normalised weight of options.blend.debug_photo (0 when none)

  cv::Mat shown() const { return valid | filled; }  // 255 where the colour holds a value
};

// GPU outputs of a frame, reused across frames of the same size.
struct RenderTarget {
  DepthTarget depth;
  // RGBA32F: rgb = blended value (RGB order on the GPU), a = 1 valid, kFilledAlpha filled, 0
  gl::Texture color;
  gl::Texture aux;  // RGBA32F: r = contributing count, g = debug photo weight

  static RenderTarget Create(int width, int height);
  int width() const { return color.width(); }
  int height() const { return color.height(); }
};

class Renderer {
 public:
  // Needs a current GL 4.5 context. Uploads points and photos, computes every photo's depth
  // map. Throws InputError naming the photo file when one cannot be read. Keeps a reference
  // to `scene`, which must outlive the renderer.
  Renderer(const gl::ShaderLibrary& shaders, const Scene& scene, RendererOptions options = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Photos allowed to contribute (indices into scene.photos); default all. Cheap: no upload.
  // Used for leave-one-out (--exclude) and per-series renders (HDR).
  void SetActivePhotos(const std::vector<int>& photo_indices);
  void SetAllPhotosActive();
  // RendererOptions::max_candidates; throws OptionError("max_candidates", ...) below 0.
  void SetMaxCandidates(int max_candidates);
  int max_candidates() const;
  // The view's depth pass draws a coarser level of the cloud below 1 (DepthPass::Process's
  // `detail`): for previews rendered at a reduced size. 1 (full detail) by default.
  void SetPointDetail(double detail);

  // Renders the view into `target` (intrinsics rescaled to the target size if they differ);
  // with `given`, its depth replaces the depth pass.
  void Render(const Camera& camera, const Rigid3d& cam_from_world, RenderTarget& target,
              const GivenDepth* given = nullptr);
  // Fills the pixels of target's colour that no photo rendered (FillPass); Render() does it
  // itself when blend_options().fill is set.
  void Fill(RenderTarget& target);
  // Render() and read back.
  RenderImages RenderToImages(const Camera& camera, const Rigid3d& cam_from_world, int width,
                              int height, const GivenDepth* given = nullptr);
  static RenderImages Read(const RenderTarget& target);

  // The candidate photos of the newest Render() (none before the first).
  const FrameCandidates& last_candidates() const;
  BlendOptions& blend_options();
  DepthPass& depth_pass();
  const Scene& scene() const;
  // GPU times of the newest Render(); waits for them (for benchmarks and one-off renders).
  const RenderTimes& last_times();
  // GPU times of the newest Render() whose queries are done, without waiting: in a render
  // loop, usually the previous frame's (Render() itself never waits on its queries).
  const RenderTimes& polled_times();
  // GPU memory of the photo textures and depth maps, bytes (resident_bytes of residency()).
  size_t gpu_bytes() const;
  // What the photo textures and depth maps hold on the GPU, against the budget.
  PhotoResidency residency() const;
  // With a cache: waits for the photos loading and uploads them (the next Render() of the
  // same view then blends them at full size); nothing otherwise.
  void SettleCache();
  // With a cache: uploads the photos loaded since the last frame without waiting and returns
  // the loads still in flight (0 without a cache): at 0, a frame rendered while they loaded is
  // out of date.
  int PollPhotoLoads();
  // True when the photos' depth maps were read from options.depth_cache_dir.
  bool depth_maps_from_cache() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hdribr::render
