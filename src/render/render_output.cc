#include "render/render_output.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <algorithm>
#include <exception>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr::render {

void WriteRgbaExr(const std::filesystem::path& path, const cv::Mat& bgr, const cv::Mat& valid) {
  HDRIBR_CHECK(bgr.type() == CV_32FC3 && valid.type() == CV_8UC1 && bgr.size() == valid.size());
  const int w = bgr.cols, h = bgr.rows;
  std::vector<float> rgba(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const cv::Vec3f c = bgr.at<cv::Vec3f>(y, x);
      float* o =
          &rgba[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 4];
      o[0] = c[2];
      o[1] = c[1];
      o[2] = c[0];
      o[3] = valid.at<uint8_t>(y, x) ? 1.0f : 0.0f;
    }
  }
  AtomicFile file(path);
  try {
    Imf::Header header(w, h);
    const char* names[4] = {"R", "G", "B", "A"};
    Imf::FrameBuffer fb;
    for (int c = 0; c < 4; ++c) {
      header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
      fb.insert(names[c],
                Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(rgba.data() + c), 4 * sizeof(float),
                           4 * sizeof(float) * static_cast<size_t>(w)));
    }
    Imf::OutputFile out(file.temp_path().c_str(), header);
    out.setFrameBuffer(fb);
    out.writePixels(h);
  } catch (const std::exception& e) {
    throw InputError(path, std::string("cannot write EXR: ") + e.what());
  }
  file.Commit();
}

cv::Mat FalseColour(const cv::Mat& value, double lo, double hi, const cv::Mat& mask) {
  HDRIBR_CHECK(value.type() == CV_32FC1);
  cv::Mat gray(value.size(), CV_8UC1);
  const double span = hi > lo ? hi - lo : 1.0;
  for (int y = 0; y < value.rows; ++y) {
    for (int x = 0; x < value.cols; ++x) {
      const double t = std::clamp((value.at<float>(y, x) - lo) / span, 0.0, 1.0);
      gray.at<uint8_t>(y, x) = static_cast<uint8_t>(t * 255.0 + 0.5);
    }
  }
  cv::Mat colour, out(value.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  cv::applyColorMap(gray, colour, cv::COLORMAP_TURBO);
  colour.copyTo(out, mask);
  return out;
}

}  // namespace hdribr::render
