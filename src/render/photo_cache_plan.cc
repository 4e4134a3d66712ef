#include "render/photo_cache_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <utility>

#include "core/error.h"

namespace hdribr::render {
namespace {

// `bytes` in MiB, two decimals.
std::string Mib(size_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f", static_cast<double>(bytes) / 1048576.0);
  return buf;
}

// The plan with every depth map resident (depth_slots 0) or `depth_slots` of them; nullopt
// when it leaves no full-size slot.
std::optional<PhotoCachePlan> PlanWith(const PhotoLayout& layout, size_t depth_layer_bytes,
                                       int depth_slots, size_t budget_bytes) {
  const size_t photos = layout.sizes.size();
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
  plan.slots = static_cast<int>(std::min(photos, for_slots / layout.LayerBytes()));
  plan.slot_bytes = static_cast<size_t>(plan.slots) * layout.LayerBytes();
  plan.pool_bytes = for_slots;
  if (plan.slots < 1) return std::nullopt;
  return plan;
}

}  // namespace

void CheckGpuMemoryMb(double mb) {
  if (!std::isfinite(mb) || mb < 0) {
    char text[32];
    std::snprintf(text, sizeof(text), "%g", mb);
    throw OptionError("gpu_memory_mb",
                      std::string("must be >= 0 MiB (0 = from the device), got ") + text);
  }
}

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

PhotoLayout TierLayout(const PhotoLayout& full, int t) {
  PhotoLayout r;
  r.is_float = full.is_float;
  r.width = std::max(1, full.width >> t);
  r.height = std::max(1, full.height >> t);
  r.levels = full.levels - t;
  return r;
}

size_t SplitBytes(const PhotoLayout& full, const std::vector<int>& counts) {
  size_t bytes = 0;
  bool reduced = false;
  for (size_t t = 0; t < counts.size(); ++t) {
    bytes += static_cast<size_t>(counts[t]) * TierLayout(full, static_cast<int>(t)).LayerBytes();
    reduced = reduced || (t > 0 && counts[t] > 0);
  }
  return bytes + (reduced ? full.LayerBytes() : 0);
}

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

std::vector<int> BetterSplit(const PhotoLayout& full, size_t pool_bytes, int photos,
                             const std::vector<int>& need, const std::vector<int>& current) {
  const int tiers = static_cast<int>(need.size());
  // What a split gives the wanted photos of known level: how many get a slot at all (the others
  // are blended from their coarse copies), then how many at their level (photos that need
  // level t can take a slot of any finer size: filled from the finest need).
  const int known = std::accumulate(need.begin(), need.end(), 0);
  auto placed = [&](const std::vector<int>& counts) {
    int n = 0, spare = 0;
    for (size_t t = 0; t < counts.size(); ++t) {
      spare += counts[t];
      const int take = std::min(spare, need[t]);
      n += take;
      spare -= take;
    }
    return std::make_pair(std::min(known, std::accumulate(counts.begin(), counts.end(), 0)), n);
  };
  if (placed(current).second == known) return {};
  // A slot per photo at its level; over the memory, the finest move one size down; what is left
  // goes to full-size slots (they serve every level), then to the smaller ones.
  std::vector<int> split = need;
  for (int t = 0; t < tiers && SplitBytes(full, split) > pool_bytes; ++t) {
    while (split[static_cast<size_t>(t)] > 0 && SplitBytes(full, split) > pool_bytes) {
      --split[static_cast<size_t>(t)];
      if (t + 1 < tiers) ++split[static_cast<size_t>(t + 1)];
    }
  }
  for (int t = 0; t < tiers; ++t) {
    while (std::accumulate(split.begin(), split.end(), 0) < photos) {
      ++split[static_cast<size_t>(t)];
      if (SplitBytes(full, split) <= pool_bytes) continue;
      --split[static_cast<size_t>(t)];
      break;
    }
  }
  if (std::accumulate(split.begin(), split.end(), 0) == 0 || placed(split) <= placed(current)) {
    return {};
  }
  return split;
}

int PickSlot(const std::vector<CacheSlot>& slots,
             const std::function<SlotUse(const CacheSlot&)>& use) {
  constexpr int kNone = static_cast<int>(SlotUse::kNone);
  constexpr int kEvict = static_cast<int>(SlotUse::kEvict);
  int pick = -1, rank = kNone;
  for (size_t s = 0; s < slots.size() && rank > 0; ++s) {
    const int r = static_cast<int>(use(slots[s]));
    if (r < rank || (r == rank && r == kEvict &&
                     slots[s].last_used < slots[static_cast<size_t>(pick)].last_used)) {
      pick = static_cast<int>(s);
      rank = r;
    }
  }
  return rank < kNone ? pick : -1;
}

}  // namespace hdribr::render
