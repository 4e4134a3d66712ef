#include "io/image.h"

#include <algorithm>
#include <exception>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

constexpr int kReadFlags = cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION;

bool IsJpeg(const std::string& b) {
  return b.size() >= 3 && static_cast<unsigned char>(b[0]) == 0xFF &&
         static_cast<unsigned char>(b[1]) == 0xD8 && static_cast<unsigned char>(b[2]) == 0xFF;
}

bool IsPng(const std::string& b) {
  return b.size() >= 8 && b.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

// libjpeg only warns on a truncated file (and fills the rest grey), so a JPEG must end with the
// EOI marker FF D9, allowing for padding bytes some writers append.
void CheckJpegComplete(const std::string& b, const fs::path& path) {
  size_t end = b.size();
  while (end > 2 &&
         (b[end - 1] == '\0' || b[end - 1] == '\n' || b[end - 1] == '\r' || b[end - 1] == ' ')) {
    --end;
  }
  if (end < 4 || static_cast<unsigned char>(b[end - 2]) != 0xFF ||
      static_cast<unsigned char>(b[end - 1]) != 0xD9) {
    throw InputError(path, "corrupt JPEG (truncated: no end-of-image marker)");
  }
}

std::string ReadBytes(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError(path, fs::exists(path, ec) ? "not a file" : "no such file");
  }
  std::string bytes = ReadFileToString(path);
  if (bytes.empty()) throw InputError(path, "empty file");
  return bytes;
}

// Size from a JPEG's SOF marker; 0x0 when not found.
cv::Size JpegSize(const std::string& b) {
  auto u8 = [&](size_t i) { return static_cast<unsigned>(static_cast<unsigned char>(b[i])); };
  size_t i = 2;
  while (i + 4 <= b.size()) {
    if (u8(i) != 0xFF) return {};
    const unsigned marker = u8(i + 1);
    if (marker == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    if (marker == 0xD8 || (marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) {
      i += 2;
      continue;
    }
    const size_t len = (u8(i + 2) << 8) | u8(i + 3);
    if (len < 2) return {};
    const bool sof =
        marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof) {
      if (i + 9 > b.size()) return {};
      const int h = static_cast<int>((u8(i + 5) << 8) | u8(i + 6));
      const int w = static_cast<int>((u8(i + 7) << 8) | u8(i + 8));
      return {w, h};
    }
    if (marker == 0xDA) return {};  // start of scan before any SOF
    i += 2 + len;
  }
  return {};
}

cv::Size PngSize(const std::string& b) {
  if (b.size() < 24 || b.compare(12, 4, "IHDR") != 0) return {};
  auto be32 = [&](size_t i) {
    return (static_cast<unsigned>(static_cast<unsigned char>(b[i])) << 24) |
           (static_cast<unsigned>(static_cast<unsigned char>(b[i + 1])) << 16) |
           (static_cast<unsigned>(static_cast<unsigned char>(b[i + 2])) << 8) |
           static_cast<unsigned>(static_cast<unsigned char>(b[i + 3]));
  };
  const unsigned w = be32(16), h = be32(20);
  if (w == 0 || h == 0 || w > (1u << 30) || h > (1u << 30)) return {};
  return {static_cast<int>(w), static_cast<int>(h)};
}

cv::Mat Decode(const std::string& bytes, const fs::path& path) {
  if (IsJpeg(bytes)) CheckJpegComplete(bytes, path);
  cv::Mat image;
  try {
    const cv::Mat buf(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data()));
    image = cv::imdecode(buf, kReadFlags);
  } catch (const std::exception& e) {
    throw InputError(path, std::string("cannot decode image (") + e.what() + ")");
  }
  if (image.empty()) throw InputError(path, "cannot decode image (corrupt or unsupported format)");
  return image;
}

}  // namespace

cv::Mat ReadImage(const fs::path& path) { return Decode(ReadBytes(path), path); }

cv::Size ReadImageSize(const fs::path& path) {
  const std::string bytes = ReadBytes(path);
  cv::Size size;
  if (IsJpeg(bytes)) {
    CheckJpegComplete(bytes, path);
    size = JpegSize(bytes);
  } else if (IsPng(bytes)) {
    size = PngSize(bytes);
  }
  if (size.width > 0 && size.height > 0) return size;
  return Decode(bytes, path).size();  // other formats, or a header we could not parse
}

void WriteImage(const fs::path& path, const cv::Mat& image, int jpeg_quality) {
  if (image.empty()) throw UsageError("WriteImage: empty image for " + path.string());
  std::vector<int> params;
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".jpg" || ext == ".jpeg") params = {cv::IMWRITE_JPEG_QUALITY, jpeg_quality};
  AtomicFile file(path);
  bool ok = false;
  try {
    ok = cv::imwrite(file.temp_path().string(), image, params);
  } catch (const std::exception& e) {
    throw InputError(path, std::string("cannot write image (") + e.what() + ")");
  }
  if (!ok) throw InputError(path, "cannot write image");
  file.Commit();
}

}  // namespace hdribr
