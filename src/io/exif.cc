#include "io/exif.h"

#include <cmath>
#include <exception>
#include <mutex>
#include <numeric>
#include <system_error>

#include "core/error.h"

// exiv2 0.27 still exposes std::auto_ptr (deprecated) in its API.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#include <exiv2/exiv2.hpp>

namespace hdribr {
namespace fs = std::filesystem;

namespace {

void QuietExiv2() {
  static std::once_flag once;
  std::call_once(once, [] { Exiv2::LogMsg::setLevel(Exiv2::LogMsg::mute); });
}

// Positive finite value of a rational/number tag, or nullopt (0/0 and 0 mean "unknown").
std::optional<double> PositiveNumber(const Exiv2::ExifData& exif, const char* key) {
  const auto it = exif.findKey(Exiv2::ExifKey(key));
  if (it == exif.end() || it->count() == 0) return std::nullopt;
  double v = 0;
  const Exiv2::TypeId type = it->typeId();
  if (type == Exiv2::unsignedRational || type == Exiv2::signedRational) {
    const Exiv2::Rational r = it->toRational(0);
    if (r.second == 0) return std::nullopt;
    v = static_cast<double>(r.first) / static_cast<double>(r.second);
  } else {
    v = static_cast<double>(it->toFloat(0));
  }
  if (!std::isfinite(v) || v <= 0) return std::nullopt;
  return v;
}

std::string Text(const Exiv2::ExifData& exif, const char* key) {
  const auto it = exif.findKey(Exiv2::ExifKey(key));
  if (it == exif.end()) return "";
  std::string s = it->toString();
  while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
  return s;
}

// A rational close to v: 1/n for exposure times like 1/125 s, else v with 4 decimals.
Exiv2::URational ToRational(double v) {
  if (v > 0 && v < 1) {
    const double inv = 1.0 / v;
    if (std::abs(inv - std::round(inv)) < 1e-6 * inv) {
      return {1, static_cast<std::uint32_t>(std::round(inv))};
    }
  }
  std::uint32_t den = 10000;
  auto num = static_cast<std::uint32_t>(std::llround(v * den));
  const std::uint32_t g = std::gcd(num, den);
  if (g > 1) {
    num /= g;
    den /= g;
  }
  return {num, den};
}

Exiv2::Image::AutoPtr Open(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError(path, fs::exists(path, ec) ? "not a file" : "no such file");
  }
  QuietExiv2();
  try {
    Exiv2::Image::AutoPtr image = Exiv2::ImageFactory::open(path.string());
    if (image.get() == nullptr) throw InputError(path, "cannot read EXIF (unknown format)");
    image->readMetadata();
    return image;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, std::string("cannot read EXIF (") + e.what() + ")");
  }
}

}  // namespace

ExifInfo ReadExif(const fs::path& path) {
  Exiv2::Image::AutoPtr image = Open(path);
  ExifInfo info;
  try {
    const Exiv2::ExifData& exif = image->exifData();
    if (exif.empty()) return info;
    info.exposure.time_s = PositiveNumber(exif, "Exif.Photo.ExposureTime");
    info.exposure.iso = PositiveNumber(exif, "Exif.Photo.ISOSpeedRatings");
    info.exposure.f_number = PositiveNumber(exif, "Exif.Photo.FNumber");
    info.exposure.focal_mm = PositiveNumber(exif, "Exif.Photo.FocalLength");
    const auto o = exif.findKey(Exiv2::ExifKey("Exif.Image.Orientation"));
    if (o != exif.end() && o->count() > 0) info.orientation = static_cast<int>(o->toLong(0));
    info.make = Text(exif, "Exif.Image.Make");
    info.model = Text(exif, "Exif.Image.Model");
  } catch (const std::exception& e) {
    throw InputError(path, std::string("cannot read EXIF (") + e.what() + ")");
  }
  return info;
}

void WriteExif(const fs::path& path, const ExifInfo& info) {
  Exiv2::Image::AutoPtr image = Open(path);
  try {
    Exiv2::ExifData& exif = image->exifData();
    const Exposure& e = info.exposure;
    if (e.time_s) exif["Exif.Photo.ExposureTime"] = ToRational(*e.time_s);
    if (e.iso) {
      exif["Exif.Photo.ISOSpeedRatings"] = static_cast<std::uint16_t>(std::lround(*e.iso));
    }
    if (e.f_number) exif["Exif.Photo.FNumber"] = ToRational(*e.f_number);
    if (e.focal_mm) exif["Exif.Photo.FocalLength"] = ToRational(*e.focal_mm);
    if (info.orientation) {
      exif["Exif.Image.Orientation"] = static_cast<std::uint16_t>(*info.orientation);
    }
    if (!info.make.empty()) exif["Exif.Image.Make"] = info.make;
    if (!info.model.empty()) exif["Exif.Image.Model"] = info.model;
    image->writeMetadata();
  } catch (const std::exception& e) {
    throw InputError(path, std::string("cannot write EXIF (") + e.what() + ")");
  }
}

std::optional<cv::Size> HeaderPixelSize(const std::string& bytes) {
  QuietExiv2();
  try {
    const Exiv2::Image::AutoPtr image = Exiv2::ImageFactory::open(
        reinterpret_cast<const Exiv2::byte*>(bytes.data()), static_cast<long>(bytes.size()));
    if (image.get() == nullptr) return std::nullopt;
    image->readMetadata();
    const cv::Size size(image->pixelWidth(), image->pixelHeight());
    if (size.width <= 0 || size.height <= 0) return std::nullopt;
    return size;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace hdribr

#pragma GCC diagnostic pop
