// The workspace's cache of the photos' depth maps (docs/formats.md, "Depth map cache"): one
// file per key, holding every photo's depth map. File I/O only; the renderer computes the key
// (render/photo_depth_key.h) and fills its textures (render/photo_depth_maps.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

namespace hdribr {

// Cache files kept per folder: the most recently used ones (see PruneDepthMapCache).
inline constexpr size_t kDepthMapCacheKeep = 3;

// The cache folder of the workspace at `workspace`: <workspace>/cache/depth_maps.
std::filesystem::path DepthMapCacheDir(const std::filesystem::path& workspace);

// The file of `key` in the cache folder `dir`: <dir>/<key as 16 hex digits>.bin.
std::filesystem::path DepthMapCacheFile(const std::filesystem::path& dir, std::uint64_t key);

// Writes `layers` (CV_32FC1 each) under `key` to `file` atomically (io/atomic_file.h),
// creating its folder; throws InputError naming the file when it cannot.
void WriteDepthMapCache(const std::filesystem::path& file, std::uint64_t key,
                        const std::vector<cv::Mat>& layers);

// The layers of `file` (CV_32FC1), which must hold `key` and layers of exactly `sizes`.
// Throws InputError naming the file and the problem: missing, not a cache file, another
// version, key or sizes, truncated, checksum mismatch.
std::vector<cv::Mat> ReadDepthMapCache(const std::filesystem::path& file, std::uint64_t key,
                                       const std::vector<cv::Size>& sizes);

// Marks `file` as just used (its modification time); false when that fails (read-only).
bool TouchDepthMapCache(const std::filesystem::path& file);

// Keeps the `keep` most recently used cache files of `dir` (newest modification times) and
// removes the others, and leftovers of interrupted writes older than an hour. Never throws;
// returns the number of files removed.
int PruneDepthMapCache(const std::filesystem::path& dir, size_t keep = kDepthMapCacheKeep);

}  // namespace hdribr
