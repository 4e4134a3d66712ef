// OpenEXR images: RGB or single channel, stored as half or float.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>

namespace hdribr {

enum class ExrPixel { kHalf, kFloat };

// Reads an EXR as CV_32FC3 (BGR order, like every cv::Mat in hdribr) when it has R,G,B
// channels, or CV_32FC1 when it has a single channel (Y, Z, R or any one name). Throws
// InputError naming the file on failure.
cv::Mat ReadExr(const std::filesystem::path& path);
// Writes CV_32FC3 (BGR) as R,G,B or CV_32FC1 as `single_channel_name`, atomically.
void WriteExr(const std::filesystem::path& path, const cv::Mat& image,
              ExrPixel pixel = ExrPixel::kHalf, const std::string& single_channel_name = "Y");

}  // namespace hdribr
