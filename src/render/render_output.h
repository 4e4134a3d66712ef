// Files written from rendered views (`hdribr render`, exports): RGBA EXR.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>

namespace hdribr::render {

// Writes linear float R, G, B (from CV_32FC3 BGR) and A = 1 where `valid` (CV_8UC1) is
// non-zero, 0 elsewhere; atomic. Throws InputError naming the file.
void WriteRgbaExr(const std::filesystem::path& path, const cv::Mat& bgr, const cv::Mat& valid);

}  // namespace hdribr::render
