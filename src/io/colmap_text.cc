#include <cctype>
#include <charconv>
#include <cstdio>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/colmap_model_internal.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

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
    m.cameras[id] = MakeColmapCamera(id, -1, tok.Str(1), tok.Int(2), tok.Int(3), std::move(params),
                                     file, tok.Where());
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
    CheckColmapPose(image, file, tok.Where());
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

ColmapModel ReadColmapText(const fs::path& dir, bool with_points) {
  ColmapModel m;
  ParseCamerasText(ReadFileToString(dir / "cameras.txt"), dir / "cameras.txt", m);
  ParseImagesText(ReadFileToString(dir / "images.txt"), dir / "images.txt", m);
  if (with_points) {
    ParsePoints3DText(ReadFileToString(dir / "points3D.txt"), dir / "points3D.txt", m);
  }
  CheckColmapReferences(m, dir / "images.txt", dir / "points3D.txt");
  return m;
}

ColmapModel ReadColmapModelText(const fs::path& dir) { return ReadColmapText(dir, true); }

ColmapTextFiles SerializeColmapModelText(const ColmapModel& model) {
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
  return {cams.str(), ims.str(), pts.str()};
}

}  // namespace hdribr
