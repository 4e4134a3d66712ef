// The input photo folder: listing photos, their EXIF, grouping into physical cameras.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/exif.h"

namespace hdribr {

struct InputPhoto {
  std::string name;  // file name relative to the photo folder (COLMAP image name)
  ExifInfo exif;
  int width = 0;
  int height = 0;
};

// Photos (jpg, jpeg, png, tif, tiff; any case) directly in `folder`, sorted by name, with EXIF
// and size. Throws InputError when the folder is missing, not a folder, or holds no photo.
std::vector<InputPhoto> ListPhotos(const std::filesystem::path& folder);

// One physical camera: photos with the same EXIF make, model and image size.
struct CameraGroup {
  std::string key;                 // "make model WxH"
  std::vector<int> photo_indices;  // into the ListPhotos() result
};
std::vector<CameraGroup> GroupByCamera(const std::vector<InputPhoto>& photos);

// Image pairs to match for multi-series hand-held captures in shooting order: within each
// exposure series the `overlap` following photos; across series the photos at the same relative
// position (+-overlap/2). `series_of[i]` is the series of photo i (photos in name order).
std::vector<std::pair<int, int>> SeriesAwarePairs(const std::vector<int>& series_of, int overlap);

}  // namespace hdribr
