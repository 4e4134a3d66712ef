#include "io/colmap_model.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kInvalidPoint3DId = std::numeric_limits<std::uint64_t>::max();

bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// ---------------------------------------------------------------- checks shared by both forms

Camera MakeCamera(int id, int model_id_or_minus1, const std::string& model_name, std::int64_t width,
                  std::int64_t height, std::vector<double> params, const fs::path& file,
                  const std::string& where) {
  Camera cam;
  cam.id = id;
  try {
    cam.model = model_id_or_minus1 >= 0 ? CameraModelFromId(model_id_or_minus1)
                                        : CameraModelFromName(model_name);
  } catch (const std::invalid_argument&) {
    throw InputError(file, where + "unknown camera model " +
                               (model_id_or_minus1 >= 0 ? std::to_string(model_id_or_minus1)
                                                        : "'" + model_name + "'"));
  }
  if (width <= 0 || height <= 0 || width > 1'000'000 || height > 1'000'000) {
    throw InputError(file, where + "camera " + std::to_string(id) + " has an invalid size " +
                               std::to_string(width) + "x" + std::to_string(height));
  }
  cam.width = static_cast<int>(width);
  cam.height = static_cast<int>(height);
  if (static_cast<int>(params.size()) != CameraModelNumParams(cam.model)) {
    throw InputError(file, where + "camera " + std::to_string(id) + " (" +
                               CameraModelName(cam.model) + ") needs " +
                               std::to_string(CameraModelNumParams(cam.model)) +
                               " parameters, got " + std::to_string(params.size()));
  }
  for (double v : params) {
    if (!std::isfinite(v)) {
      throw InputError(file,
                       where + "camera " + std::to_string(id) + " has a non-finite parameter");
    }
  }
  cam.params = std::move(params);
  if (!(cam.fx() > 0) || !(cam.fy() > 0)) {
    throw InputError(file, where + "camera " + std::to_string(id) + " has a focal length <= 0 (" +
                               std::to_string(cam.fx()) + ", " + std::to_string(cam.fy()) + " px)");
  }
  return cam;
}

void CheckPose(const ColmapImage& image, const fs::path& file, const std::string& where) {
  const Eigen::Quaterniond& q = image.cam_from_world.rotation;
  if (!q.coeffs().allFinite() || !image.cam_from_world.translation.allFinite()) {
    throw InputError(file, where + "image " + std::to_string(image.id) + " (" + image.name +
                               ") has a non-finite pose");
  }
  if (!IsValidRotation(q)) {
    throw InputError(file, where + "image " + std::to_string(image.id) + " (" + image.name +
                               ") has a quaternion of norm " + std::to_string(q.norm()) +
                               ", not a rotation");
  }
}

// Cross-references: image -> camera, point2D -> point3D, track -> image and point2D index.
void CheckReferences(const ColmapModel& m, const fs::path& images_file,
                     const fs::path& points_file) {
  for (const auto& [id, image] : m.images) {
    if (!m.cameras.count(image.camera_id)) {
      throw InputError(images_file, "image " + std::to_string(id) + " (" + image.name +
                                        ") refers to camera " + std::to_string(image.camera_id) +
                                        ", which cameras does not define");
    }
    for (const auto& p : image.points2d) {
      if (p.point3d_id != -1 && !m.points3d.count(p.point3d_id)) {
        throw InputError(images_file, "image " + std::to_string(id) + " refers to 3D point " +
                                          std::to_string(p.point3d_id) +
                                          ", which points3D does not define");
      }
    }
  }
  for (const auto& [id, point] : m.points3d) {
    if (!point.xyz.allFinite()) {
      throw InputError(points_file, "point " + std::to_string(id) + " is not finite");
    }
    for (const auto& t : point.track) {
      auto it = m.images.find(t.image_id);
      if (it == m.images.end()) {
        throw InputError(points_file, "point " + std::to_string(id) + " refers to image " +
                                          std::to_string(t.image_id) +
                                          ", which images does not define");
      }
      if (t.point2d_idx < 0 || t.point2d_idx >= static_cast<int>(it->second.points2d.size())) {
        throw InputError(points_file, "point " + std::to_string(id) + " refers to 2D point " +
                                          std::to_string(t.point2d_idx) + " of image " +
                                          std::to_string(t.image_id) + ", which has only " +
                                          std::to_string(it->second.points2d.size()));
      }
    }
  }
}

// ---------------------------------------------------------------- binary

// Little-endian reader over a memory buffer; every read is bounds-checked.
class BinaryReader {
 public:
  BinaryReader(std::string_view data, fs::path file) : data_(data), file_(std::move(file)) {}

  template <typename T>
  T Read() {
    static_assert(std::is_trivially_copyable_v<T>);
    Need(sizeof(T));
    T v;
    std::memcpy(&v, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  // A count of records of at least `min_record_bytes` each; refuses counts the remaining bytes
  // cannot hold, so that a corrupt count never drives a huge allocation.
  std::uint64_t ReadCount(size_t min_record_bytes, const char* what) {
    const std::uint64_t n = Read<std::uint64_t>();
    if (n > Remaining() / min_record_bytes) {
      throw InputError(file_, "claims " + std::to_string(n) + " " + what + " at byte " +
                                  std::to_string(pos_ - 8) + " but only " +
                                  std::to_string(Remaining()) +
                                  " bytes follow (truncated or corrupt)");
    }
    return n;
  }
  std::string ReadCString() {
    const size_t end = data_.find('\0', pos_);
    if (end == std::string_view::npos) Fail("unterminated image name");
    std::string s(data_.substr(pos_, end - pos_));
    pos_ = end + 1;
    return s;
  }
  size_t Remaining() const { return data_.size() - pos_; }
  size_t pos() const { return pos_; }
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(file_, what + " at byte " + std::to_string(pos_));
  }
  const fs::path& file() const { return file_; }

 private:
  void Need(size_t n) const {
    if (Remaining() < n) {
      throw InputError(file_, "truncated: needs " + std::to_string(n) + " more bytes at byte " +
                                  std::to_string(pos_) + " of " + std::to_string(data_.size()));
    }
  }
  std::string_view data_;
  size_t pos_ = 0;
  fs::path file_;
};

int ToIntId(std::uint64_t v, const BinaryReader& r, const char* what) {
  if (v > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) {
    r.Fail(std::string(what) + " " + std::to_string(v) + " is out of range");
  }
  return static_cast<int>(v);
}

void ParseCamerasBinary(BinaryReader& r, ColmapModel& m) {
  const std::uint64_t n = r.ReadCount(4 + 4 + 8 + 8, "cameras");
  for (std::uint64_t i = 0; i < n; ++i) {
    const int id = ToIntId(r.Read<std::uint32_t>(), r, "camera id");
    const int model_id = r.Read<std::int32_t>();
    const std::uint64_t width = r.Read<std::uint64_t>();
    const std::uint64_t height = r.Read<std::uint64_t>();
    int num_params = 0;
    try {
      num_params = CameraModelNumParams(CameraModelFromId(model_id));
    } catch (const std::invalid_argument&) {
      throw InputError(r.file(), "camera " + std::to_string(id) + ": unknown camera model " +
                                     std::to_string(model_id));
    }
    std::vector<double> params(num_params);
    for (double& p : params) p = r.Read<double>();
    if (m.cameras.count(id)) r.Fail("camera " + std::to_string(id) + " defined twice");
    m.cameras[id] = MakeCamera(id, model_id, "",
                               static_cast<std::int64_t>(std::min<std::uint64_t>(width, 1u << 30)),
                               static_cast<std::int64_t>(std::min<std::uint64_t>(height, 1u << 30)),
                               std::move(params), r.file(), "");
  }
  if (r.Remaining() != 0) r.Fail("unexpected trailing data");
}

void ParseImagesBinary(BinaryReader& r, ColmapModel& m) {
  const std::uint64_t n = r.ReadCount(4 + 7 * 8 + 4 + 1 + 8, "images");
  for (std::uint64_t i = 0; i < n; ++i) {
    ColmapImage image;
    image.id = ToIntId(r.Read<std::uint32_t>(), r, "image id");
    double q[4], t[3];
    for (double& v : q) v = r.Read<double>();
    for (double& v : t) v = r.Read<double>();
    image.cam_from_world =
        Rigid3d(Eigen::Quaterniond(q[0], q[1], q[2], q[3]), Eigen::Vector3d(t[0], t[1], t[2]));
    image.camera_id = ToIntId(r.Read<std::uint32_t>(), r, "camera id");
    image.name = r.ReadCString();
    if (image.name.empty()) r.Fail("image " + std::to_string(image.id) + " has an empty name");
    const std::uint64_t np = r.ReadCount(3 * 8, "2D points");
    image.points2d.resize(np);
    for (auto& p : image.points2d) {
      p.xy.x() = r.Read<double>();
      p.xy.y() = r.Read<double>();
      const std::uint64_t pid = r.Read<std::uint64_t>();
      if (pid == kInvalidPoint3DId) {
        p.point3d_id = -1;
      } else if (pid > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
        r.Fail("3D point id out of range");
      } else {
        p.point3d_id = static_cast<std::int64_t>(pid);
      }
    }
    CheckPose(image, r.file(), "");
    if (m.images.count(image.id)) r.Fail("image " + std::to_string(image.id) + " defined twice");
    m.images[image.id] = std::move(image);
  }
  if (r.Remaining() != 0) r.Fail("unexpected trailing data");
}

void ParsePoints3DBinary(BinaryReader& r, ColmapModel& m) {
  const std::uint64_t n = r.ReadCount(8 + 3 * 8 + 3 + 8 + 8, "3D points");
  for (std::uint64_t i = 0; i < n; ++i) {
    ColmapPoint3D p;
    const std::uint64_t id = r.Read<std::uint64_t>();
    if (id > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      r.Fail("3D point id out of range");
    }
    p.id = static_cast<std::int64_t>(id);
    for (int k = 0; k < 3; ++k) p.xyz[k] = r.Read<double>();
    for (auto& c : p.color) c = r.Read<std::uint8_t>();
    p.error = r.Read<double>();
    const std::uint64_t nt = r.ReadCount(8, "track elements");
    p.track.resize(nt);
    for (auto& t : p.track) {
      t.image_id = ToIntId(r.Read<std::uint32_t>(), r, "image id");
      t.point2d_idx = ToIntId(r.Read<std::uint32_t>(), r, "2D point index");
    }
    if (m.points3d.count(p.id)) r.Fail("3D point " + std::to_string(p.id) + " defined twice");
    m.points3d[p.id] = std::move(p);
  }
  if (r.Remaining() != 0) r.Fail("unexpected trailing data");
}

template <typename T>
void Put(std::string& out, T v) {
  static_assert(std::is_trivially_copyable_v<T>);
  char buf[sizeof(T)];
  std::memcpy(buf, &v, sizeof(T));
  out.append(buf, sizeof(T));
}

// ---------------------------------------------------------------- text

// Whitespace-separated tokens of one line, parsed with file and line in every error.
class LineTokens {
 public:
  LineTokens(std::string_view line, const fs::path& file, int line_no)
      : file_(file), line_no_(line_no) {
    size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      const size_t start = i;
      while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      if (i > start) tokens_.push_back(line.substr(start, i - start));
    }
  }
  size_t size() const { return tokens_.size(); }
  std::string Str(size_t i) const { return std::string(tokens_.at(i)); }
  double Double(size_t i) const {
    const std::string_view t = tokens_.at(i);
    double v = 0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || ptr != t.data() + t.size())
      Fail("'" + std::string(t) + "' is not a number");
    return v;
  }
  std::int64_t Int(size_t i) const {
    const std::string_view t = tokens_.at(i);
    std::int64_t v = 0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || ptr != t.data() + t.size()) {
      Fail("'" + std::string(t) + "' is not an integer");
    }
    return v;
  }
  int Id(size_t i, const char* what) const {
    const std::int64_t v = Int(i);
    if (v < 0 || v > std::numeric_limits<int>::max()) {
      Fail(std::string(what) + " " + std::to_string(v) + " is out of range");
    }
    return static_cast<int>(v);
  }
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(file_, "line " + std::to_string(line_no_) + ": " + what);
  }
  std::string Where() const { return "line " + std::to_string(line_no_) + ": "; }

 private:
  std::vector<std::string_view> tokens_;
  const fs::path& file_;
  int line_no_;
};

// Splits text into lines, tracking line numbers; skips comments and blank lines on request.
class LineStream {
 public:
  explicit LineStream(const std::string& text) : text_(text) {}
  // Next line (trimmed of '\r'); false at the end.
  bool Next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    size_t end = text_.find('\n', pos_);
    if (end == std::string::npos) end = text_.size();
    line = std::string_view(text_).substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    ++line_no_;
    return true;
  }
  // Next line that is neither blank nor a comment.
  bool NextData(std::string_view& line) {
    while (Next(line)) {
      size_t i = 0;
      while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      if (i < line.size() && line[i] != '#') return true;
    }
    return false;
  }
  int line_no() const { return line_no_; }

 private:
  const std::string& text_;
  size_t pos_ = 0;
  int line_no_ = 0;
};

void ParseCamerasText(const std::string& text, const fs::path& file, ColmapModel& m) {
  LineStream lines(text);
  std::string_view line;
  while (lines.NextData(line)) {
    const LineTokens tok(line, file, lines.line_no());
    if (tok.size() < 4) tok.Fail("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS...");
    const int id = tok.Id(0, "camera id");
    std::vector<double> params;
    for (size_t i = 4; i < tok.size(); ++i) params.push_back(tok.Double(i));
    if (m.cameras.count(id)) tok.Fail("camera " + std::to_string(id) + " defined twice");
    m.cameras[id] = MakeCamera(id, -1, tok.Str(1), tok.Int(2), tok.Int(3), std::move(params), file,
                               tok.Where());
  }
}

void ParseImagesText(const std::string& text, const fs::path& file, ColmapModel& m) {
  LineStream lines(text);
  std::string_view line;
  while (lines.NextData(line)) {
    const LineTokens tok(line, file, lines.line_no());
    if (tok.size() != 10) tok.Fail("expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    ColmapImage image;
    image.id = tok.Id(0, "image id");
    image.cam_from_world =
        Rigid3d(Eigen::Quaterniond(tok.Double(1), tok.Double(2), tok.Double(3), tok.Double(4)),
                Eigen::Vector3d(tok.Double(5), tok.Double(6), tok.Double(7)));
    image.camera_id = tok.Id(8, "camera id");
    image.name = tok.Str(9);
    CheckPose(image, file, tok.Where());
    // The points line always follows (empty when the image has no 2D points), as in COLMAP.
    std::string_view points_line;
    if (lines.Next(points_line)) {
      const LineTokens pts(points_line, file, lines.line_no());
      if (pts.size() % 3 != 0) pts.Fail("expected triples X Y POINT3D_ID");
      image.points2d.resize(pts.size() / 3);
      for (size_t k = 0; k < image.points2d.size(); ++k) {
        image.points2d[k].xy = Eigen::Vector2d(pts.Double(3 * k), pts.Double(3 * k + 1));
        const std::int64_t pid = pts.Int(3 * k + 2);
        if (pid < -1) pts.Fail("invalid 3D point id " + std::to_string(pid));
        image.points2d[k].point3d_id = pid;
      }
    }
    if (m.images.count(image.id)) tok.Fail("image " + std::to_string(image.id) + " defined twice");
    m.images[image.id] = std::move(image);
  }
}

void ParsePoints3DText(const std::string& text, const fs::path& file, ColmapModel& m) {
  LineStream lines(text);
  std::string_view line;
  while (lines.NextData(line)) {
    const LineTokens tok(line, file, lines.line_no());
    if (tok.size() < 8 || (tok.size() - 8) % 2 != 0) {
      tok.Fail("expected POINT3D_ID X Y Z R G B ERROR (IMAGE_ID POINT2D_IDX)...");
    }
    ColmapPoint3D p;
    p.id = tok.Int(0);
    if (p.id < 0) tok.Fail("invalid 3D point id " + std::to_string(p.id));
    p.xyz = Eigen::Vector3d(tok.Double(1), tok.Double(2), tok.Double(3));
    for (int c = 0; c < 3; ++c) {
      const std::int64_t v = tok.Int(4 + c);
      if (v < 0 || v > 255) tok.Fail("colour component " + std::to_string(v) + " is not 0..255");
      p.color[c] = static_cast<std::uint8_t>(v);
    }
    p.error = tok.Double(7);
    for (size_t i = 8; i < tok.size(); i += 2) {
      p.track.push_back({tok.Id(i, "image id"), tok.Id(i + 1, "2D point index")});
    }
    if (m.points3d.count(p.id)) tok.Fail("3D point " + std::to_string(p.id) + " defined twice");
    m.points3d[p.id] = std::move(p);
  }
}

std::string FormatDouble(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

}  // namespace

ColmapModel ParseColmapModelBinary(const std::string& cameras_bin, const std::string& images_bin,
                                   const std::string& points3d_bin, const fs::path& dir) {
  ColmapModel m;
  {
    BinaryReader r(cameras_bin, dir / "cameras.bin");
    ParseCamerasBinary(r, m);
  }
  {
    BinaryReader r(images_bin, dir / "images.bin");
    ParseImagesBinary(r, m);
  }
  {
    BinaryReader r(points3d_bin, dir / "points3D.bin");
    ParsePoints3DBinary(r, m);
  }
  CheckReferences(m, dir / "images.bin", dir / "points3D.bin");
  return m;
}

ColmapModel ReadColmapModelBinary(const fs::path& dir) {
  const std::string cameras = ReadFileToString(dir / "cameras.bin");
  const std::string images = ReadFileToString(dir / "images.bin");
  const std::string points = ReadFileToString(dir / "points3D.bin");
  return ParseColmapModelBinary(cameras, images, points, dir);
}

namespace {

// A TEXT model; without `with_points`, points3D.txt is not read (no point is then defined).
ColmapModel ReadText(const fs::path& dir, bool with_points) {
  ColmapModel m;
  ParseCamerasText(ReadFileToString(dir / "cameras.txt"), dir / "cameras.txt", m);
  ParseImagesText(ReadFileToString(dir / "images.txt"), dir / "images.txt", m);
  if (with_points) {
    ParsePoints3DText(ReadFileToString(dir / "points3D.txt"), dir / "points3D.txt", m);
  }
  CheckReferences(m, dir / "images.txt", dir / "points3D.txt");
  return m;
}

// Throws InputError unless `dir` is a folder.
void CheckModelFolder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw InputError(dir, fs::exists(dir, ec) ? "not a folder" : "no such model folder");
  }
}

}  // namespace

ColmapModel ReadColmapModelText(const fs::path& dir) { return ReadText(dir, true); }

ColmapModel ReadColmapCameras(const fs::path& dir) {
  CheckModelFolder(dir);
  if (IsFile(dir / "points3D.txt") || IsFile(dir / "points3D.bin")) return ReadColmapModel(dir);
  return ReadText(dir, false);
}

ColmapModel ReadColmapModel(const fs::path& dir) {
  CheckModelFolder(dir);
  const bool any_bin =
      IsFile(dir / "cameras.bin") || IsFile(dir / "images.bin") || IsFile(dir / "points3D.bin");
  const bool all_txt =
      IsFile(dir / "cameras.txt") && IsFile(dir / "images.txt") && IsFile(dir / "points3D.txt");
  const bool all_bin =
      IsFile(dir / "cameras.bin") && IsFile(dir / "images.bin") && IsFile(dir / "points3D.bin");
  if (all_bin || (any_bin && !all_txt)) return ReadColmapModelBinary(dir);  // names what's missing
  return ReadColmapModelText(dir);
}

ColmapBinaryFiles SerializeColmapModelBinary(const ColmapModel& model) {
  ColmapBinaryFiles f;
  Put<std::uint64_t>(f.cameras, model.cameras.size());
  for (const auto& [id, c] : model.cameras) {
    Put<std::uint32_t>(f.cameras, static_cast<std::uint32_t>(id));
    Put<std::int32_t>(f.cameras, static_cast<std::int32_t>(c.model));
    Put<std::uint64_t>(f.cameras, static_cast<std::uint64_t>(c.width));
    Put<std::uint64_t>(f.cameras, static_cast<std::uint64_t>(c.height));
    for (double p : c.params) Put<double>(f.cameras, p);
  }
  Put<std::uint64_t>(f.images, model.images.size());
  for (const auto& [id, im] : model.images) {
    Put<std::uint32_t>(f.images, static_cast<std::uint32_t>(id));
    const Eigen::Quaterniond& q = im.cam_from_world.rotation;
    for (double v : {q.w(), q.x(), q.y(), q.z()}) Put<double>(f.images, v);
    for (int k = 0; k < 3; ++k) Put<double>(f.images, im.cam_from_world.translation[k]);
    Put<std::uint32_t>(f.images, static_cast<std::uint32_t>(im.camera_id));
    f.images.append(im.name);
    f.images.push_back('\0');
    Put<std::uint64_t>(f.images, im.points2d.size());
    for (const auto& p : im.points2d) {
      Put<double>(f.images, p.xy.x());
      Put<double>(f.images, p.xy.y());
      Put<std::uint64_t>(f.images, p.point3d_id < 0 ? kInvalidPoint3DId
                                                    : static_cast<std::uint64_t>(p.point3d_id));
    }
  }
  Put<std::uint64_t>(f.points3d, model.points3d.size());
  for (const auto& [id, p] : model.points3d) {
    Put<std::uint64_t>(f.points3d, static_cast<std::uint64_t>(id));
    for (int k = 0; k < 3; ++k) Put<double>(f.points3d, p.xyz[k]);
    for (auto c : p.color) Put<std::uint8_t>(f.points3d, c);
    Put<double>(f.points3d, p.error);
    Put<std::uint64_t>(f.points3d, p.track.size());
    for (const auto& t : p.track) {
      Put<std::uint32_t>(f.points3d, static_cast<std::uint32_t>(t.image_id));
      Put<std::uint32_t>(f.points3d, static_cast<std::uint32_t>(t.point2d_idx));
    }
  }
  return f;
}

void WriteColmapModel(const ColmapModel& model, const fs::path& dir, ColmapFormat format) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir, "cannot create folder (" + ec.message() + ")");
  if (format == ColmapFormat::kBinary) {
    const ColmapBinaryFiles f = SerializeColmapModelBinary(model);
    WriteFileAtomic(dir / "cameras.bin", f.cameras);
    WriteFileAtomic(dir / "images.bin", f.images);
    WriteFileAtomic(dir / "points3D.bin", f.points3d);
    return;
  }
  std::ostringstream cams;
  cams << "# Camera list with one line of data per camera:\n"
       << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
       << "# Number of cameras: " << model.cameras.size() << "\n";
  for (const auto& [id, c] : model.cameras) {
    cams << id << " " << CameraModelName(c.model) << " " << c.width << " " << c.height;
    for (double p : c.params) cams << " " << FormatDouble(p);
    cams << "\n";
  }
  std::ostringstream ims;
  ims << "# Image list with two lines of data per image:\n"
      << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
      << "# Number of images: " << model.images.size() << "\n";
  for (const auto& [id, im] : model.images) {
    const Eigen::Quaterniond& q = im.cam_from_world.rotation;
    const Eigen::Vector3d& t = im.cam_from_world.translation;
    ims << id;
    for (double v : {q.w(), q.x(), q.y(), q.z(), t.x(), t.y(), t.z()})
      ims << " " << FormatDouble(v);
    ims << " " << im.camera_id << " " << im.name << "\n";
    for (size_t k = 0; k < im.points2d.size(); ++k) {
      const auto& p = im.points2d[k];
      ims << (k ? " " : "") << FormatDouble(p.xy.x()) << " " << FormatDouble(p.xy.y()) << " "
          << p.point3d_id;
    }
    ims << "\n";
  }
  std::ostringstream pts;
  pts << "# 3D point list with one line of data per point:\n"
      << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
      << "# Number of points: " << model.points3d.size() << "\n";
  for (const auto& [id, p] : model.points3d) {
    pts << id << " " << FormatDouble(p.xyz.x()) << " " << FormatDouble(p.xyz.y()) << " "
        << FormatDouble(p.xyz.z()) << " " << int(p.color[0]) << " " << int(p.color[1]) << " "
        << int(p.color[2]) << " " << FormatDouble(p.error);
    for (const auto& t : p.track) pts << " " << t.image_id << " " << t.point2d_idx;
    pts << "\n";
  }
  WriteFileAtomic(dir / "cameras.txt", cams.str());
  WriteFileAtomic(dir / "images.txt", ims.str());
  WriteFileAtomic(dir / "points3D.txt", pts.str());
}

bool IsColmapModelDir(const fs::path& dir) {
  const bool bin =
      IsFile(dir / "cameras.bin") && IsFile(dir / "images.bin") && IsFile(dir / "points3D.bin");
  const bool txt =
      IsFile(dir / "cameras.txt") && IsFile(dir / "images.txt") && IsFile(dir / "points3D.txt");
  return bin || txt;
}

}  // namespace hdribr
