#include "frontend/photo_folder.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "core/error.h"
#include "io/image.h"

namespace hdribr {
namespace fs = std::filesystem;

std::vector<InputPhoto> ListPhotos(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec)) throw InputError(folder, "photo folder does not exist");
  if (!fs::is_directory(folder, ec)) throw InputError(folder, "is not a folder of photos");
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    const std::string ext = LowerExtension(entry.path());
    if (ext == ".jpg" || ext == ".jpeg" || ext == ".png" || ext == ".tif" || ext == ".tiff") {
      names.push_back(entry.path().filename().string());
    }
  }
  if (names.empty()) {
    throw InputError(folder, "no photos found (expected .jpg, .jpeg, .png, .tif files)");
  }
  std::sort(names.begin(), names.end());
  std::vector<InputPhoto> photos;
  for (const auto& name : names) {
    InputPhoto p;
    p.name = name;
    p.exif = ReadExif(folder / name);
    const cv::Size size = ReadImageSize(folder / name);
    p.width = size.width;
    p.height = size.height;
    photos.push_back(std::move(p));
  }
  return photos;
}

std::vector<CameraGroup> GroupByCamera(const std::vector<InputPhoto>& photos) {
  std::map<std::string, int> index;
  std::vector<CameraGroup> groups;
  for (size_t i = 0; i < photos.size(); ++i) {
    const auto& p = photos[i];
    const std::string key = p.exif.make + " " + p.exif.model + " " + std::to_string(p.width) + "x" +
                            std::to_string(p.height);
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, static_cast<int>(groups.size())).first;
      groups.push_back({key, {}});
    }
    groups[it->second].photo_indices.push_back(static_cast<int>(i));
  }
  return groups;
}

std::vector<std::pair<int, int>> SeriesAwarePairs(const std::vector<int>& series_of, int overlap) {
  std::map<int, std::vector<int>> members;  // series -> photos in name order
  for (size_t i = 0; i < series_of.size(); ++i)
    members[series_of[i]].push_back(static_cast<int>(i));
  std::set<std::pair<int, int>> pairs;
  auto add = [&](int a, int b) {
    if (a != b) pairs.insert({std::min(a, b), std::max(a, b)});
  };
  for (const auto& [s, list] : members) {
    const int n = static_cast<int>(list.size());
    for (int i = 0; i < n; ++i) {
      for (int k = 1; k <= overlap && i + k < n; ++k) add(list[i], list[i + k]);
      // Cross-series: the same relative position in every other series.
      for (const auto& [s2, list2] : members) {
        if (s2 == s) continue;
        const int n2 = static_cast<int>(list2.size());
        const double pos = n > 1 ? double(i) / (n - 1) * (n2 - 1) : 0.0;
        const int centre = static_cast<int>(std::lround(pos));
        for (int d = -overlap / 2; d <= overlap / 2; ++d) {
          const int j = centre + d;
          if (j >= 0 && j < n2) add(list[i], list2[j]);
        }
      }
    }
  }
  return {pairs.begin(), pairs.end()};
}

}  // namespace hdribr
