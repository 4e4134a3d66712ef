#include "render/render_output.h"

#include "io/exr.h"

namespace hdribr::render {

void WriteRgbaExr(const std::filesystem::path& path, const cv::Mat& bgr, const cv::Mat& valid) {
  WriteExrWithMask(path, bgr, valid, "A", ExrPixel::kFloat);
}

}  // namespace hdribr::render
