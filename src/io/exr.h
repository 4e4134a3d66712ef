// OpenEXR images: RGB or single channel, stored as half or float.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

namespace hdribr {

enum class ExrPixel { kHalf, kFloat };

// Reads an EXR as CV_32FC3 (BGR order, like every cv::Mat in hdribr) when it has R,G,B
// channels, or CV_32FC1 when it has a single channel (Y, Z, R or any one name). Throws
// InputError naming the file on failure.
cv::Mat ReadExr(const std::filesystem::path& path);
// Writes CV_32FC3 (BGR) as R,G,B or CV_32FC1 as `single_channel_name`, atomically.
void WriteExr(const std::filesystem::path& path, const cv::Mat& image,
              ExrPixel pixel = ExrPixel::kHalf, const std::string& single_channel_name = "Y");
// Writes CV_32FC3 (BGR) as R,G,B plus channel `mask_name` = 1 where `mask` (CV_8UC1, same
// size) is non-zero and 0 elsewhere (e.g. "A", or "valid" for an HDR photo set), atomically.
void WriteExrWithMask(const std::filesystem::path& path, const cv::Mat& image, const cv::Mat& mask,
                      const std::string& mask_name, ExrPixel pixel = ExrPixel::kHalf);
// Channel `mask_name` of an EXR as CV_8UC1 (255 where > 0.5); all 255 when the file has no such
// channel. `size` is the expected image size (InputError when it differs).
cv::Mat ReadExrMask(const std::filesystem::path& path, const std::string& mask_name, cv::Size size);

}  // namespace hdribr
