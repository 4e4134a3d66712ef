#include "render/photo_cache.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <opencv2/imgproc.hpp>
#include <string>

#include "core/error.h"
#include "render/photo_loader.h"

namespace hdribr::render {

void CheckGpuMemoryMb(double mb) {
  if (!std::isfinite(mb) || mb < 0) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", mb);
    throw OptionError("gpu_memory_mb",
                      std::string("must be >= 0 MiB (0 = from the device), got ") + text);
  }
}

size_t GpuBudgetBytes(double mb) {
  CheckGpuMemoryMb(mb);
  if (mb > 0) return static_cast<size_t>(mb * 1048576.0);
  GLint kib[4] = {0, 0, 0, 0};
  if (epoxy_has_gl_extension("GL_NVX_gpu_memory_info")) {
    glGetIntegerv(GL_GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX, kib);
  } else if (epoxy_has_gl_extension("GL_ATI_meminfo")) {
    glGetIntegerv(GL_TEXTURE_FREE_MEMORY_ATI, kib);  // kib[0]: total free
  }
  if (kib[0] > 0) return static_cast<size_t>(kib[0]) * 1024 / 4 * 3;
  return static_cast<size_t>(kDefaultGpuMemoryMb * 1048576.0);
}

namespace {

// The layout of the coarse copies: every photo's size divided by 2^shift.
PhotoLayout FallbackLayout(const PhotoLayout& full, int shift) {
  PhotoLayout f;
  f.is_float = full.is_float;
  f.limit = full.limit;
  const double scale = std::ldexp(1.0, -shift);
  for (const cv::Size& s : full.sizes) {
    const cv::Size c(std::max(1, static_cast<int>(std::lround(s.width * scale))),
                     std::max(1, static_cast<int>(std::lround(s.height * scale))));
    f.sizes.push_back(c);
    f.width = std::max(f.width, c.width);
    f.height = std::max(f.height, c.height);
  }
  f.levels = 1 + static_cast<int>(std::floor(std::log2(std::max(f.width, f.height))));
  return f;
}

std::string Mib(size_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f", static_cast<double>(bytes) / 1048576.0);
  return buf;
}

}  // namespace

namespace {

// The plan with every depth map resident (depth_slots 0) or `depth_slots` of them; nullopt
// when it leaves no full-size slot.
std::optional<PhotoCachePlan> PlanWith(const PhotoLayout& layout, size_t depth_layer_bytes,
                                       int depth_slots, size_t budget_bytes) {
  const size_t photos = layout.sizes.size();
  const size_t layer = layout.LayerBytes();
  PhotoCachePlan plan;
  plan.depth_slots = depth_slots;
  plan.depth_bytes =
      depth_layer_bytes * (depth_slots > 0 ? static_cast<size_t>(depth_slots) : photos);
  const size_t left = budget_bytes > plan.depth_bytes ? budget_bytes - plan.depth_bytes : 0;
  // The finest coarse copies within their share (the coarsest are 1 x 1 per photo).
  const int max_shift = std::max(1, layout.levels - 1);
  for (plan.fallback_shift = 1; plan.fallback_shift < max_shift; ++plan.fallback_shift) {
    if (FallbackLayout(layout, plan.fallback_shift).Bytes() <= kFallbackShare * left) break;
  }
  plan.fallback_bytes = FallbackLayout(layout, plan.fallback_shift).Bytes();
  const size_t for_slots = left > plan.fallback_bytes ? left - plan.fallback_bytes : 0;
  plan.slots = static_cast<int>(std::min(photos, for_slots / layer));
  plan.slot_bytes = static_cast<size_t>(plan.slots) * layer;
  if (plan.slots < 1) return std::nullopt;
  return plan;
}

}  // namespace

std::optional<PhotoCachePlan> PlanPhotoCache(const PhotoLayout& layout, size_t depth_layer_bytes,
                                             int candidates, size_t budget_bytes) {
  const size_t photos = layout.sizes.size();
  if (layout.Bytes() + depth_layer_bytes * photos <= budget_bytes) return std::nullopt;
  const int per_frame =
      candidates > 0 ? static_cast<int>(std::min<size_t>(static_cast<size_t>(candidates), photos))
                     : static_cast<int>(photos);
  const std::optional<PhotoCachePlan> resident =
      PlanWith(layout, depth_layer_bytes, 0, budget_bytes);
  if (resident && resident->slots >= per_frame) return resident;
  if (per_frame < static_cast<int>(photos)) {
    const std::optional<PhotoCachePlan> slotted =
        PlanWith(layout, depth_layer_bytes, per_frame, budget_bytes);
    if (slotted && (!resident || slotted->slots > resident->slots)) return slotted;
  }
  if (resident) return resident;
  // The smallest budget that works, to name it (to a KiB).
  const int depth_slots = per_frame < static_cast<int>(photos) ? per_frame : 0;
  size_t low = budget_bytes, high = std::max<size_t>(budget_bytes, 1024) * 2;
  while (!PlanWith(layout, depth_layer_bytes, depth_slots, high)) high *= 2;
  while (high - low > 1024) {
    const size_t mid = low + (high - low) / 2;
    (PlanWith(layout, depth_layer_bytes, depth_slots, mid) ? high : low) = mid;
  }
  const size_t depth =
      depth_layer_bytes * (depth_slots > 0 ? static_cast<size_t>(depth_slots) : photos);
  throw OptionError("gpu_memory_mb",
                    Mib(budget_bytes) + " MiB cannot hold the depth maps of a frame's photos (" +
                        Mib(depth) + " MiB), the photos' coarse copies and one full-size " +
                        "photo (" + Mib(layout.LayerBytes()) + " MiB): at least " + Mib(high) +
                        " MiB");
}

PhotoCache::PhotoCache(const Scene& scene, std::vector<cv::Mat> images, PhotoLayout layout,
                       const PhotoCachePlan& plan, std::vector<cv::Mat> depth_layers,
                       cv::Size depth_size)
    : layout_(std::move(layout)),
      fallback_layout_(FallbackLayout(layout_, plan.fallback_shift)),
      plan_(plan),
      images_(std::move(images)) {
  const size_t n = scene.photos.size();
  HDRIBR_CHECK(layout_.sizes.size() == n && plan.slots >= 1);
  const GLenum format = layout_.is_float ? GL_RGBA16F : GL_RGBA8;
  const float zero[4] = {0, 0, 0, 0};
  fallback_ = MipmappedArray(format, fallback_layout_.width, fallback_layout_.height,
                             static_cast<int>(std::max<size_t>(1, n)), fallback_layout_.levels);
  for (int l = 0; l < fallback_layout_.levels; ++l) {
    glClearTexImage(fallback_.id(), l, GL_RGBA, GL_FLOAT, zero);
  }
  for (size_t i = 0; i < n; ++i) {
    const cv::Mat full = LoadPhotoPixels(scene, images_, layout_, i);
    cv::Mat coarse;
    cv::resize(full, coarse, fallback_layout_.sizes[i], 0, 0, cv::INTER_AREA);
    UploadLayer(fallback_.id(), static_cast<int>(i), coarse);
  }
  glGenerateTextureMipmap(fallback_.id());
  slots_ = MipmappedArray(format, layout_.width, layout_.height, plan.slots, layout_.levels);
  for (int l = 0; l < layout_.levels; ++l) glClearTexImage(slots_.id(), l, GL_RGBA, GL_FLOAT, zero);
  slot_.resize(static_cast<size_t>(plan.slots));
  slot_of_.assign(n, -1);
  slot_map_ = gl::Buffer(std::max<size_t>(1, n) * sizeof(int), nullptr, GL_DYNAMIC_STORAGE_BIT);
  if (plan.depth_slots > 0) {
    HDRIBR_CHECK(depth_layers.size() == n && depth_size.width > 0 && depth_size.height > 0);
    depth_layers_ = std::move(depth_layers);
    depth_slots_ =
        gl::Texture::Create2DArray(GL_R32F, depth_size.width, depth_size.height, plan.depth_slots);
    glClearTexImage(depth_slots_.id(), 0, GL_RED, GL_FLOAT, zero);
    depth_slot_.resize(static_cast<size_t>(plan.depth_slots));
    depth_slot_of_.assign(n, -1);
    const std::vector<int> none(std::max<size_t>(1, n), -1);
    depth_slot_map_ = gl::Buffer(none.size() * sizeof(int), none.data(), GL_DYNAMIC_STORAGE_BIT);
  }
  UploadMap();
  loader_ = std::make_unique<PhotoLoader>(scene, images_, layout_);
}

PhotoCache::~PhotoCache() = default;

void PhotoCache::Request(const std::vector<int>& wanted, bool wait) {
  Collect(loader_->TakeDone());
  if (wanted.size() > slot_.size() && !warned_) {
    spdlog::warn(
        "photo cache: {} candidate photos for {} full-size slots: the others are blended from "
        "their coarse copies (a larger GPU memory budget or fewer candidates avoids it)",
        wanted.size(), slot_.size());
    warned_ = true;
  }
  if (caches_depth() && wanted.size() > depth_slot_.size() && !warned_depth_) {
    spdlog::warn(
        "photo cache: {} candidate photos for {} depth-map slots: the others are left out (a "
        "larger GPU memory budget or fewer candidates avoids it)",
        wanted.size(), depth_slot_.size());
    warned_depth_ = true;
  }
  ++frame_;
  std::vector<bool> is_wanted(slot_of_.size(), false);
  for (int p : wanted) is_wanted[static_cast<size_t>(p)] = true;
  for (int p : wanted) {
    const int s = slot_of_[static_cast<size_t>(p)];
    if (s >= 0) slot_[static_cast<size_t>(s)].last_used = frame_;
  }
  for (int p : wanted) {
    if (slot_of_[static_cast<size_t>(p)] >= 0) continue;
    // A free slot, else the least recently used one holding a photo this frame does not want.
    int best = -1;
    for (size_t s = 0; s < slot_.size(); ++s) {
      const Slot& c = slot_[s];
      if (c.pending || (c.photo >= 0 && is_wanted[static_cast<size_t>(c.photo)])) continue;
      if (best < 0 || c.photo < 0 ||
          (slot_[static_cast<size_t>(best)].photo >= 0 &&
           c.last_used < slot_[static_cast<size_t>(best)].last_used)) {
        best = static_cast<int>(s);
        if (c.photo < 0) break;
      }
    }
    if (best < 0) break;  // every slot holds a wanted photo: the rest stay coarse
    Slot& slot = slot_[static_cast<size_t>(best)];
    if (slot.photo >= 0) {
      slot_of_[static_cast<size_t>(slot.photo)] = -1;
      ++evictions_;
      map_dirty_ = true;
    }
    slot.photo = p;
    slot.pending = true;
    slot.last_used = frame_;
    slot_of_[static_cast<size_t>(p)] = best;
    loader_->Request(p);
    ++in_flight_;
  }
  if (caches_depth()) RequestDepth(wanted, is_wanted);
  if (wait) {
    Settle();
  } else {
    UploadMap();
  }
}

void PhotoCache::RequestDepth(const std::vector<int>& wanted, const std::vector<bool>& is_wanted) {
  for (int p : wanted) {
    const int s = depth_slot_of_[static_cast<size_t>(p)];
    if (s >= 0) depth_slot_[static_cast<size_t>(s)].last_used = frame_;
  }
  bool changed = false;
  for (int p : wanted) {
    if (depth_slot_of_[static_cast<size_t>(p)] >= 0) continue;
    int best = -1;
    for (size_t s = 0; s < depth_slot_.size(); ++s) {
      const Slot& c = depth_slot_[s];
      if (c.photo >= 0 && is_wanted[static_cast<size_t>(c.photo)]) continue;
      if (best < 0 || c.photo < 0 ||
          (depth_slot_[static_cast<size_t>(best)].photo >= 0 &&
           c.last_used < depth_slot_[static_cast<size_t>(best)].last_used)) {
        best = static_cast<int>(s);
        if (c.photo < 0) break;
      }
    }
    if (best < 0) break;  // every depth slot holds a wanted photo
    Slot& slot = depth_slot_[static_cast<size_t>(best)];
    if (slot.photo >= 0) depth_slot_of_[static_cast<size_t>(slot.photo)] = -1;
    slot.photo = p;
    slot.last_used = frame_;
    depth_slot_of_[static_cast<size_t>(p)] = best;
    // The layer's corner; the blend never reads beyond the photo's own size (clamped).
    const cv::Mat& d = depth_layers_[static_cast<size_t>(p)];
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(depth_slots_.id(), 0, 0, 0, best, d.cols, d.rows, 1, GL_RED, GL_FLOAT,
                        d.data);
    changed = true;
  }
  if (changed) {
    std::vector<int> map(std::max<size_t>(1, depth_slot_of_.size()), -1);
    std::copy(depth_slot_of_.begin(), depth_slot_of_.end(), map.begin());
    glNamedBufferSubData(depth_slot_map_.id(), 0, static_cast<GLsizeiptr>(map.size() * sizeof(int)),
                         map.data());
  }
}

void PhotoCache::Settle() {
  if (in_flight_ > 0) Collect(loader_->WaitDone(in_flight_));
  UploadMap();
}

int PhotoCache::Poll() {
  Collect(loader_->TakeDone());
  UploadMap();
  return static_cast<int>(in_flight_);
}

void PhotoCache::Collect(std::vector<LoadedPhoto> loaded) {
  HDRIBR_CHECK(loaded.size() <= in_flight_);
  in_flight_ -= loaded.size();
  const float zero[4] = {0, 0, 0, 0};
  const GLenum format = layout_.is_float ? GL_RGBA16F : GL_RGBA8;
  std::exception_ptr error;  // the first load that failed, rethrown once the others are in
  for (LoadedPhoto& l : loaded) {
    const int s = slot_of_[static_cast<size_t>(l.photo)];
    HDRIBR_CHECK(s >= 0 && slot_[static_cast<size_t>(s)].pending);
    if (l.error) {
      if (!error) error = l.error;
      slot_[static_cast<size_t>(s)] = Slot{};
      slot_of_[static_cast<size_t>(l.photo)] = -1;
      continue;
    }
    // Level 0 of the slot cleared, the photo in its corner and the mipmaps of this layer
    // alone (a one-layer view): the texels the all-resident array holds for the photo.
    glClearTexSubImage(slots_.id(), 0, 0, 0, s, layout_.width, layout_.height, 1, GL_RGBA, GL_FLOAT,
                       zero);
    UploadLayer(slots_.id(), s, l.pixels);
    GLuint view = 0;
    glGenTextures(1, &view);
    glTextureView(view, GL_TEXTURE_2D_ARRAY, slots_.id(), format, 0,
                  static_cast<GLuint>(layout_.levels), static_cast<GLuint>(s), 1);
    glGenerateTextureMipmap(view);
    glDeleteTextures(1, &view);
    slot_[static_cast<size_t>(s)].pending = false;
    ++loads_;
    map_dirty_ = true;
  }
  if (error) std::rethrow_exception(error);
}

void PhotoCache::UploadMap() {
  if (!map_dirty_) return;
  std::vector<int> map(std::max<size_t>(1, slot_of_.size()), -1);
  for (size_t p = 0; p < slot_of_.size(); ++p) {
    const int s = slot_of_[p];
    if (s >= 0 && !slot_[static_cast<size_t>(s)].pending) map[p] = s;
  }
  glNamedBufferSubData(slot_map_.id(), 0, static_cast<GLsizeiptr>(map.size() * sizeof(int)),
                       map.data());
  map_dirty_ = false;
}

PhotoResidency PhotoCache::residency() const {
  PhotoResidency r;
  r.cached = true;
  r.photos = static_cast<int>(slot_of_.size());
  r.slots = plan_.slots;
  for (const Slot& s : slot_) {
    if (s.photo >= 0 && !s.pending) ++r.full_size;
  }
  r.pending = static_cast<int>(in_flight_);
  r.fallback_divisor = 1 << plan_.fallback_shift;
  r.depth_slots = plan_.depth_slots;
  r.depth_bytes = plan_.depth_bytes;
  r.resident_bytes = plan_.fallback_bytes + plan_.slot_bytes + plan_.depth_bytes;
  r.total_bytes = layout_.Bytes();
  r.loads = loads_;
  r.evictions = evictions_;
  return r;
}

}  // namespace hdribr::render
