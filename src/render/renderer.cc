#include "render/renderer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/photo_candidates.h"
#include "render/blend_pass.h"
#include "render/fill_pass.h"
#include "render/photo_depth_maps.h"
#include "render/photo_textures.h"
#include "render/readback.h"
#include "render/response_lut.h"

namespace hdribr::render {

RenderTarget RenderTarget::Create(int width, int height) {
  RenderTarget t;
  t.depth = DepthTarget::Create(width, height);
  t.color = gl::Texture::Create2D(GL_RGBA32F, width, height);
  t.aux = gl::Texture::Create2D(GL_RGBA32F, width, height);
  return t;
}

struct Renderer::Impl {
  const Scene& scene;
  RendererOptions options;
  BlendPass blend;  // first: its shader fails fast, before the photos are loaded
  DepthPass depth_pass;
  FillPass fill;
  PhotoLayout layout;  // the photos' sizes, measured before any upload
  PhotoDepthMaps depth_maps;
  cv::Size depth_size;     // the depth maps' array
  size_t depth_total = 0;  // every depth map, bytes
  size_t budget = 0;
  // Every photo at full size, or (beyond the budget) the cache.
  std::optional<PhotoTextures> textures;
  std::unique_ptr<PhotoCache> cache;
  gl::Texture response;  // 256 x 1 RGB32F g(Z), empty without a response curve
  std::vector<int> active;
  std::vector<int> uploaded;  // the blend pass's active list
  // Built at the first capped Render(): its sample and occlusion grids cost set-up time that
  // renderers without a cap (max_candidates 0) never need.
  std::optional<PhotoCandidates> candidates;
  FrameCandidates last;
  // Two sets of timestamp queries used in turn, so that a render loop reads a frame's times
  // when the next one is issued instead of stalling on them.
  struct Stamps {
    gl::TimestampQuery t[4] = {gl::TimestampQuery::Create(), gl::TimestampQuery::Create(),
                               gl::TimestampQuery::Create(), gl::TimestampQuery::Create()};
    bool unread = false;
  };
  Stamps stamps[2];
  int newest = 0;             // the set of the newest Render()
  double point_detail = 1.0;  // SetPointDetail
  RenderTimes times;

  void ReadStamps(Stamps& s) {
    const GLuint64 t0 = s.t[0].ResultNs(), t1 = s.t[1].ResultNs(), t2 = s.t[2].ResultNs(),
                   t3 = s.t[3].ResultNs();
    times.depth_ms = static_cast<double>(t1 - t0) * 1e-6;
    times.blend_ms = static_cast<double>(t2 - t1) * 1e-6;
    times.fill_ms = static_cast<double>(t3 - t2) * 1e-6;
    s.unread = false;
  }
  std::optional<RenderTarget> scratch;  // RenderToImages' target

  Impl(const gl::ShaderLibrary& shaders, const Scene& s, RendererOptions o)
      : scene(s),
        options(std::move(o)),
        blend(shaders),
        depth_pass(shaders, WithPoints(options.depth)),
        fill(shaders),
        layout(MeasurePhotos(s, options.photo_images, options.max_photo_size)),
        depth_maps(MakeDepthMaps(s, depth_pass, options)),
        budget(GpuBudgetBytes(options.gpu_memory_mb)) {
    options.photo_depths.clear();
    options.photo_depths.shrink_to_fit();
    depth_size = cv::Size(depth_maps.depth().width(), depth_maps.depth().height());
    const size_t depth_layer = static_cast<size_t>(depth_size.area()) * 4;
    depth_total = depth_layer * scene.photos.size();
    const int per_frame =
        options.blend.mode == BlendMode::kNearestPhoto ? 1 : options.max_candidates;
    const std::optional<PhotoCachePlan> plan =
        PlanPhotoCache(layout, depth_layer, per_frame, budget);
    if (plan) {
      // The cache keeps photos given in memory for its loads, and with depth slots every
      // depth map on the CPU.
      std::vector<cv::Mat> depth_layers;
      if (plan->depth_slots > 0) depth_layers = depth_maps.TakeLayers();
      cache = std::make_unique<PhotoCache>(scene, std::move(options.photo_images), layout, *plan,
                                           std::move(depth_layers), depth_size);
      blend.SetPhotos(scene, *cache, depth_maps);
    } else {
      textures.emplace(s, options.photo_images, layout);
      blend.SetPhotos(scene, *textures, depth_maps);
    }
    // The pixels were uploaded: do not keep a second copy of an HDR photo set in memory.
    options.photo_images.clear();
    options.photo_images.shrink_to_fit();
    SetAll();
    if (options.response) response = MakeResponseLut(*options.response);
  }

  static DepthPassOptions WithPoints(DepthPassOptions o) { return o; }
  static PhotoDepthMaps MakeDepthMaps(const Scene& s, DepthPass& pass, const RendererOptions& o) {
    pass.SetPoints(s.points);
    if (!o.photo_depths.empty()) {
      if (o.photo_depths.size() != s.photos.size()) {
        throw UsageError("given photo depth maps: " + std::to_string(o.photo_depths.size()) +
                         " for " + std::to_string(s.photos.size()) + " photos");
      }
      return PhotoDepthMaps(s, o.photo_depths, o.photo_depth_scale);
    }
    return PhotoDepthMaps(s, pass, o.photo_depth_scale, o.depth_cache_dir);
  }

  void SetAll() {
    std::vector<int> all(scene.photos.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    SetActive(all);
  }

  void SetActive(const std::vector<int>& photos) {
    Upload(photos);
    active = photos;
  }

  // The blend pass's list, re-uploaded only when it changes.
  void Upload(const std::vector<int>& photos) {
    if (photos == uploaded) return;
    blend.SetActive(photos);
    uploaded = photos;
  }
};

namespace {

void CheckMaxCandidates(int max_candidates) {
  if (max_candidates < 0) {
    throw OptionError("max_candidates", "must be >= 0 (0 = every active photo), got " +
                                            std::to_string(max_candidates));
  }
}

}  // namespace

Renderer::Renderer(const gl::ShaderLibrary& shaders, const Scene& scene, RendererOptions options) {
  ValidateBlendOptions(options.blend);  // before any upload
  CheckMaxCandidates(options.max_candidates);
  CheckGpuMemoryMb(options.gpu_memory_mb);
  const auto t0 = std::chrono::steady_clock::now();
  impl_ = std::make_unique<Impl>(shaders, scene, std::move(options));
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const PhotoLayout& l = impl_->layout;
  const PhotoResidency r = residency();
  spdlog::info(
      "renderer: {} photos ({}x{} array, {} levels, {}), {} points; GPU memory {:.1f} MiB "
      "(photos {:.1f}, depth maps {:.1f}); set up in {:.2f} s",
      scene.photos.size(), l.width, l.height, l.levels, l.is_float ? "RGBA16F" : "RGBA8",
      scene.points.size(), r.resident_bytes / 1048576.0,
      (r.resident_bytes - r.depth_bytes) / 1048576.0, r.depth_bytes / 1048576.0, s);
  if (r.cached) {
    spdlog::info(
        "renderer: the photos need {:.1f} MiB with their depth maps, over the budget of {:.1f} "
        "MiB: photo cache of {} full-size slots, {} reduced slots (mip levels 1 or 2 on) and "
        "coarse copies at 1/{} size",
        r.total_bytes / 1048576.0, r.budget_bytes / 1048576.0, r.slots, r.reduced_slots,
        r.fallback_divisor);
  }
}

Renderer::~Renderer() = default;

void Renderer::SetActivePhotos(const std::vector<int>& photo_indices) {
  impl_->SetActive(photo_indices);
}

void Renderer::SetAllPhotosActive() { impl_->SetAll(); }

void Renderer::SetMaxCandidates(int max_candidates) {
  CheckMaxCandidates(max_candidates);
  impl_->options.max_candidates = max_candidates;
}

int Renderer::max_candidates() const { return impl_->options.max_candidates; }

void Renderer::SetPointDetail(double detail) { impl_->point_detail = detail; }

namespace {

// Uploads a given depth and normal into the view's depth target.
void UploadGivenDepth(const GivenDepth& given, DepthTarget& target) {
  const int w = target.width(), h = target.height();
  if (given.depth.type() != CV_32FC1 || given.normal.type() != CV_32FC3 || given.depth.cols != w ||
      given.depth.rows != h || given.normal.size() != given.depth.size()) {
    throw UsageError("a given depth must be CV_32FC1 with CV_32FC3 normals of the target's size");
  }
  const cv::Mat depth = given.depth.clone();  // continuous
  cv::Mat normal;
  cv::cvtColor(given.normal, normal, cv::COLOR_RGB2RGBA);  // x, y, z kept in order
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(target.depth.id(), 0, 0, 0, w, h, GL_RED, GL_FLOAT, depth.data);
  glTextureSubImage2D(target.normal.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, normal.data);
}

}  // namespace

void Renderer::Render(const Camera& camera, const Rigid3d& cam_from_world, RenderTarget& target,
                      const GivenDepth* given) {
  Impl& m = *impl_;
  const Camera cam = (camera.width == target.width() && camera.height == target.height())
                         ? camera
                         : camera.Scaled(target.width(), target.height());
  // The photos of this frame: the nearest one, the candidates or every active photo.
  m.last.active = static_cast<int>(m.active.size());
  m.last.select_ms = 0;
  if (m.options.blend.mode == BlendMode::kNearestPhoto) {
    const int best = m.scene.NearestPhoto(cam_from_world, m.active);
    m.last.photos = best >= 0 ? std::vector<int>{best} : std::vector<int>{};
  } else if (m.options.max_candidates > 0 && !m.active.empty()) {
    const int ranked = RankedPhotosPerPixel(m.options.blend);
    if (!m.candidates) m.candidates.emplace(m.scene);
    const auto t0 = std::chrono::steady_clock::now();
    m.last.photos = m.candidates->Select(cam, cam_from_world, m.active, m.options.max_candidates,
                                         ranked > 0 ? ranked : m.options.max_candidates);
    m.last.select_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  } else {
    m.last.photos = m.active;
  }
  if (m.options.max_candidates > 0 && m.candidates &&
      BlendRanksPhotos(m.options.blend, static_cast<int>(m.last.photos.size()))) {
    // The blend ranks photos per pixel: it visits the best-scored candidates first, so that
    // the photos it meets later mostly rank below its list and skip their shadow-map test
    // (shaders/blend_visibility.glsl, Weight). Summing every photo keeps their order (the sum's).
    std::vector<int> order = m.last.photos;
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return m.candidates->score(a) > m.candidates->score(b); });
    m.Upload(order);
  } else {
    m.Upload(m.last.photos);
  }
  if (m.cache) m.cache->Request(m.last.photos, m.options.wait_for_photos);
  // The older set is re-used: read it first if it is done (it is overwritten otherwise).
  m.newest = 1 - m.newest;
  Impl::Stamps& stamps = m.stamps[m.newest];
  if (stamps.unread && stamps.t[3].Available()) m.ReadStamps(stamps);
  stamps.t[0].Stamp();
  if (given) {
    UploadGivenDepth(*given, target.depth);
  } else {
    m.depth_pass.Process(cam, cam_from_world, target.depth, m.point_detail);
  }
  stamps.t[1].Stamp();
  m.blend.Process(cam, cam_from_world, target.depth, m.options.blend,
                  m.response ? &m.response : nullptr, target.color, target.aux);
  // Waiting renders are the all-resident render: when the blend sampled a photo finer than its
  // slot holds, the cache moves it to a finer slot and the blend runs again (twice at most: the
  // second placement knows every photo's level).
  for (int round = 0; round < 2 && m.cache && m.options.wait_for_photos && m.cache->Refine(true);
       ++round) {
    m.blend.Process(cam, cam_from_world, target.depth, m.options.blend,
                    m.response ? &m.response : nullptr, target.color, target.aux);
  }
  stamps.t[2].Stamp();
  if (m.options.blend.fill) Fill(target);
  stamps.t[3].Stamp();
  stamps.unread = true;
}

void Renderer::Fill(RenderTarget& target) { impl_->fill.Process(target.color); }

RenderImages Renderer::RenderToImages(const Camera& camera, const Rigid3d& cam_from_world,
                                      int width, int height, const GivenDepth* given) {
  Impl& m = *impl_;
  if (!m.scratch || m.scratch->width() != width || m.scratch->height() != height) {
    m.scratch = RenderTarget::Create(width, height);
  }
  Render(camera, cam_from_world, *m.scratch, given);
  return Read(*m.scratch);
}

RenderImages Renderer::Read(const RenderTarget& target) {
  RenderImages out;
  const DepthImages d = ReadDepthTarget(target.depth);
  out.depth = d.depth;
  out.normal = d.normal;
  cv::Mat rgba(target.height(), target.width(), CV_32FC4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(target.color.id(), 0, GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(rgba.total() * 16), rgba.data);
  cv::cvtColor(rgba, out.color, cv::COLOR_RGBA2BGR);
  cv::Mat alpha;
  cv::extractChannel(rgba, alpha, 3);
  // Thresholds half-way between the alphas (1, kFilledAlpha, 0).
  out.valid = alpha > 0.5f * (1.0f + kFilledAlpha);
  out.filled = (alpha > 0.5f * kFilledAlpha) & ~out.valid;
  cv::Mat aux(target.height(), target.width(), CV_32FC4);
  glGetTextureImage(target.aux.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(aux.total() * 16),
                    aux.data);
  cv::extractChannel(aux, out.count, 0);
  cv::extractChannel(aux, out.weight, 1);
  return out;
}

const FrameCandidates& Renderer::last_candidates() const { return impl_->last; }
BlendOptions& Renderer::blend_options() { return impl_->options.blend; }
DepthPass& Renderer::depth_pass() { return impl_->depth_pass; }
const Scene& Renderer::scene() const { return impl_->scene; }
const RenderTimes& Renderer::last_times() {
  Impl& m = *impl_;
  if (m.stamps[m.newest].unread) {
    m.ReadStamps(m.stamps[m.newest]);
    m.stamps[1 - m.newest].unread = false;  // older than what was just read
  }
  return m.times;
}

const RenderTimes& Renderer::polled_times() {
  Impl& m = *impl_;
  Impl::Stamps& newest = m.stamps[m.newest];
  Impl::Stamps& older = m.stamps[1 - m.newest];
  if (newest.unread && newest.t[3].Available()) {
    m.ReadStamps(newest);
    older.unread = false;
  } else if (older.unread && older.t[3].Available()) {
    m.ReadStamps(older);
  }
  return m.times;
}

size_t Renderer::gpu_bytes() const { return residency().resident_bytes; }

PhotoResidency Renderer::residency() const {
  const Impl& m = *impl_;
  PhotoResidency r;
  if (m.cache) {
    r = m.cache->residency();  // its resident bytes count the depth maps it holds
  } else {
    r.photos = static_cast<int>(m.scene.photos.size());
    r.full_size = r.photos;
    r.slots = r.photos;
    r.depth_bytes = m.depth_total;
    r.resident_bytes = m.layout.Bytes() + m.depth_total;
  }
  r.budget_bytes = m.budget;
  r.total_bytes = m.layout.Bytes() + m.depth_total;
  return r;
}

void Renderer::SettleCache() {
  if (impl_->cache) impl_->cache->Settle();
}

int Renderer::PollPhotoLoads() { return impl_->cache ? impl_->cache->Poll() : 0; }

bool Renderer::depth_maps_from_cache() const { return impl_->depth_maps.from_cache(); }

}  // namespace hdribr::render
