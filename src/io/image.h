// 8-bit photos through OpenCV, read exactly as COLMAP reads them.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

namespace hdribr {

// Reads stored pixels as 8-bit BGR, ignoring the EXIF orientation tag as COLMAP does. Throws
// InputError naming the file when missing or not decodable.
cv::Mat ReadImage(const std::filesystem::path& path);
// Width and height of an image without decoding all pixels, ignoring orientation as above.
cv::Size ReadImageSize(const std::filesystem::path& path);
// Writes PNG/JPEG (by extension) atomically; quality applies to JPEG.
void WriteImage(const std::filesystem::path& path, const cv::Mat& image, int jpeg_quality = 95);
// A file's extension in lower case with its dot (".exr" for "a.EXR"), empty when it has none:
// the rule by which every reader and writer picks a format.
std::string LowerExtension(const std::filesystem::path& path);

}  // namespace hdribr
