// Photos beyond the GPU memory budget: every photo stays resident as a coarse copy (the
// fallback array), and a fixed number of full-size slots hold the photos the frames need,
// loaded on a worker thread (photo_loader.h) and evicted least recently used first. The blend
// pass samples a photo's slot when it is resident, else its coarse copy: never a hole.
#pragma once

#include <epoxy/gl.h>

#include <cstddef>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "core/scene.h"
#include "gl/objects.h"
#include "render/photo_textures.h"

namespace hdribr::render {

// The GPU memory budget when none is given and the driver reports none, MiB.
inline constexpr double kDefaultGpuMemoryMb = 2048.0;
// Share of the budget left after the depth maps that the coarse copies may use.
inline constexpr double kFallbackShare = 0.25;

// Throws OptionError("gpu_memory_mb", ...) unless `mb` is finite and >= 0 (0 = automatic).
void CheckGpuMemoryMb(double mb);
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
  int slots = 0;             // full-size slots (the photos when not cached)
  int pending = 0;           // loads in flight
  int fallback_divisor = 1;  // the coarse copies' size is the photos' divided by this
  int depth_slots = 0;       // depth-map slots; 0 = every depth map resident
  size_t loads = 0;          // photos loaded into slots so far
  size_t evictions = 0;      // photos evicted from their slot so far
};

// How a cache fits a budget: the coarse copies' size, the number of full-size slots and of
// depth-map slots.
struct PhotoCachePlan {
  int fallback_shift = 1;  // coarse copies at 1 / 2^shift of the photos' size
  int slots = 0;
  size_t fallback_bytes = 0;
  size_t slot_bytes = 0;   // all slots
  int depth_slots = 0;     // 0: every depth map resident
  size_t depth_bytes = 0;  // the depth maps resident (all, or the depth slots)
};

// The plan for photos of `layout` and one depth map of `depth_layer_bytes` per photo within
// `budget_bytes`, for frames of at most `candidates` photos (0 = every photo); nullopt when
// everything fits as it is. The depth maps stay resident when the rest leaves a slot per
// candidate; else, with fewer candidates than photos, they get a slot per candidate when that
// leaves more slots. Throws OptionError("gpu_memory_mb", ...) when the budget cannot hold the
// depth maps, the coarse copies and one full-size slot.
std::optional<PhotoCachePlan> PlanPhotoCache(const PhotoLayout& layout, size_t depth_layer_bytes,
                                             int candidates, size_t budget_bytes);

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

  // GL thread, before a frame: uploads the photos loaded since the last call, then gives the
  // `wanted` photos (indices into scene.photos) slots, evicting the least recently used photo
  // not wanted, and queues their loads; as many as there are slots, those already resident
  // first. With `wait`, returns once they are uploaded. Rethrows a load's InputError. With
  // depth slots, the wanted photos' depth maps are uploaded at once (CPU copies, no decoding);
  // a wanted photo beyond the depth slots is seen by no pixel.
  void Request(const std::vector<int>& wanted, bool wait);
  // Waits for every queued load and uploads it.
  void Settle();
  // GL thread, between frames: uploads the photos loaded since the last call, without waiting;
  // returns the loads still in flight.
  int Poll();

  const PhotoLayout& layout() const { return layout_; }
  const PhotoLayout& fallback_layout() const { return fallback_layout_; }
  GLuint slots_texture() const { return slots_.id(); }
  GLuint fallback_texture() const { return fallback_.id(); }
  // int per photo: its slot when resident at full size, else -1.
  GLuint slot_map() const { return slot_map_.id(); }
  bool caches_depth() const { return plan_.depth_slots > 0; }
  // With depth slots: their R32F array, and per photo (int) its depth slot, -1 when none.
  GLuint depth_texture() const { return depth_slots_.id(); }
  GLuint depth_slot_map() const { return depth_slot_map_.id(); }
  // The fields of PhotoResidency this cache knows (not the depth maps).
  PhotoResidency residency() const;

 private:
  struct Slot {
    int photo = -1;
    bool pending = false;
    long last_used = -1;  // the frame that last wanted it
  };
  void Collect(std::vector<LoadedPhoto> loaded);
  void UploadMap();
  void RequestDepth(const std::vector<int>& wanted, const std::vector<bool>& is_wanted);

  PhotoLayout layout_, fallback_layout_;
  PhotoCachePlan plan_;
  std::vector<cv::Mat> images_;
  MipmappedArray fallback_;
  MipmappedArray slots_;
  gl::Buffer slot_map_;
  std::vector<Slot> slot_;
  std::vector<int> slot_of_;           // per photo, -1 when none
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
