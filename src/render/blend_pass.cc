#include "render/blend_pass.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "core/dominant_plane.h"
#include "core/error.h"
#include "core/photo_candidates.h"

namespace hdribr::render {
namespace {

// The program for the pixels with a point, and the one for the pixels without (the
// background and the holes of the view's depth).
constexpr const char* kSurfaceProgram = "blend.comp";
constexpr const char* kBackgroundProgram = "blend_background.comp";

// std430 mirror of PhotoGpu in shaders/blend_common.glsl.
struct PhotoGpu {
  float cam_from_world[16];
  float intrinsics[4];
  float center[4];
  float size[4];
  float tex[4];
  float dmap[4];
  float coarse[4];
};
static_assert(sizeof(PhotoGpu) == 40 * 4);

// True when the blend low-passes its photos (filtered blending; never for the nearest photo).
bool Filtered(const BlendOptions& options) {
  return options.mode != BlendMode::kNearestPhoto && options.filter > 0.0f;
}

// True when the blend reweights its ranked photos by their colours' agreement: 8-bit photos
// (the scale is in their units), never for the nearest photo nor when every photo is summed.
bool RejectsOutliers(const BlendOptions& options, bool sum_all, bool float_photos) {
  return options.mode != BlendMode::kNearestPhoto && !sum_all && !float_photos &&
         options.outlier_scale > 0.0f;
}

// True when the blend moves each point to its photos' most consistent depth (a list of ranked
// photos to compare; never for the nearest photo).
bool RefinesDepth(const BlendOptions& options, bool sum_all) {
  return options.mode != BlendMode::kNearestPhoto && !sum_all && options.refine_depth > 0.0f;
}

// The modes compiled into a blend program (the defines of shaders/blend_common.glsl): `keep`
// entries in the per-pixel list, `sum_all` for eq. 5 over every photo, `tiers` the slot sizes of
// the PhotoCache holding the photos (0: none), `cached_depth` when it holds their depth maps,
// `float_photos` for RGBA16F photos; the background only for kBackgroundProgram, the one
// program that draws it.
gl::Defines ProgramModes(const char* file, const BlendOptions& options, int keep, bool sum_all,
                         int tiers, bool cached_depth, bool float_photos) {
  const bool nearest = options.mode == BlendMode::kNearestPhoto;
  gl::Defines modes = {{"KEEP", std::to_string(keep)},
                       {"ENCODING", options.encoding == PhotoEncoding::kRadiance ? "1" : "0"},
                       {"NEAREST", nearest ? "1" : "0"},
                       {"ULR", options.weights == BlendWeights::kUnstructured ? "1" : "0"},
                       {"SUM_ALL", sum_all ? "1" : "0"},
                       {"SOFT_VISIBILITY", options.visibility == Visibility::kSoft ? "1" : "0"},
                       {"CACHED", tiers > 0 ? "1" : "0"},
                       {"TIERS", std::to_string(std::max(tiers, 1))},
                       {"CACHED_DEPTH", cached_depth ? "1" : "0"},
                       {"CUBIC", options.sampling == PhotoSampling::kCubic ? "1" : "0"},
                       {"OUTLIER", RejectsOutliers(options, sum_all, float_photos) ? "1" : "0"},
                       {"REFINE", RefinesDepth(options, sum_all) ? "1" : "0"},
                       {"DELTA_WEIGHT", std::to_string(kUlrDistanceWeight)}};
  if (std::string(file) == kBackgroundProgram) {
    modes.emplace_back("BACKGROUND", std::to_string(static_cast<int>(options.background)));
  }
  if (Filtered(options)) modes.emplace_back("FILTERED", "1");
  return modes;
}

// The per-pixel list's length for `options` with `active` photos, and whether eq. 5 sums every
// photo instead of ranking them.
std::pair<int, bool> ListFor(const BlendOptions& options, int active) {
  const bool ulr = options.weights == BlendWeights::kUnstructured;
  int k_best = options.k_best;
  if (ulr) {
    // K >= the active photos: every photo, thresholded at the cosine horizon (shader).
    if (k_best == 0) k_best = kDefaultUnstructuredK;
    k_best = std::min({k_best, std::max(active, 1), kMaxKBest});
  } else if (!BlendRanksPhotos(options, active)) {
    k_best = 0;  // K >= the active photos is all of them (exactly)
  }
  // K + 1 entries for the Unstructured Lumigraph, K for the paper's K best (1, unused, when
  // every photo is blended).
  const bool nearest = options.mode == BlendMode::kNearestPhoto;
  const int keep = ulr && !nearest ? k_best + 1 : std::max(k_best, 1);
  return {keep, k_best <= 0 && !(ulr && !nearest)};
}

}  // namespace

Eigen::Vector4d BackgroundSphere(const Scene& scene) {
  std::vector<double> d;
  d.reserve(scene.points.size());
  for (const auto& p : scene.points.positions)
    d.push_back((p.cast<double>() - scene.centroid).norm());
  double radius = 0.0;
  if (!d.empty()) {
    const auto at = d.begin() + static_cast<std::ptrdiff_t>((d.size() - 1) * 99 / 100);
    std::nth_element(d.begin(), at, d.end());
    radius = *at;
  }
  for (const Photo& photo : scene.photos) {
    radius = std::max(radius, 1.25 * (photo.Center() - scene.centroid).norm());
  }
  if (!(radius > 0.0)) radius = scene.scene_scale;
  return {scene.centroid.x(), scene.centroid.y(), scene.centroid.z(), radius};
}

BlendPass::BlendPass(const gl::ShaderLibrary& shaders)
    : shaders_(shaders), params_buffer_(sizeof(BlendParamsGpu), nullptr, GL_DYNAMIC_STORAGE_BIT) {
  // The default's, so that compile errors show early.
  for (const char* file : {kSurfaceProgram, kBackgroundProgram}) {
    ProgramFor(file, ProgramModes(file, BlendOptions(), kDefaultUnstructuredK + 1, false, 0, false,
                                  false));
  }
}

std::vector<std::pair<std::string, gl::Defines>> BlendPass::ReachablePrograms() {
  // Each option's values with the others at their defaults, with 20 photos in memory (where
  // every option reaches its modes), then the modes of the photo cache and of float photos.
  std::vector<BlendOptions> variants(1);
  const auto vary = [&](auto set) {
    BlendOptions o;
    set(o);
    variants.push_back(o);
  };
  vary([](BlendOptions& o) { o.mode = BlendMode::kNearestPhoto; });
  vary([](BlendOptions& o) { o.encoding = PhotoEncoding::kRadiance; });
  vary([](BlendOptions& o) { o.weights = BlendWeights::kPaper; });
  vary([](BlendOptions& o) {
    o.weights = BlendWeights::kPaper;
    o.k_best = kDefaultUnstructuredK;
  });
  vary([](BlendOptions& o) { o.k_best = kMaxKBest; });
  for (Background b : kAllBackgrounds) vary([b](BlendOptions& o) { o.background = b; });
  vary([](BlendOptions& o) { o.visibility = Visibility::kSoft; });
  vary([](BlendOptions& o) { o.filter = kMaxFilter; });
  for (PhotoSampling p : kAllPhotoSamplings) vary([p](BlendOptions& o) { o.sampling = p; });
  vary([](BlendOptions& o) { o.outlier_scale = 0.0f; });
  vary([](BlendOptions& o) { o.refine_depth = 0.0f; });
  struct Memory {
    int tiers;
    bool cached_depth, float_photos;
  };
  const Memory kMemories[] = {
      {0, false, true}, {1, false, false}, {2, false, false}, {3, true, false}};
  std::vector<std::pair<std::string, gl::Defines>> out;
  const auto add = [&](const char* file, const gl::Defines& modes) {
    std::pair<std::string, gl::Defines> program(file, modes);
    if (std::find(out.begin(), out.end(), program) == out.end()) out.push_back(program);
  };
  for (const char* file : {kSurfaceProgram, kBackgroundProgram}) {
    for (const BlendOptions& o : variants) {
      const auto [keep, sum_all] = ListFor(o, 20);
      add(file, ProgramModes(file, o, keep, sum_all, 0, false, false));
    }
    const auto [keep, sum_all] = ListFor(BlendOptions(), 20);
    for (const Memory& m : kMemories) {
      add(file, ProgramModes(file, BlendOptions(), keep, sum_all, m.tiers, m.cached_depth,
                             m.float_photos));
    }
  }
  return out;
}

const gl::Program& BlendPass::ProgramFor(const char* file, const gl::Defines& modes) const {
  auto key = std::make_pair(std::string(file), modes);
  auto it = programs_.find(key);
  if (it == programs_.end()) it = programs_.emplace(key, shaders_.Build({file}, modes)).first;
  return it->second;
}

void BlendPass::SetPhotos(const Scene& scene, const PhotoTextures& textures,
                          const PhotoDepthMaps& depth_maps) {
  SetPhotos(scene, textures.layout(), textures.id(), depth_maps, nullptr);
}

void BlendPass::SetPhotos(const Scene& scene, const PhotoCache& cache,
                          const PhotoDepthMaps& depth_maps) {
  // The cache's arrays change when it re-splits its slots: Process binds its current ones.
  SetPhotos(scene, cache.layout(), 0, depth_maps, &cache);
}

void BlendPass::SetPhotos(const Scene& scene, const PhotoLayout& textures, GLuint texture,
                          const PhotoDepthMaps& depth_maps, const PhotoCache* cache) {
  std::vector<PhotoGpu> gpu(std::max<size_t>(1, scene.photos.size()));
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    const Photo& photo = scene.photos[i];
    const Camera& cam = scene.CameraOf(photo);
    PhotoGpu& g = gpu[i];
    const Eigen::Matrix4f m = photo.cam_from_world.Matrix4().cast<float>();
    std::copy(m.data(), m.data() + 16, g.cam_from_world);  // column-major like GLSL
    g.intrinsics[0] = static_cast<float>(cam.fx());
    g.intrinsics[1] = static_cast<float>(cam.fy());
    g.intrinsics[2] = static_cast<float>(cam.cx());
    g.intrinsics[3] = static_cast<float>(cam.cy());
    const Eigen::Vector3d c = photo.Center();
    const double relative = scene.RelativeExposureOf(photo);
    g.center[0] = static_cast<float>(c.x());
    g.center[1] = static_cast<float>(c.y());
    g.center[2] = static_cast<float>(c.z());
    g.center[3] = relative > 0 ? static_cast<float>(1.0 / relative) : 1.0f;
    const cv::Size ts = textures.sizes[i];
    const double texels_per_px = static_cast<double>(ts.width) / cam.width;
    g.size[0] = static_cast<float>(cam.width);
    g.size[1] = static_cast<float>(cam.height);
    g.size[2] = static_cast<float>(texels_per_px);
    g.tex[0] = static_cast<float>(static_cast<double>(ts.width) / cam.width / textures.width);
    g.tex[1] = static_cast<float>(static_cast<double>(ts.height) / cam.height / textures.height);
    g.tex[2] = static_cast<float>((ts.width - 0.5) / textures.width);
    g.tex[3] = static_cast<float>((ts.height - 0.5) / textures.height);
    if (cache) {
      // The coarse copy: its texture coordinate per full-size one, its largest coordinate, and
      // (size.w) the level of detail to add, log2 of its texels per full-size texel.
      const PhotoLayout& f = cache->fallback_layout();
      const cv::Size fs = f.sizes[i];
      const double full_per_px = static_cast<double>(ts.width) / cam.width / textures.width;
      const double coarse_per_px = static_cast<double>(fs.width) / cam.width / f.width;
      const double full_per_py = static_cast<double>(ts.height) / cam.height / textures.height;
      const double coarse_per_py = static_cast<double>(fs.height) / cam.height / f.height;
      g.coarse[0] = static_cast<float>(coarse_per_px / full_per_px);
      g.coarse[1] = static_cast<float>(coarse_per_py / full_per_py);
      g.coarse[2] = static_cast<float>((fs.width - 0.5) / f.width);
      g.coarse[3] = static_cast<float>((fs.height - 0.5) / f.height);
      g.size[3] = static_cast<float>(std::log2(static_cast<double>(fs.width) / ts.width));
    }
    const cv::Size ds = depth_maps.layer_size(static_cast<int>(i));
    g.dmap[0] = static_cast<float>(static_cast<double>(ds.width) / cam.width);
    g.dmap[1] = static_cast<float>(static_cast<double>(ds.height) / cam.height);
    g.dmap[2] = static_cast<float>(ds.width);
    g.dmap[3] = static_cast<float>(ds.height);
  }
  photos_ = gl::Buffer(gpu.size() * sizeof(PhotoGpu), gpu.data());
  photo_texture_ = texture;
  cache_ = cache;
  cached_depth_ = cache && cache->caches_depth();
  depth_maps_ = cached_depth_ ? cache->depth_texture() : depth_maps.depth().id();
  photo_count_ = static_cast<int>(scene.photos.size());
  float_photos_ = textures.is_float;
  params_.photo_texels[0] = static_cast<float>(textures.width);
  params_.photo_texels[1] = static_cast<float>(textures.height);
  params_.inv_scene_scale =
      scene.scene_scale > 0 ? static_cast<float>(1.0 / scene.scene_scale) : 1.0f;
  const Eigen::Vector4d sphere = BackgroundSphere(scene);
  for (int k = 0; k < 4; ++k) params_.sphere[k] = static_cast<float>(sphere[k]);
  // Without a dominant plane the zero normal never meets a ray: the sphere alone.
  const DominantPlane plane = FindDominantPlane(scene);
  for (int k = 0; k < 3; ++k) {
    params_.plane[k] = plane.valid() ? static_cast<float>(plane.normal[k]) : 0.0f;
    params_.plane_u[k] = static_cast<float>(plane.axis_u[k]);
    params_.plane_v[k] = static_cast<float>(plane.axis_v[k]);
  }
  params_.plane[3] = static_cast<float>(plane.offset);
  for (int k = 0; k < 4; ++k) params_.plane_extent[k] = static_cast<float>(plane.extent[k]);
  std::vector<int> all(scene.photos.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  SetActive(all);
}

void BlendPass::SetActive(const std::vector<int>& photo_indices) {
  for (int i : photo_indices) {
    if (i < 0 || i >= photo_count_) {
      throw UsageError("active photo index " + std::to_string(i) + " out of range (" +
                       std::to_string(photo_count_) + " photos)");
    }
  }
  std::vector<int> list = photo_indices;
  if (list.empty()) list.push_back(0);  // the buffer needs a byte; active_count_ stays 0
  active_ = gl::Buffer(list.size() * sizeof(int), list.data());
  active_count_ = static_cast<int>(photo_indices.size());
}

void BlendPass::Process(const Camera& camera, const Rigid3d& cam_from_world,
                        const DepthTarget& depth, const BlendOptions& options,
                        const gl::Texture* response, gl::Texture& color, gl::Texture& aux) const {
  HDRIBR_CHECK(color.width() == depth.width() && color.height() == depth.height());
  if (options.encoding == PhotoEncoding::kRadiance && response == nullptr) {
    throw UsageError("radiance blending needs a response curve (RendererOptions::response)");
  }
  HDRIBR_CHECK_MSG(BlendOptionProblems(options).empty(), "blend options not validated");
  const auto [keep, sum_all] = ListFor(options, active_count_);
  BlendParamsGpu params = params_;
  const Eigen::Matrix4f wfc = cam_from_world.Inverse().Matrix4().cast<float>();
  std::copy(wfc.data(), wfc.data() + 16, params.world_from_cam);
  params.intrinsics[0] = static_cast<float>(camera.fx());
  params.intrinsics[1] = static_cast<float>(camera.fy());
  params.intrinsics[2] = static_cast<float>(camera.cx());
  params.intrinsics[3] = static_cast<float>(camera.cy());
  params.size[0] = depth.width();
  params.size[1] = depth.height();
  params.active_count = active_count_;
  params.lambda = options.lambda;
  params.tolerance = options.occlusion_tolerance;
  params.debug_photo = options.debug_photo;
  params.filter = options.filter;
  params.outlier_scale = options.outlier_scale;
  params.refine = options.refine_depth;
  glNamedBufferSubData(params_buffer_.id(), 0, sizeof(params), &params);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, params_buffer_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, photos_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, active_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, cache_ ? cache_->slot_map() : active_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3,
                   cached_depth_ ? cache_->depth_slot_map() : active_.id());
  if (cache_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, cache_->feedback());
  glBindTextureUnit(0, depth.depth.id());
  glBindTextureUnit(1, depth.normal.id());
  glBindTextureUnit(2, cache_ ? cache_->slots_texture() : photo_texture_);
  glBindTextureUnit(3, depth_maps_);
  glBindTextureUnit(4, response ? response->id() : 0);
  glBindTextureUnit(5, cache_ ? cache_->fallback_texture() : 0);
  glBindTextureUnit(6, cache_ ? cache_->tier_texture(1) : 0);
  glBindTextureUnit(7, cache_ ? cache_->tier_texture(2) : 0);
  glBindImageTexture(0, color.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(1, aux.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  // The pixels with a point, which lists the others in holes_ (and their dispatch's size),
  // then those.
  const size_t holes_bytes = 16 + 4 * static_cast<size_t>(depth.width()) * depth.height();
  if (holes_.size() < holes_bytes)
    holes_ = gl::Buffer(holes_bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
  const GLuint empty_list[4] = {0, 1, 1, 0};  // groups x, y, z; pixels listed
  glNamedBufferSubData(holes_.id(), 0, sizeof(empty_list), empty_list);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, holes_.id());
  const int tiers = cache_ ? cache_->tiers() : 0;
  ProgramFor(kSurfaceProgram, ProgramModes(kSurfaceProgram, options, keep, sum_all, tiers,
                                           cached_depth_, float_photos_))
      .Use();
  glDispatchCompute(static_cast<GLuint>((depth.width() + 7) / 8),
                    static_cast<GLuint>((depth.height() + 7) / 8), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  ProgramFor(kBackgroundProgram, ProgramModes(kBackgroundProgram, options, keep, sum_all, tiers,
                                              cached_depth_, float_photos_))
      .Use();
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, holes_.id());
  glDispatchComputeIndirect(0);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
}

}  // namespace hdribr::render
