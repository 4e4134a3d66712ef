#include "io/depth_map_cache.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>

#include "core/error.h"
#include "core/hash.h"
#include "io/atomic_file.h"

namespace hdribr {
namespace fs = std::filesystem;
namespace {

// The file stores numbers as the host does; every supported host is little-endian.
static_assert(std::endian::native == std::endian::little, "the cache format is little-endian");

constexpr char kMagic[8] = {'H', 'D', 'R', 'I', 'B', 'R', 'D', 'M'};
constexpr std::uint32_t kVersion = 1;
constexpr size_t kHeaderBytes = 8 + 4 + 4 + 8;  // magic, version, layer count, key

std::string HexKey(std::uint64_t key) {
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(key));
  return text;
}

template <typename T>
void Append(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(value));
}

template <typename T>
T Take(const char*& p) {
  T value;
  std::memcpy(&value, p, sizeof(value));
  p += sizeof(value);
  return value;
}

// A cache file's name: 16 lower-case hex digits and ".bin".
bool IsCacheFileName(const std::string& name) {
  return name.size() == 20 && name.ends_with(".bin") &&
         std::all_of(name.begin(), name.begin() + 16,
                     [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

// A temporary file of AtomicFile for a cache file: ".<16 hex>.tmp<pid>_<n>.bin".
bool IsTemporaryName(const std::string& name) {
  return name.size() > 22 && name[0] == '.' && IsCacheFileName(name.substr(1, 16) + ".bin") &&
         name.compare(17, 4, ".tmp") == 0 && name.ends_with(".bin");
}

}  // namespace

fs::path DepthMapCacheDir(const fs::path& workspace) { return workspace / "cache" / "depth_maps"; }

fs::path DepthMapCacheFile(const fs::path& dir, std::uint64_t key) {
  return dir / (HexKey(key) + ".bin");
}

void WriteDepthMapCache(const fs::path& file, std::uint64_t key,
                        const std::vector<cv::Mat>& layers) {
  std::string head(kMagic, sizeof(kMagic));
  Append(head, kVersion);
  Append(head, static_cast<std::uint32_t>(layers.size()));
  Append(head, key);
  for (const cv::Mat& layer : layers) {
    HDRIBR_CHECK(layer.type() == CV_32FC1);
    Append(head, static_cast<std::uint32_t>(layer.cols));
    Append(head, static_cast<std::uint32_t>(layer.rows));
  }
  std::error_code ec;
  if (!file.parent_path().empty()) fs::create_directories(file.parent_path(), ec);
  if (ec) throw InputError(file.parent_path(), "cannot create the folder (" + ec.message() + ")");
  AtomicFile atomic(file);
  {
    std::ofstream out(atomic.temp_path(), std::ios::binary);
    if (!out) throw InputError(file, "cannot open for writing");
    Fnv1a64 checksum;
    checksum.AddBytes(head.data(), head.size());
    out.write(head.data(), static_cast<std::streamsize>(head.size()));
    for (const cv::Mat& layer : layers) {
      const auto row_bytes = static_cast<size_t>(layer.cols) * sizeof(float);
      for (int y = 0; y < layer.rows; ++y) {
        checksum.AddBytes(layer.ptr(y), row_bytes);
        out.write(reinterpret_cast<const char*>(layer.ptr(y)),
                  static_cast<std::streamsize>(row_bytes));
      }
    }
    const std::uint64_t sum = checksum.value();
    out.write(reinterpret_cast<const char*>(&sum), sizeof(sum));
    out.flush();
    if (!out) throw InputError(file, "write failed");
  }
  atomic.Commit();
}

std::vector<cv::Mat> ReadDepthMapCache(const fs::path& file, std::uint64_t key,
                                       const std::vector<cv::Size>& sizes) {
  std::error_code ec;
  const std::uintmax_t file_bytes = fs::file_size(file, ec);
  if (ec == std::errc::no_such_file_or_directory) throw InputError(file, "no such file");
  if (ec) throw InputError(file, "cannot read (" + ec.message() + ")");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file, "cannot open");
  const size_t head_bytes = kHeaderBytes + 8 * sizes.size();
  std::string head(head_bytes, '\0');
  in.read(head.data(),
          static_cast<std::streamsize>(std::min<std::uintmax_t>(head_bytes, file_bytes)));
  if (file_bytes < sizeof(kMagic) || std::memcmp(head.data(), kMagic, sizeof(kMagic)) != 0) {
    throw InputError(file, "not a depth map cache file");
  }
  if (file_bytes < kHeaderBytes) throw InputError(file, "truncated");
  const char* p = head.data() + sizeof(kMagic);
  const auto version = Take<std::uint32_t>(p);
  if (version != kVersion) {
    throw InputError(file, "format version " + std::to_string(version) + ", expected " +
                               std::to_string(kVersion));
  }
  const auto count = Take<std::uint32_t>(p);
  const auto stored_key = Take<std::uint64_t>(p);
  if (stored_key != key) {
    throw InputError(file, "holds key " + HexKey(stored_key) + ", expected " + HexKey(key));
  }
  if (count != sizes.size()) {
    throw InputError(
        file, std::to_string(count) + " depth maps, expected " + std::to_string(sizes.size()));
  }
  if (file_bytes < head_bytes) throw InputError(file, "truncated");
  std::uintmax_t expected_bytes = head_bytes + sizeof(std::uint64_t);
  for (size_t i = 0; i < sizes.size(); ++i) {
    const auto width = Take<std::uint32_t>(p);
    const auto height = Take<std::uint32_t>(p);
    if (width != static_cast<std::uint32_t>(sizes[i].width) ||
        height != static_cast<std::uint32_t>(sizes[i].height)) {
      throw InputError(file, "depth map " + std::to_string(i) + " is " + std::to_string(width) +
                                 "x" + std::to_string(height) + ", expected " +
                                 std::to_string(sizes[i].width) + "x" +
                                 std::to_string(sizes[i].height));
    }
    expected_bytes += std::uintmax_t{width} * height * sizeof(float);
  }
  if (file_bytes != expected_bytes) {
    throw InputError(file, (file_bytes < expected_bytes ? "truncated: " : "too long: ") +
                               std::to_string(file_bytes) + " bytes, expected " +
                               std::to_string(expected_bytes));
  }
  Fnv1a64 checksum;
  checksum.AddBytes(head.data(), head.size());
  std::vector<cv::Mat> layers;
  layers.reserve(sizes.size());
  for (const cv::Size& size : sizes) {
    cv::Mat layer(size, CV_32FC1);
    const size_t bytes = layer.total() * sizeof(float);
    in.read(reinterpret_cast<char*>(layer.data), static_cast<std::streamsize>(bytes));
    checksum.AddBytes(layer.data, bytes);
    layers.push_back(std::move(layer));
  }
  std::uint64_t stored_sum = 0;
  in.read(reinterpret_cast<char*>(&stored_sum), sizeof(stored_sum));
  if (!in) throw InputError(file, "read failed");
  if (stored_sum != checksum.value()) throw InputError(file, "checksum mismatch (corrupt)");
  return layers;
}

bool TouchDepthMapCache(const fs::path& file) {
  std::error_code ec;
  fs::last_write_time(file, fs::file_time_type::clock::now(), ec);
  return !ec;
}

int PruneDepthMapCache(const fs::path& dir, size_t keep) {
  std::error_code ec;
  std::vector<std::pair<fs::file_time_type, fs::path>> files;
  std::vector<fs::path> stale;
  const auto an_hour_ago = fs::file_time_type::clock::now() - std::chrono::hours(1);
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code entry_ec;
    if (!it->is_regular_file(entry_ec)) continue;
    const std::string name = it->path().filename().string();
    const fs::file_time_type time = it->last_write_time(entry_ec);
    if (entry_ec) continue;
    if (IsCacheFileName(name)) {
      files.emplace_back(time, it->path());
    } else if (IsTemporaryName(name) && time < an_hour_ago) {
      stale.push_back(it->path());
    }
  }
  std::sort(files.begin(), files.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  for (size_t i = keep; i < files.size(); ++i) stale.push_back(files[i].second);
  int removed = 0;
  for (const fs::path& path : stale) {
    std::error_code remove_ec;
    if (fs::remove(path, remove_ec)) ++removed;
  }
  return removed;
}

}  // namespace hdribr
