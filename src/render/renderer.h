// The image-based renderer (Lechelek et al. 2019, sec. 4): depth pass of the new view, then
// the blend pass over the photos on the GPU. This is the API the CLI, eval, HDR and the viewer
// share; the passes themselves live in depth_pass.h, blend_pass.h, photo_textures.h.
#pragma once

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
#include "render/depth_pass.h"

namespace hdribr::render {

// What the blend pass computes per pixel.
enum class BlendMode {
  kBlend,         // blend the photos that see the point (weights: BlendWeights)
  kNearestPhoto,  // baseline: projective texturing from the single photo nearest the view
};

// The blending weights of BlendMode::kBlend.
enum class BlendWeights {
  kPaper,         // LEC19 eq. 5: max(0, V . V_k) / (delta_k + 1) over all (or the K best)
  kUnstructured,  // Unstructured Lumigraph (Buehler et al. 2001): K smallest angle + delta
                  // penalties p_k, w_k = (1 - p_k / p_(K+1)) / p_k
};

// "paper", "ulr"; ParseBlendWeights throws UsageError for anything else.
std::string BlendWeightsName(BlendWeights weights);
BlendWeights ParseBlendWeights(const std::string& name);

// K of BlendWeights::kUnstructured when BlendOptions::k_best is 0.
inline constexpr int kDefaultUnstructuredK = 4;

// How photo pixels are turned into the blended value.
enum class PhotoEncoding {
  kDisplay,   // the photo's stored values (8-bit / 255, or float for an HDR photo set)
  kRadiance,  // direct radiance blending (issue 6 mode 3): exp(g(Z)) / relative exposure,
              // blending weight times Debevec's hat weight of Z; needs a response curve
};

struct BlendOptions {
  BlendMode mode = BlendMode::kBlend;
  PhotoEncoding encoding = PhotoEncoding::kDisplay;
  // Unstructured Lumigraph by default (1.7 dB closer than eq. 5 in leave-one-out on the
  // default capture, docs/benchmarks.md); kPaper is the paper's blending exactly.
  BlendWeights weights = BlendWeights::kUnstructured;
  int k_best = 0;        // 0 = all photos for kPaper (the paper), kDefaultUnstructuredK for ULR
  float lambda = 1e-4f;  // a photo counts when N_p . V_k > lambda (paper eq. 3)
  float occlusion_tolerance = 0.01f;  // |z_k(P) - depth_k| <= tolerance * depth_k passes
  int debug_photo = -1;               // photo index whose weight goes to RenderImages::weight
};

// Throws UsageError, naming the command-line option (--k-best, --lambda, --tolerance), for
// values no blend can use: k_best < 0, lambda outside [0, 1), tolerance outside (0, 1).
void ValidateBlendOptions(const BlendOptions& options);

struct RendererOptions {
  DepthPassOptions depth;
  BlendOptions blend;
  int max_photo_size = 0;          // longest side of photos on the GPU; 0 = full size
  double photo_depth_scale = 1.0;  // size of the per-photo depth maps relative to the photos
  // Photo pixels to use instead of the files on disk (an HDR photo set, CV_32FC3 BGR, one per
  // scene photo in scene order); empty = read scene.photos[i].image_path.
  std::vector<cv::Mat> photo_images;
  // Needed by PhotoEncoding::kRadiance.
  std::optional<ResponseCurve> response;
};

// Per-frame GPU timings in milliseconds (GL timestamp queries).
struct RenderTimes {
  double depth_ms = 0;
  double blend_ms = 0;
};

// CPU read-back of one rendered view. Rows top to bottom; colours BGR like the rest of the code.
struct RenderImages {
  cv::Mat color;   // CV_32FC3, blended value (see PhotoEncoding); 0 where invalid; never NaN
  cv::Mat valid;   // CV_8UC1, 255 where depth is valid and at least one photo contributed
  cv::Mat depth;   // CV_32FC1 camera z, 0 = no depth
  cv::Mat normal;  // CV_32FC3 camera-space normal (x, y, z)
  cv::Mat count;   // CV_32FC1 number of contributing photos
  cv::Mat weight;  // CV_32FC1 normalised weight of options.blend.debug_photo (0 when none)
};

// GPU outputs of a frame, reused across frames of the same size.
struct RenderTarget {
  DepthTarget depth;
  gl::Texture color;  // RGBA32F: rgb = blended value (RGB order on the GPU), a = 1 valid / 0
  gl::Texture aux;    // RGBA32F: r = contributing count, g = debug photo weight

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

  // Renders the view into `target` (intrinsics rescaled to the target size if they differ).
  void Render(const Camera& camera, const Rigid3d& cam_from_world, RenderTarget& target);
  // Render() and read back.
  RenderImages RenderToImages(const Camera& camera, const Rigid3d& cam_from_world, int width,
                              int height);
  static RenderImages Read(const RenderTarget& target);

  BlendOptions& blend_options();
  DepthPass& depth_pass();
  const Scene& scene() const;
  // GPU times of the newest Render(); waits for them (for benchmarks and one-off renders).
  const RenderTimes& last_times();
  // GPU times of the newest Render() whose queries are done, without waiting: in a render
  // loop, usually the previous frame's (Render() itself never waits on its queries).
  const RenderTimes& polled_times();
  // GPU memory of the photo textures and depth maps, bytes.
  size_t gpu_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hdribr::render
