// The web bundle: the viewer's files (embedded from web/), the cameras and calibration
// (capture/scene.json), the points quantised to 10 bytes each (capture/points.bin) and the
// photos as JPEG (capture/photos/).
#include "io/web_bundle.h"

#include <zlib.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "core/dominant_plane.h"
#include "core/error.h"
#include "core/photo_candidates.h"
#include "io/atomic_file.h"
#include "io/image.h"
#include "io/radiometric_calibration.h"

namespace hdribr {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

void WriteBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!f) throw InputError(path, "cannot write");
}

// Octahedral encoding of a unit vector (Cigolle et al. 2014), each axis in [-127, 127].
std::array<std::int8_t, 2> OctEncode(Eigen::Vector3f n) {
  const float l1 = std::abs(n.x()) + std::abs(n.y()) + std::abs(n.z());
  if (!(l1 > 0.0f)) return {0, 0};
  n /= l1;
  float x = n.x(), y = n.y();
  if (n.z() < 0.0f) {
    x = (1.0f - std::abs(n.y())) * (n.x() >= 0.0f ? 1.0f : -1.0f);
    y = (1.0f - std::abs(n.x())) * (n.y() >= 0.0f ? 1.0f : -1.0f);
  }
  const auto q = [](float v) {
    return static_cast<std::int8_t>(std::lround(std::clamp(v, -1.0f, 1.0f) * 127.0f));
  };
  return {q(x), q(y)};
}

// Bits of a 16-bit value spread to every third bit (Morton order).
std::uint64_t Spread3(std::uint64_t x) {
  x &= 0xffff;
  x = (x | (x << 16)) & 0x0000ff0000ffULL;
  x = (x | (x << 8)) & 0x00f00f00f00fULL;
  x = (x | (x << 4)) & 0x0c30c30c30c3ULL;
  return (x | (x << 2)) & 0x249249249249ULL;
}

// The cloud as capture/points.bin, and its description for scene.json. Each point is x, y, z
// as uint16 within the bounds, the normal as 2 int8 (octahedral), the radius as uint16 of the
// largest; the points in Morton order, positions as differences from the previous point
// (modulo 2^16), then stored by byte planes (the low bytes of dx for every point, then the
// high bytes, ..., kWebPointBytes planes) and deflated (zlib): about half the bytes of the
// plain records.
std::string EncodePoints(const PointCloud& cloud, json& desc) {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(0), hi = Eigen::Vector3f::Constant(0);
  float max_radius = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    lo = i == 0 ? cloud.positions[i] : lo.cwiseMin(cloud.positions[i]);
    hi = i == 0 ? cloud.positions[i] : hi.cwiseMax(cloud.positions[i]);
    if (cloud.HasRadii()) max_radius = std::max(max_radius, cloud.radii[i]);
  }
  const Eigen::Vector3f extent = (hi - lo).cwiseMax(1e-12f);
  const size_t n = cloud.size();
  // Per point: the 5 uint16 fields x, y, z, normal (2 int8), radius.
  std::vector<std::array<std::uint16_t, 5>> q(n);
  std::vector<std::uint64_t> code(n);
  for (size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      q[i][a] = static_cast<std::uint16_t>(
          std::lround((cloud.positions[i][a] - lo[a]) / extent[a] * 65535.0f));
    }
    const std::array<std::int8_t, 2> oct =
        cloud.HasNormals() ? OctEncode(cloud.normals[i]) : std::array<std::int8_t, 2>{0, 0};
    q[i][3] = static_cast<std::uint16_t>(static_cast<std::uint8_t>(oct[0]) |
                                         (static_cast<std::uint8_t>(oct[1]) << 8));
    const float r = cloud.HasRadii() ? cloud.radii[i] : 0.0f;
    q[i][4] = static_cast<std::uint16_t>(
        max_radius > 0 ? std::lround(std::clamp(r / max_radius, 0.0f, 1.0f) * 65535.0f) : 0);
    code[i] = Spread3(q[i][0]) | (Spread3(q[i][1]) << 1) | (Spread3(q[i][2]) << 2);
  }
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return code[a] < code[b]; });
  std::string planes(n * kWebPointBytes, '\0');
  std::array<std::uint16_t, 3> prev = {0, 0, 0};
  for (size_t k = 0; k < n; ++k) {
    std::array<std::uint16_t, 5> f = q[order[k]];
    for (int a = 0; a < 3; ++a) {
      const std::uint16_t v = f[a];
      f[a] = static_cast<std::uint16_t>(v - prev[a]);
      prev[a] = v;
    }
    for (int field = 0; field < 5; ++field) {
      planes[(2 * field) * n + k] = static_cast<char>(f[field] & 0xff);
      planes[(2 * field + 1) * n + k] = static_cast<char>(f[field] >> 8);
    }
  }
  uLongf size = compressBound(static_cast<uLong>(planes.size()));
  std::string bytes(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(bytes.data()), &size,
                reinterpret_cast<const Bytef*>(planes.data()), static_cast<uLong>(planes.size()),
                Z_BEST_COMPRESSION) != Z_OK) {
    throw std::runtime_error("zlib: cannot compress the points");
  }
  bytes.resize(size);
  desc = {{"file", "points.bin"},
          {"count", n},
          {"bytes_per_point", kWebPointBytes},
          {"encoding", "morton-delta-planes-zlib"},
          {"min", {lo.x(), lo.y(), lo.z()}},
          {"max", {hi.x(), hi.y(), hi.z()}},
          {"max_radius", max_radius},
          {"normals", cloud.HasNormals()}};
  return bytes;
}

// The photo as JPEG at most max_size on its longest side: its own bytes when it is a JPEG
// that needs no resizing, else decoded, reduced with area averaging (as the renderer's
// max_photo_size) and encoded. Size receives the JPEG's pixel size.
std::string PhotoJpeg(const fs::path& path, const WebBundleOptions& opt, cv::Size& size) {
  const std::string ext = LowerExtension(path);
  size = ReadImageSize(path);
  const int longest = std::max(size.width, size.height);
  const bool fits = opt.max_photo_size <= 0 || longest <= opt.max_photo_size;
  if (fits && (ext == ".jpg" || ext == ".jpeg")) return ReadFileToString(path);
  cv::Mat image = ReadImage(path);
  if (image.depth() != CV_8U) throw InputError(path, "the web viewer takes 8-bit photos only");
  if (!fits) {
    const double s = static_cast<double>(opt.max_photo_size) / longest;
    cv::resize(image, image,
               cv::Size(std::max(1, static_cast<int>(std::lround(image.cols * s))),
                        std::max(1, static_cast<int>(std::lround(image.rows * s)))),
               0, 0, cv::INTER_AREA);
  }
  size = image.size();
  std::vector<unsigned char> buf;
  if (!cv::imencode(".jpg", image, buf, {cv::IMWRITE_JPEG_QUALITY, opt.jpeg_quality})) {
    throw InputError(path, "cannot encode as JPEG");
  }
  return {buf.begin(), buf.end()};
}

// The response the renderer's direct radiance mode uses: the workspace's calibration, else the
// HDR photo set's; null without either (the viewer then blends display values).
json ResponseOf(const Scene& scene) {
  for (const fs::path& f : {scene.workspace / kCalibFolder / kCalibResponse,
                            scene.workspace / "hdr" / kCalibResponse}) {
    if (!fs::exists(f)) continue;
    const json j = json::parse(ReadFileToString(f), nullptr, /*allow_exceptions=*/false);
    if (!j.is_object() || !j.contains("log_inverse")) throw InputError(f, "not a response curve");
    json out;
    for (const char* c : {"R", "G", "B"}) {
      const json& ch = j["log_inverse"][c];
      if (!ch.is_array() || ch.size() != 256) throw InputError(f, "needs 256 values per channel");
      out[c] = ch;
    }
    return {{"source", f.lexically_relative(scene.workspace).string()}, {"log_inverse", out}};
  }
  return nullptr;
}

}  // namespace

WebBundleReport WriteWebBundle(const Scene& scene, const fs::path& out,
                               const WebBundleOptions& opt) {
  if (fs::exists(out) && !(fs::is_directory(out) && fs::is_empty(out))) {
    throw InputError(out, "exists and is not an empty folder");
  }
  if (scene.photos.empty()) throw InputError(scene.workspace, "has no photos");
  const fs::path tmp = out.parent_path() / (out.filename().string() + ".partial");
  fs::remove_all(tmp);
  WebBundleReport report;
  try {
    fs::create_directories(tmp / "capture" / "photos");
    for (const auto& [name, contents] : EmbeddedWebFiles()) {
      fs::create_directories((tmp / name).parent_path());
      WriteBytes(tmp / name, contents);
      report.viewer += contents.size();
    }
    json scene_json = {{"format", "hdribr-web"}, {"version", kWebBundleVersion}};
    json cams = json::object();
    for (const auto& [id, cam] : scene.cameras) {
      cams[std::to_string(id)] = {{"width", cam.width}, {"height", cam.height}, {"fx", cam.fx()},
                                  {"fy", cam.fy()},     {"cx", cam.cx()},       {"cy", cam.cy()}};
    }
    scene_json["cameras"] = cams;
    json photos = json::array();
    for (size_t i = 0; i < scene.photos.size(); ++i) {
      const Photo& p = scene.photos[i];
      cv::Size size;
      const std::string jpeg = PhotoJpeg(p.image_path, opt, size);
      const std::string file = "photos/" + std::to_string(i) + ".jpg";
      WriteBytes(tmp / "capture" / file, jpeg);
      report.photos += jpeg.size();
      const Eigen::Quaterniond& q = p.cam_from_world.rotation;
      const Eigen::Vector3d& t = p.cam_from_world.translation;
      photos.push_back({{"name", p.name},
                        {"file", file},
                        {"camera_id", p.camera_id},
                        {"image_size", {size.width, size.height}},
                        {"qvec", {q.w(), q.x(), q.y(), q.z()}},
                        {"tvec", {t.x(), t.y(), t.z()}},
                        {"exposure", scene.RelativeExposureOf(p)}});
      ++report.photo_count;
      if (opt.progress) opt.progress(report.photo_count, static_cast<int>(scene.photos.size()));
    }
    scene_json["photos"] = photos;
    json points;
    const std::string point_bytes = EncodePoints(scene.points, points);
    WriteBytes(tmp / "capture" / "points.bin", point_bytes);
    report.points = point_bytes.size();
    report.point_count = scene.points.size();
    scene_json["points"] = points;
    scene_json["scene_scale"] = scene.scene_scale;
    scene_json["centroid"] = {scene.centroid.x(), scene.centroid.y(), scene.centroid.z()};
    scene_json["median_exposure"] = scene.MedianRelativeExposure();
    const DominantPlane plane = FindDominantPlane(scene);
    if (plane.valid()) {
      const auto v = [](const Eigen::Vector3d& x) { return json{x.x(), x.y(), x.z()}; };
      scene_json["plane"] = {
          {"normal", v(plane.normal)},
          {"offset", plane.offset},
          {"axis_u", v(plane.axis_u)},
          {"axis_v", v(plane.axis_v)},
          {"extent", {plane.extent[0], plane.extent[1], plane.extent[2], plane.extent[3]}}};
    } else {
      scene_json["plane"] = nullptr;
    }
    scene_json["response"] = ResponseOf(scene);
    scene_json["blend"] = {{"delta_weight", kUlrDistanceWeight}};
    const std::string text = scene_json.dump(1);
    WriteBytes(tmp / "capture" / "scene.json", text);
    report.other += text.size();
    if (fs::exists(out)) fs::remove(out);  // an empty folder
    fs::rename(tmp, out);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
  return report;
}

}  // namespace hdribr
