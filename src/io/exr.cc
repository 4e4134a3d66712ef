#include "io/exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <half.h>

#include <exception>
#include <string>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

// Refuse data windows beyond this many pixels: a corrupt header must not drive the allocation.
constexpr std::int64_t kMaxPixels = std::int64_t{1} << 28;

}  // namespace

cv::Mat ReadExr(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError(path, fs::exists(path, ec) ? "not a file" : "no such file");
  }
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const std::int64_t w = std::int64_t{dw.max.x} - dw.min.x + 1;
    const std::int64_t h = std::int64_t{dw.max.y} - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w * h > kMaxPixels) {
      throw InputError(path, "invalid data window " + std::to_string(w) + "x" + std::to_string(h));
    }
    const Imf::ChannelList& channels = file.header().channels();
    std::vector<std::string> names;
    for (auto it = channels.begin(); it != channels.end(); ++it) names.emplace_back(it.name());
    const bool rgb =
        channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B");
    if (!rgb && names.size() != 1 && !channels.findChannel("Y")) {
      throw InputError(path, "has " + std::to_string(names.size()) +
                                 " channels but neither R,G,B nor a single channel");
    }
    const int nc = rgb ? 3 : 1;
    cv::Mat image(static_cast<int>(h), static_cast<int>(w), nc == 3 ? CV_32FC3 : CV_32FC1,
                  cv::Scalar::all(0));
    // Slices address pixel (x, y) of the data window at base + x*xs + y*ys.
    const size_t xs = sizeof(float) * nc;
    const size_t ys = xs * static_cast<size_t>(w);
    auto base = [&](int channel) {
      return reinterpret_cast<char*>(image.ptr<float>(0) + channel) -
             static_cast<std::ptrdiff_t>(dw.min.x) * static_cast<std::ptrdiff_t>(xs) -
             static_cast<std::ptrdiff_t>(dw.min.y) * static_cast<std::ptrdiff_t>(ys);
    };
    Imf::FrameBuffer fb;
    if (rgb) {
      fb.insert("B", Imf::Slice(Imf::FLOAT, base(0), xs, ys));
      fb.insert("G", Imf::Slice(Imf::FLOAT, base(1), xs, ys));
      fb.insert("R", Imf::Slice(Imf::FLOAT, base(2), xs, ys));
    } else {
      const std::string name = channels.findChannel("Y") ? "Y" : names.front();
      fb.insert(name, Imf::Slice(Imf::FLOAT, base(0), xs, ys));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return image;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, std::string("cannot read EXR (") + e.what() + ")");
  }
}

namespace {

// Writes the interleaved CV_32F channels of `src` under `names` (one per channel), atomically.
void WriteChannels(const fs::path& path, const cv::Mat& image,
                   const std::vector<std::string>& names, ExrPixel pixel) {
  const cv::Mat src = image.isContinuous() ? image : image.clone();
  const int nc = src.channels();
  const Imf::PixelType type = pixel == ExrPixel::kHalf ? Imf::HALF : Imf::FLOAT;
  // OpenEXR does not convert float slices to half channels on output: convert here.
  std::vector<Imath::half> halves;
  if (type == Imf::HALF) {
    halves.resize(src.total() * nc);
    const float* f = src.ptr<float>(0);
    for (size_t i = 0; i < halves.size(); ++i) halves[i] = Imath::half(f[i]);
  }
  const size_t elem = type == Imf::HALF ? sizeof(Imath::half) : sizeof(float);
  char* data = type == Imf::HALF
                   ? reinterpret_cast<char*>(halves.data())
                   : const_cast<char*>(reinterpret_cast<const char*>(src.ptr<float>(0)));
  AtomicFile file(path);
  try {
    Imf::Header header(src.cols, src.rows);
    header.compression() = Imf::ZIP_COMPRESSION;
    const size_t xs = elem * nc;
    const size_t ys = xs * static_cast<size_t>(src.cols);
    Imf::FrameBuffer fb;
    for (int c = 0; c < nc; ++c) {
      header.channels().insert(names[static_cast<size_t>(c)], Imf::Channel(type));
      fb.insert(names[static_cast<size_t>(c)], Imf::Slice(type, data + c * elem, xs, ys));
    }
    {
      Imf::OutputFile out(file.temp_path().c_str(), header);
      out.setFrameBuffer(fb);
      out.writePixels(src.rows);
    }
  } catch (const std::exception& e) {
    throw InputError(path, std::string("cannot write EXR (") + e.what() + ")");
  }
  file.Commit();
}

}  // namespace

void WriteExr(const fs::path& path, const cv::Mat& image, ExrPixel pixel,
              const std::string& single_channel_name) {
  if (image.empty() || (image.type() != CV_32FC3 && image.type() != CV_32FC1)) {
    throw UsageError("WriteExr: " + path.string() +
                     ": image must be non-empty CV_32FC3 or CV_32FC1");
  }
  if (single_channel_name.empty()) throw UsageError("WriteExr: empty channel name");
  if (image.channels() == 3) {
    WriteChannels(path, image, {"B", "G", "R"}, pixel);  // BGR in memory
  } else {
    WriteChannels(path, image, {single_channel_name}, pixel);
  }
}

void WriteExrWithMask(const fs::path& path, const cv::Mat& image, const cv::Mat& mask,
                      const std::string& mask_name, ExrPixel pixel) {
  if (image.empty() || image.type() != CV_32FC3 || mask.type() != CV_8UC1 ||
      mask.size() != image.size() || mask_name.empty()) {
    throw UsageError("WriteExrWithMask: " + path.string() +
                     ": needs CV_32FC3, a CV_8UC1 mask of the same size and a channel name");
  }
  const cv::Mat nonzero = mask != 0;  // 255 / 0
  cv::Mat mask01;
  nonzero.convertTo(mask01, CV_32F, 1.0 / 255.0);
  cv::Mat bgra;
  cv::merge(std::vector<cv::Mat>{image, mask01}, bgra);
  WriteChannels(path, bgra, {"B", "G", "R", mask_name}, pixel);
}

cv::Mat ReadExrMask(const fs::path& path, const std::string& mask_name, cv::Size size) {
  cv::Mat mask(size, CV_8UC1, cv::Scalar(255));
  try {
    Imf::InputFile file(path.c_str());
    if (!file.header().channels().findChannel(mask_name)) return mask;
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    if (w != size.width || h != size.height) throw InputError(path, "inconsistent size");
    std::vector<float> v(static_cast<size_t>(w) * h);
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(v.data()) -
                 (static_cast<ptrdiff_t>(dw.min.x) + static_cast<ptrdiff_t>(dw.min.y) * w) *
                     static_cast<ptrdiff_t>(sizeof(float));
    fb.insert(mask_name, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * w));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) mask.at<uint8_t>(y, x) = v[y * w + x] > 0.5f ? 255 : 0;
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, "cannot read the '" + mask_name + "' channel: " + e.what());
  }
  return mask;
}

}  // namespace hdribr
