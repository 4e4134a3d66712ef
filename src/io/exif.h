// EXIF exposure metadata and image header sizes through exiv2.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "core/photo.h"

namespace hdribr {

struct ExifInfo {
  Exposure exposure;               // fields absent from the file stay empty
  std::optional<int> orientation;  // EXIF Orientation tag (1 = normal, 6 = rotate 90 CW)
  std::string make;
  std::string model;
};

// Reads EXIF; a file without EXIF gives an empty ExifInfo (callers warn). Throws InputError for
// a missing or unreadable file.
ExifInfo ReadExif(const std::filesystem::path& path);
// Writes exposure time, ISO, f-number and focal length (the fields that are set) plus make and
// model into an existing JPEG, in place (for files this program is creating).
void WriteExif(const std::filesystem::path& path, const ExifInfo& info);

// Width and height that the header of an encoded image (JPEG SOF, PNG IHDR, ...: the formats
// exiv2 reads) gives, without decoding the pixels and ignoring the orientation tag; nullopt when
// exiv2 does not read the format or the header gives no size.
std::optional<cv::Size> HeaderPixelSize(const std::string& bytes);

}  // namespace hdribr
