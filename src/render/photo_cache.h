// Photos beyond the GPU memory budget: every photo stays resident as a coarse copy (the
// fallback array), and slots hold the photos the frames need from the mip level the view needs
// on (full-size slots, and slots of half and a quarter of the size that hold a photo's levels
// from 1 or 2 on), loaded on a worker thread (photo_loader.h) and evicted least recently used
// first. The blend pass samples a photo's slot when it is resident, else its coarse copy: never
// a hole; it reports the finest level it sampled of each photo, which places the photos of the
// next frame and splits the slots' memory between the sizes.
#pragma once

#include <epoxy/gl.h>

#include <cstddef>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "core/scene.h"
#include "gl/objects.h"
#include "render/photo_cache_plan.h"
#include "render/photo_textures.h"

namespace hdribr::render {

// The GPU memory budget when none is given and the driver reports none, MiB.
inline constexpr double kDefaultGpuMemoryMb = 2048.0;
// Needs a current GL context. The budget in bytes for `mb` (MiB, > 0), or for 0: three
// quarters of the free video memory that GL_NVX_gpu_memory_info or GL_ATI_meminfo reports,
// else kDefaultGpuMemoryMb.
size_t GpuBudgetBytes(double mb);

// What the photo textures and depth maps hold on the GPU against what all of them need.
struct PhotoResidency {
  bool cached = false;        // false: every photo resident at full size (within the budget)
  size_t budget_bytes = 0;    // the GPU memory budget
  size_t resident_bytes = 0;  // photo textures (slots and coarse copies) + depth maps
  size_t total_bytes = 0;     // every photo at full size with mipmaps + depth maps
  size_t depth_bytes = 0;     // the depth maps resident (all, or the depth slots)
  int photos = 0;
  int full_size = 0;         // photos resident at full size
  int reduced = 0;           // photos resident from mip level 1 or 2 on (reduced slots)
  int slots = 0;             // full-size slots (the photos when not cached)
  int reduced_slots = 0;     // slots of 1/2 and 1/4 of the full size
  int pending = 0;           // loads in flight
  int fallback_divisor = 1;  // the coarse copies' size is the photos' divided by this
  int depth_slots = 0;       // depth-map slots; 0 = every depth map resident
  size_t loads = 0;          // photos loaded into slots so far
  size_t evictions = 0;      // photos evicted from their slot so far
};

class PhotoLoader;
struct LoadedPhoto;

class PhotoCache {
 public:
  // Needs a current GL context. Reads every photo once (`images` when not empty, else the
  // files) to build the coarse copies; keeps `images` for the loads and a reference to
  // `scene`, which must outlive the cache. With plan.depth_slots, `depth_layers` are the
  // photos' depth maps (PhotoDepthMaps::TakeLayers), for an R32F array of `depth_size`.
  PhotoCache(const Scene& scene, std::vector<cv::Mat> images, PhotoLayout layout,
             const PhotoCachePlan& plan, std::vector<cv::Mat> depth_layers = {},
             cv::Size depth_size = {});
  ~PhotoCache();
  PhotoCache(const PhotoCache&) = delete;
  PhotoCache& operator=(const PhotoCache&) = delete;

  // GL thread, before a frame: uploads the photos loaded since the last call, reads the level
  // of detail the last frame sampled each photo at, then gives the `wanted` photos (indices
  // into scene.photos) slots of the size that level needs (a photo never sampled: full size),
  // finest needs first, evicting the least recently used photo not wanted, and queues their
  // loads; those already resident at a level fine enough stay. When another split of the slots'
  // memory between sizes serves the wanted photos of known level better (Resplit), the slots
  // are rebuilt (every slot emptied; without `wait`, at most once in kResplitFrames frames).
  // With `wait`, returns once they are uploaded. Rethrows a load's InputError. With depth slots,
  // the wanted photos' depth maps are uploaded at once (CPU copies, no decoding); a wanted photo
  // beyond the depth slots is seen by no pixel.
  void Request(const std::vector<int>& wanted, bool wait);
  // GL thread, after a frame: reads the levels it sampled; when one of its photos sampled
  // below the level of its slot (a coarser copy than the view needs), requests the frame's
  // photos again and returns true (the frame would change if drawn again).
  bool Refine(bool wait);
  // Waits for every queued load and uploads it.
  void Settle();
  // GL thread, between frames: uploads the photos loaded since the last call, refines the last
  // frame's slots without waiting; returns the loads still in flight.
  int Poll();

  const PhotoLayout& layout() const { return layout_; }
  const PhotoLayout& fallback_layout() const { return fallback_layout_; }
  GLuint slots_texture() const { return tiers_[0].texture.id(); }
  // The reduced slots of 1 / 2^t of the full size (t in [1, tiers())); 0 when there are none.
  GLuint tier_texture(int t) const { return t < tiers() ? tiers_[t].texture.id() : 0; }
  // Slot sizes: 1 (full size only) to kSlotTiers.
  int tiers() const { return static_cast<int>(tiers_.size()); }
  GLuint fallback_texture() const { return fallback_.id(); }
  // int per photo: its slot when resident, t << 24 | layer (t: the slot's size 1 / 2^t), else -1.
  GLuint slot_map() const { return slot_map_.id(); }
  // int per photo, written by the blend: the finest mip level it sampled of the photo
  // (kNotSampled when none); cleared by Request.
  GLuint feedback() const { return feedback_.id(); }
  static constexpr int kNotSampled = 127;
  // Frames between two rebuilds of the slots without waiting (the viewer): no thrashing.
  static constexpr long kResplitFrames = 16;
  bool caches_depth() const { return plan_.depth_slots > 0; }
  // With depth slots: their R32F array, and per photo (int) its depth slot, -1 when none.
  GLuint depth_texture() const { return depth_slots_.id(); }
  GLuint depth_slot_map() const { return depth_slot_map_.id(); }
  // The fields of PhotoResidency this cache knows (not the depth maps).
  PhotoResidency residency() const;

 private:
  using Slot = CacheSlot;
  // The slots of one size: 1 / 2^t of the full size, the full array's mip levels t and coarser.
  struct Tier {
    MipmappedArray texture;
    int width = 1, height = 1, levels = 1;
    std::vector<Slot> slot;
  };
  struct Where {
    int tier = -1, slot = -1;  // -1: coarse copy only
  };
  void Collect(std::vector<LoadedPhoto> loaded);
  void UploadMap();
  // Gives the wanted photos slots (Request); true when it queued a load.
  bool Place(const std::vector<int>& wanted);
  // Rebuilds the slots when another split of their memory between sizes gives more wanted
  // photos of known level a slot, or as many a slot and more of them one at their level
  // (Request); true when it did.
  bool Resplit(const std::vector<int>& wanted, bool wait);
  // Empties every slot and allocates counts[t] slots of 1 / 2^t of the full size.
  void Build(const std::vector<int>& counts);
  void ClearFeedback();
  void RequestDepth(const std::vector<int>& wanted, const std::vector<bool>& is_wanted);
  // Reads the blend's feedback into level_of_ once per frame; true when a photo sampled a level
  // finer than its slot holds.
  bool ReadFeedback();
  // Frees photo p's slot (its map entry first: the blend never samples a slot being refilled).
  void Evict(int p);
  Slot& SlotAt(const Where& w) {
    return tiers_[static_cast<size_t>(w.tier)].slot[static_cast<size_t>(w.slot)];
  }

  PhotoLayout layout_, fallback_layout_;
  PhotoCachePlan plan_;
  std::vector<cv::Mat> images_;
  MipmappedArray fallback_;
  std::vector<Tier> tiers_;
  MipmappedArray staging_;  // one full-size layer: a photo's mipmaps before a reduced slot
  gl::Buffer slot_map_;
  gl::Buffer feedback_;
  bool feedback_unread_ = false;  // a frame was drawn since the feedback was last read
  std::vector<int> last_wanted_;
  std::vector<Where> slot_of_;         // per photo
  std::vector<int> level_of_;          // per photo: the finest level last sampled (-1 before any)
  size_t slot_bytes_ = 0;              // the slots allocated now, with the staging layer
  long last_split_ = -1;               // the frame of the last rebuild (-1: none yet)
  std::vector<cv::Mat> depth_layers_;  // with depth slots: every photo's depth map (CPU)
  gl::Texture depth_slots_;
  gl::Buffer depth_slot_map_;
  std::vector<Slot> depth_slot_;
  std::vector<int> depth_slot_of_;
  bool map_dirty_ = true;
  bool warned_ = false;        // about more candidates than slots
  bool warned_depth_ = false;  // about more candidates than depth slots
  long frame_ = 0;
  size_t in_flight_ = 0;
  size_t loads_ = 0, evictions_ = 0;
  std::unique_ptr<PhotoLoader> loader_;  // last: its thread stops before the rest goes
};

}  // namespace hdribr::render
