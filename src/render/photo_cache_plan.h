// The CPU side of the photo cache (photo_cache.h), without GL: how a cache fits a GPU memory
// budget, the layouts of its coarse copies and slots, how the slots' memory is split between
// their sizes, and which slot a photo takes.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "render/photo_layout.h"

namespace hdribr::render {

// Share of the budget left after the depth maps that the coarse copies may use.
inline constexpr double kFallbackShare = 0.25;
// Slot sizes: full size and 1 / 2^t of it for t < kSlotTiers (finer than the coarse copies).
inline constexpr int kSlotTiers = 3;

// Throws OptionError("gpu_memory_mb", ...) unless `mb` is finite and >= 0 (0 = automatic).
void CheckGpuMemoryMb(double mb);

// How a cache fits a budget: the coarse copies' size, the number of slots per size and of
// depth-map slots.
struct PhotoCachePlan {
  int fallback_shift = 1;  // coarse copies at 1 / 2^shift of the photos' size
  int slots = 0;           // full-size slots that the slots' memory holds (the first split)
  size_t fallback_bytes = 0;
  size_t slot_bytes = 0;   // the full-size slots
  size_t pool_bytes = 0;   // what the slots of every size may use
  int depth_slots = 0;     // 0: every depth map resident
  size_t depth_bytes = 0;  // the depth maps resident (all, or the depth slots)
};

// The plan for photos of `layout` and one depth map of `depth_layer_bytes` per photo within
// `budget_bytes`, for frames of at most `candidates` photos (0 = every photo); nullopt when
// everything fits as it is. The depth maps stay resident when the rest leaves a full-size slot
// per candidate; else, with fewer candidates than photos, they get a slot per candidate when
// that leaves more slots. Throws OptionError("gpu_memory_mb", ...) when the budget cannot hold the
// depth maps, the coarse copies and one full-size slot.
std::optional<PhotoCachePlan> PlanPhotoCache(const PhotoLayout& layout, size_t depth_layer_bytes,
                                             int candidates, size_t budget_bytes);

// The layout of the coarse copies: every photo's size divided by 2^shift.
PhotoLayout FallbackLayout(const PhotoLayout& full, int shift);
// The layout of the slots of 1 / 2^t of the full size: the full array's levels t and coarser.
PhotoLayout TierLayout(const PhotoLayout& full, int t);
// Bytes of counts[t] slots of 1 / 2^t of the full size, with the full-size staging layer when
// a reduced slot is among them.
size_t SplitBytes(const PhotoLayout& full, const std::vector<int>& counts);

// A better split of the slots' memory (`pool_bytes`) between the sizes than `current` (slots
// per size) for the wanted photos of known level, need[t] of them needing 1 / 2^t of the full
// size (t the last size: that or coarser): one that gives more of them a slot, or as many a
// slot and more of them one at their level (a photo can take a slot of any finer size). Empty
// when `current` serves them as well. `photos` bounds the slots.
std::vector<int> BetterSplit(const PhotoLayout& full, size_t pool_bytes, int photos,
                             const std::vector<int>& need, const std::vector<int>& current);

// A slot of the cache: the photo it holds (-1: free), whether its load is in flight, and the
// frame that last wanted it.
struct CacheSlot {
  int photo = -1;
  bool pending = false;
  long last_used = -1;
};

// How a slot may be taken for a photo, best first.
enum class SlotUse { kFree, kEvict, kLastResort, kNone };

// The slot to give a photo: the first that `use` calls free, else the least recently used it
// lets evict, else the first last resort; -1 when `use` says none.
int PickSlot(const std::vector<CacheSlot>& slots,
             const std::function<SlotUse(const CacheSlot&)>& use);

}  // namespace hdribr::render
