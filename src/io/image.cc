#include "io/image.h"

#include <algorithm>
#include <cctype>
#include <exception>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/exif.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

constexpr int kReadFlags = cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION;

bool IsJpeg(const std::string& b) {
  return b.size() >= 3 && static_cast<unsigned char>(b[0]) == 0xFF &&
         static_cast<unsigned char>(b[1]) == 0xD8 && static_cast<unsigned char>(b[2]) == 0xFF;
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
  if (IsJpeg(bytes)) CheckJpegComplete(bytes, path);
  if (const std::optional<cv::Size> size = HeaderPixelSize(bytes)) return *size;
  return Decode(bytes, path).size();  // a format exiv2 does not read, or a header without size
}

void WriteImage(const fs::path& path, const cv::Mat& image, int jpeg_quality) {
  if (image.empty()) throw UsageError("WriteImage: empty image for " + path.string());
  std::vector<int> params;
  const std::string ext = LowerExtension(path);
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

std::string LowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace hdribr
