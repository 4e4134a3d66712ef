#include "render/photo_cache.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <exception>
#include <opencv2/imgproc.hpp>
#include <string>

#include "core/error.h"
#include "render/photo_loader.h"

namespace hdribr::render {

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
  slot_of_.assign(n, Where{});
  level_of_.assign(n, -1);
  tiers_.resize(static_cast<size_t>(std::min({kSlotTiers, plan.fallback_shift, layout_.levels})));
  std::vector<int> counts(tiers_.size(), 0);
  counts[0] = plan.slots;
  Build(counts);
  slot_map_ = gl::Buffer(std::max<size_t>(1, n) * sizeof(int), nullptr, GL_DYNAMIC_STORAGE_BIT);
  feedback_ = gl::Buffer(std::max<size_t>(1, n) * sizeof(int), nullptr, GL_DYNAMIC_STORAGE_BIT);
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

void PhotoCache::Build(const std::vector<int>& counts) {
  HDRIBR_CHECK(counts.size() == tiers_.size() && in_flight_ == 0);
  for (size_t p = 0; p < slot_of_.size(); ++p) {
    if (slot_of_[p].tier >= 0) ++evictions_;
    slot_of_[p] = Where{};
  }
  const GLenum format = layout_.is_float ? GL_RGBA16F : GL_RGBA8;
  const float zero[4] = {0, 0, 0, 0};
  bool reduced = false;
  for (size_t t = 0; t < tiers_.size(); ++t) {
    Tier& tier = tiers_[t];
    const PhotoLayout tl = TierLayout(layout_, static_cast<int>(t));
    tier.width = tl.width;
    tier.height = tl.height;
    tier.levels = tl.levels;
    tier.slot.assign(static_cast<size_t>(counts[t]), Slot{});
    tier.texture = MipmappedArray();
    if (counts[t] == 0) continue;
    reduced = reduced || t > 0;
    tier.texture = MipmappedArray(format, tier.width, tier.height, counts[t], tier.levels);
    for (int l = 0; l < tier.levels; ++l) {
      glClearTexImage(tier.texture.id(), l, GL_RGBA, GL_FLOAT, zero);
    }
  }
  staging_ = reduced ? MipmappedArray(format, layout_.width, layout_.height, 1, layout_.levels)
                     : MipmappedArray();
  slot_bytes_ = SplitBytes(layout_, counts);
  HDRIBR_CHECK(slot_bytes_ <= plan_.pool_bytes);
  map_dirty_ = true;
}

bool PhotoCache::Resplit(const std::vector<int>& wanted, bool wait) {
  if (in_flight_ > 0 || (!wait && last_split_ >= 0 && frame_ - last_split_ < kResplitFrames)) {
    return false;
  }
  const int tiers = this->tiers();
  if (tiers < 2) return false;
  std::vector<int> need(static_cast<size_t>(tiers), 0);
  for (int p : wanted) {
    const int level = level_of_[static_cast<size_t>(p)];
    if (level >= 0) ++need[static_cast<size_t>(std::min(level, tiers - 1))];
  }
  std::vector<int> current(static_cast<size_t>(tiers));
  for (size_t t = 0; t < current.size(); ++t) current[t] = static_cast<int>(tiers_[t].slot.size());
  const std::vector<int> split =
      BetterSplit(layout_, plan_.pool_bytes, static_cast<int>(slot_of_.size()), need, current);
  if (split.empty()) return false;
  Build(split);
  last_split_ = frame_;
  return true;
}

void PhotoCache::Request(const std::vector<int>& wanted, bool wait) {
  Collect(loader_->TakeDone());
  ReadFeedback();
  size_t slots = 0;
  for (const Tier& tier : tiers_) slots += tier.slot.size();
  if (wanted.size() > slots && !warned_) {
    spdlog::warn(
        "photo cache: {} candidate photos for {} slots: the others are blended from their "
        "coarse copies (a larger GPU memory budget or fewer candidates avoids it)",
        wanted.size(), slots);
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
  last_wanted_ = wanted;
  Resplit(wanted, wait);
  for (int p : wanted) {
    const Where& w = slot_of_[static_cast<size_t>(p)];
    if (w.tier >= 0) SlotAt(w).last_used = frame_;
  }
  Place(wanted);
  if (caches_depth()) {
    std::vector<bool> is_wanted(slot_of_.size(), false);
    for (int p : wanted) is_wanted[static_cast<size_t>(p)] = true;
    RequestDepth(wanted, is_wanted);
  }
  ClearFeedback();
  if (wait) {
    Settle();
  } else {
    UploadMap();
  }
}

bool PhotoCache::Place(const std::vector<int>& wanted) {
  const int tiers = this->tiers();
  std::vector<bool> is_wanted(slot_of_.size(), false), placed(slot_of_.size(), false);
  for (int p : wanted) is_wanted[static_cast<size_t>(p)] = true;
  // The tier photo p asks for: the coarsest whose levels hold the finest level it was sampled at.
  auto desired = [&](int p) { return std::clamp(level_of_[static_cast<size_t>(p)], 0, tiers - 1); };
  std::vector<int> order = wanted;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return desired(a) < desired(b); });
  bool changed = false;
  for (int p : order) {
    placed[static_cast<size_t>(p)] = true;
    const int need = desired(p);
    const Where held = slot_of_[static_cast<size_t>(p)];
    if (held.tier >= 0 && (held.tier <= need || SlotAt(held).pending)) continue;
    // The tier it needs, then finer ones (the same pixels), then coarser ones than it needs but
    // finer than what it has (sharper than its coarse copy).
    std::vector<int> tries;
    for (int t = need; t >= 0; --t) tries.push_back(t);
    for (int t = need + 1; t < tiers; ++t) tries.push_back(t);
    Where best;
    for (int t : tries) {
      if (held.tier >= 0 && t >= held.tier) continue;
      // A free slot, else the least recently used one holding a photo this frame does not
      // want, else one holding a wanted photo not placed yet that needs a coarser tier.
      const int pick = PickSlot(tiers_[static_cast<size_t>(t)].slot, [&](const CacheSlot& c) {
        if (c.pending) return SlotUse::kNone;
        if (c.photo < 0) return SlotUse::kFree;
        const size_t q = static_cast<size_t>(c.photo);
        if (!is_wanted[q]) return SlotUse::kEvict;
        return !placed[q] && desired(c.photo) > t ? SlotUse::kLastResort : SlotUse::kNone;
      });
      if (pick >= 0) {
        best = Where{t, pick};
        break;
      }
    }
    if (best.tier < 0) continue;  // stays where it is, or on its coarse copy
    if (held.tier >= 0) Evict(p);
    Slot& slot = SlotAt(best);
    if (slot.photo >= 0) Evict(slot.photo);
    slot.photo = p;
    slot.pending = true;
    slot.last_used = frame_;
    slot_of_[static_cast<size_t>(p)] = best;
    loader_->Request(p);
    ++in_flight_;
    changed = true;
  }
  return changed;
}

void PhotoCache::Evict(int p) {
  Where& w = slot_of_[static_cast<size_t>(p)];
  SlotAt(w) = Slot{};
  w = Where{};
  ++evictions_;
  map_dirty_ = true;
}

void PhotoCache::ClearFeedback() {
  const int none = kNotSampled;
  glClearNamedBufferData(feedback_.id(), GL_R32I, GL_RED_INTEGER, GL_INT, &none);
  feedback_unread_ = true;
}

bool PhotoCache::ReadFeedback() {
  if (!feedback_unread_) return false;
  feedback_unread_ = false;
  std::vector<int> sampled(std::max<size_t>(1, slot_of_.size()));
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(feedback_.id(), 0, static_cast<GLsizeiptr>(sampled.size() * sizeof(int)),
                          sampled.data());
  bool finer = false;
  for (size_t p = 0; p < slot_of_.size(); ++p) {
    if (sampled[p] == kNotSampled) continue;
    level_of_[p] = std::max(0, sampled[p]);
    const Where& w = slot_of_[p];
    const int has = w.tier >= 0 && !SlotAt(w).pending ? w.tier : plan_.fallback_shift;
    if (sampled[p] < has) finer = true;
  }
  return finer;
}

bool PhotoCache::Refine(bool wait) {
  if (!ReadFeedback()) return false;
  const bool rebuilt = Resplit(last_wanted_, wait);
  if (!Place(last_wanted_) && !rebuilt) return false;
  ClearFeedback();
  if (wait) {
    Settle();
  } else {
    UploadMap();
  }
  return true;
}

void PhotoCache::RequestDepth(const std::vector<int>& wanted, const std::vector<bool>& is_wanted) {
  for (int p : wanted) {
    const int s = depth_slot_of_[static_cast<size_t>(p)];
    if (s >= 0) depth_slot_[static_cast<size_t>(s)].last_used = frame_;
  }
  bool changed = false;
  for (int p : wanted) {
    if (depth_slot_of_[static_cast<size_t>(p)] >= 0) continue;
    // A free slot, else the least recently used one holding a photo this frame does not want.
    const int best = PickSlot(depth_slot_, [&](const CacheSlot& c) {
      if (c.photo < 0) return SlotUse::kFree;
      return is_wanted[static_cast<size_t>(c.photo)] ? SlotUse::kNone : SlotUse::kEvict;
    });
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
  if (in_flight_ == 0) Refine(false);
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
    const Where w = slot_of_[static_cast<size_t>(l.photo)];
    HDRIBR_CHECK(w.tier >= 0 && SlotAt(w).pending);
    if (l.error) {
      if (!error) error = l.error;
      SlotAt(w) = Slot{};
      slot_of_[static_cast<size_t>(l.photo)] = Where{};
      continue;
    }
    // Level 0 cleared, the photo in its corner and the mipmaps of this layer alone (a one-layer
    // view): the texels the all-resident array holds for the photo. A reduced slot takes
    // levels t and coarser of them from the staging layer.
    const Tier& tier = tiers_[static_cast<size_t>(w.tier)];
    const GLuint target = w.tier == 0 ? tier.texture.id() : staging_.id();
    const int layer = w.tier == 0 ? w.slot : 0;
    glClearTexSubImage(target, 0, 0, 0, layer, layout_.width, layout_.height, 1, GL_RGBA, GL_FLOAT,
                       zero);
    UploadLayer(target, layer, l.pixels);
    GLuint view = 0;
    glGenTextures(1, &view);
    glTextureView(view, GL_TEXTURE_2D_ARRAY, target, format, 0, static_cast<GLuint>(layout_.levels),
                  static_cast<GLuint>(layer), 1);
    glGenerateTextureMipmap(view);
    glDeleteTextures(1, &view);
    for (int k = 0; w.tier > 0 && k < tier.levels; ++k) {
      const int level = w.tier + k;
      glCopyImageSubData(staging_.id(), GL_TEXTURE_2D_ARRAY, level, 0, 0, 0, tier.texture.id(),
                         GL_TEXTURE_2D_ARRAY, k, 0, 0, w.slot, std::max(1, layout_.width >> level),
                         std::max(1, layout_.height >> level), 1);
    }
    SlotAt(w).pending = false;
    ++loads_;
    map_dirty_ = true;
  }
  if (error) std::rethrow_exception(error);
}

void PhotoCache::UploadMap() {
  if (!map_dirty_) return;
  std::vector<int> map(std::max<size_t>(1, slot_of_.size()), -1);
  for (size_t p = 0; p < slot_of_.size(); ++p) {
    const Where& w = slot_of_[p];
    if (w.tier >= 0 && !SlotAt(w).pending) map[p] = w.tier << 24 | w.slot;
  }
  glNamedBufferSubData(slot_map_.id(), 0, static_cast<GLsizeiptr>(map.size() * sizeof(int)),
                       map.data());
  map_dirty_ = false;
}

PhotoResidency PhotoCache::residency() const {
  PhotoResidency r;
  r.cached = true;
  r.photos = static_cast<int>(slot_of_.size());
  r.slots = static_cast<int>(tiers_[0].slot.size());
  for (size_t t = 0; t < tiers_.size(); ++t) {
    for (const Slot& s : tiers_[t].slot) {
      if (s.photo >= 0 && !s.pending) ++(t == 0 ? r.full_size : r.reduced);
    }
    if (t > 0) r.reduced_slots += static_cast<int>(tiers_[t].slot.size());
  }
  r.pending = static_cast<int>(in_flight_);
  r.fallback_divisor = 1 << plan_.fallback_shift;
  r.depth_slots = plan_.depth_slots;
  r.depth_bytes = plan_.depth_bytes;
  r.resident_bytes = plan_.fallback_bytes + slot_bytes_ + plan_.depth_bytes;
  r.total_bytes = layout_.Bytes();
  r.loads = loads_;
  r.evictions = evictions_;
  return r;
}

}  // namespace hdribr::render
