#include "io/ply.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/ply_io.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

constexpr size_t kMaxHeaderBytes = 1 << 16;
constexpr std::uint64_t kMaxElementCount = std::uint64_t{1} << 31;

// Byte size of a PLY scalar type name; 0 when unknown.
size_t ScalarSize(const std::string& t) {
  static const std::map<std::string, size_t> sizes = {
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  const auto it = sizes.find(t);
  return it == sizes.end() ? 0 : it->second;
}

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  size_t min_bytes = 0;  // binary: fixed part (scalars and list counts)
  size_t num_props = 0;
  std::set<std::string> props;
  std::vector<std::pair<std::string, std::string>> scalars;  // (name, type) in order
  bool has_list = false;
};

bool IsColorName(const std::string& n) {
  for (const char* c : {"red", "green", "blue", "alpha", "diffuse_red", "diffuse_green",
                        "diffuse_blue", "diffuse_alpha", "rgb", "rgba"}) {
    if (n == c) return true;
  }
  return false;
}

// PCL packs colour properties into one field and asserts (aborts) on any layout other than
// consecutive uchar red, green, blue, optionally followed by uchar alpha: refuse others here.
bool ColorLayoutSupported(const PlyElement& e) {
  const auto& s = e.scalars;
  size_t first = s.size();
  size_t count = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    if (IsColorName(s[i].first)) {
      if (first == s.size()) first = i;
      ++count;
    }
  }
  if (count == 0) return true;
  const char* order[] = {"red", "green", "blue", "alpha"};
  if (count != 3 && count != 4) return false;
  for (size_t k = 0; k < count; ++k) {
    if (first + k >= s.size() || s[first + k].first != order[k]) return false;
    const std::string& t = s[first + k].second;
    if (t != "uchar" && t != "uint8") return false;
  }
  return true;
}

struct PlyHeader {
  bool ascii = false;
  std::uint64_t vertex_count = 0;
  std::set<std::string> vertex_props;
};

// Our own strict check of the header and the body size before PCL sees the file: PCL sizes its
// buffers from the header's counts, so a corrupt count must be refused here.
PlyHeader ValidateHeader(std::string_view head, std::uint64_t file_size, const fs::path& name) {
  auto fail = [&](const std::string& what) -> void {
    throw InputError(name, "corrupt PLY: " + what);
  };
  if (head.substr(0, 4) != "ply\n" && head.substr(0, 5) != "ply\r\n") {
    throw InputError(name, "not a PLY file (no 'ply' magic)");
  }
  // The header ends at the first line that is exactly "end_header" (as PCL parses it).
  size_t end = std::string_view::npos;
  size_t body = 0;
  for (size_t pos = 0; pos < head.size();) {
    const size_t nl = head.find('\n', pos);
    if (nl == std::string_view::npos) break;
    std::string_view l = head.substr(pos, nl - pos);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    if (l == "end_header") {
      end = pos;
      body = nl + 1;
      break;
    }
    pos = nl + 1;
  }
  if (end == std::string_view::npos) fail("no end_header line within the first 64 KiB");

  for (size_t i = 0; i < body; ++i) {
    const unsigned char c = static_cast<unsigned char>(head[i]);
    if ((c < 0x20 && c != '\n' && c != '\r' && c != '\t') || c >= 0x7F) {
      fail("header has a non-text byte at offset " + std::to_string(i));
    }
  }
  PlyHeader h;
  std::vector<PlyElement> elements;
  bool have_format = false;
  std::istringstream lines{std::string(head.substr(0, end))};
  std::string line;
  std::getline(lines, line);  // "ply"
  int line_no = 1;
  while (std::getline(lines, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    const std::string at = "header line " + std::to_string(line_no) + ": ";
    if (kw.empty() || kw == "comment" || kw == "obj_info") continue;
    auto no_more = [&] {
      std::string extra;
      if (ls >> extra) fail(at + "unexpected '" + extra + "'");
    };
    if (kw == "format") {
      std::string fmt, version;
      ls >> fmt >> version;
      no_more();
      if (fmt == "ascii") {
        h.ascii = true;
      } else if (fmt != "binary_little_endian" && fmt != "binary_big_endian") {
        fail(at + "unknown format '" + fmt + "'");
      }
      if (version != "1.0") fail(at + "unsupported version '" + version + "'");
      have_format = true;
    } else if (kw == "element") {
      PlyElement e;
      std::string count;
      ls >> e.name >> count;
      no_more();
      if (e.name.empty() || count.empty() ||
          count.find_first_not_of("0123456789") != std::string::npos || count.size() > 12) {
        fail(at + "bad element line");
      }
      e.count = std::stoull(count);
      if (e.count > kMaxElementCount) fail(at + "absurd element count " + count);
      elements.push_back(e);
    } else if (kw == "property") {
      if (elements.empty()) fail(at + "property before any element");
      PlyElement& e = elements.back();
      std::string type, pname;
      ls >> type;
      if (type == "list") {
        std::string count_type, item_type;
        ls >> count_type >> item_type >> pname;
        no_more();
        const size_t cs = ScalarSize(count_type);
        if (cs == 0 || ScalarSize(item_type) == 0 || pname.empty()) fail(at + "bad list property");
        if (count_type == "float" || count_type == "float32" || count_type == "double" ||
            count_type == "float64") {
          fail(at + "list count type must be an integer");
        }
        e.min_bytes += cs;
        e.has_list = true;
      } else {
        ls >> pname;
        no_more();
        const size_t s = ScalarSize(type);
        if (s == 0 || pname.empty()) fail(at + "bad property '" + line + "'");
        e.min_bytes += s;
        e.scalars.emplace_back(pname, type);
      }
      if (!e.props.insert(pname).second) fail(at + "property '" + pname + "' given twice");
      ++e.num_props;
    } else {
      fail(at + "unknown keyword '" + kw + "'");
    }
  }
  if (!have_format) fail("no format line");

  std::uint64_t remaining = file_size >= body ? file_size - body : 0;
  bool found_vertex = false;
  for (const auto& e : elements) {
    if (e.num_props == 0) fail("element '" + e.name + "' has no properties");
    // Bytes each record needs at least: binary exact fixed part; ASCII one digit and a separator
    // per property.
    const std::uint64_t per = h.ascii ? 2 * e.num_props - 1 : e.min_bytes;
    if (e.count > 0 && e.count > remaining / per) {
      throw InputError(name, "truncated PLY: element '" + e.name + "' declares " +
                                 std::to_string(e.count) + " records but only " +
                                 std::to_string(remaining) + " bytes of data remain");
    }
    remaining -= e.count * per;
    if (e.name == "vertex") {
      if (found_vertex) fail("two vertex elements");
      found_vertex = true;
      if (e.has_list) fail("vertex element with a list property is not supported");
      if (!ColorLayoutSupported(e)) {
        fail("unsupported vertex colour layout (need consecutive uchar red, green, blue[, alpha])");
      }
      h.vertex_count = e.count;
      h.vertex_props = e.props;
    }
  }
  if (!found_vertex) fail("no vertex element");
  for (const char* p : {"x", "y", "z"}) {
    if (!h.vertex_props.count(p)) fail(std::string("vertex has no '") + p + "' property");
  }
  if (h.vertex_count == 0) throw InputError(name, "PLY has no vertices");
  return h;
}

// Reads scalar field `f` of point i from a PCL blob as double.
double FieldValue(const pcl::PCLPointCloud2& c, const pcl::PCLPointField& f, size_t i,
                  std::uint32_t element = 0) {
  const std::uint8_t* p = c.data.data() + i * c.point_step + f.offset;
  auto get = [&](auto tag) {
    decltype(tag) v;
    std::memcpy(&v, p + element * sizeof(v), sizeof(v));
    return static_cast<double>(v);
  };
  switch (f.datatype) {
    case pcl::PCLPointField::INT8:
      return get(std::int8_t{});
    case pcl::PCLPointField::UINT8:
      return get(std::uint8_t{});
    case pcl::PCLPointField::INT16:
      return get(std::int16_t{});
    case pcl::PCLPointField::UINT16:
      return get(std::uint16_t{});
    case pcl::PCLPointField::INT32:
      return get(std::int32_t{});
    case pcl::PCLPointField::UINT32:
      return get(std::uint32_t{});
    case pcl::PCLPointField::FLOAT32:
      return get(float{});
    case pcl::PCLPointField::FLOAT64:
      return get(double{});
    default:
      return std::nan("");
  }
}

size_t FieldSize(std::uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8:
    case pcl::PCLPointField::UINT8:
      return 1;
    case pcl::PCLPointField::INT16:
    case pcl::PCLPointField::UINT16:
      return 2;
    case pcl::PCLPointField::INT32:
    case pcl::PCLPointField::UINT32:
    case pcl::PCLPointField::FLOAT32:
      return 4;
    case pcl::PCLPointField::FLOAT64:
      return 8;
    default:
      return 0;
  }
}

const pcl::PCLPointField* FindField(const pcl::PCLPointCloud2& c,
                                    std::initializer_list<const char*> names) {
  for (const char* n : names) {
    for (const auto& f : c.fields) {
      if (f.name == n) return &f;
    }
  }
  return nullptr;
}

// Reads a PLY file already checked by ValidateHeader through PCL; `name` labels errors.
PointCloud ReadWithPcl(const fs::path& file, const PlyHeader& header, const fs::path& name) {
  pcl::PCLPointCloud2 blob;
  int rc = -1;
  {
    static std::mutex mutex;  // PCL's console verbosity is global
    std::lock_guard<std::mutex> lock(mutex);
    const auto old_level = pcl::console::getVerbosityLevel();
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    try {
      pcl::PLYReader reader;
      Eigen::Vector4f origin;
      Eigen::Quaternionf orientation;
      int ply_version = 0;
      rc = reader.read(file.string(), blob, origin, orientation, ply_version, 0);
    } catch (const std::exception& e) {
      pcl::console::setVerbosityLevel(old_level);
      throw InputError(name, std::string("corrupt PLY (") + e.what() + ")");
    } catch (...) {
      pcl::console::setVerbosityLevel(old_level);
      throw InputError(name, "corrupt PLY");
    }
    pcl::console::setVerbosityLevel(old_level);
  }
  if (rc < 0) throw InputError(name, "corrupt or truncated PLY (the PLY parser failed)");
  const std::uint64_t n = std::uint64_t{blob.width} * blob.height;
  if (n != header.vertex_count) {
    throw InputError(name, "truncated PLY: read " + std::to_string(n) + " of " +
                               std::to_string(header.vertex_count) + " vertices");
  }
  if (blob.data.size() < n * blob.point_step) throw InputError(name, "corrupt PLY (short data)");
  for (const auto& f : blob.fields) {
    const size_t fs = FieldSize(f.datatype);
    if (fs == 0 || f.offset + fs * std::max<std::uint32_t>(f.count, 1) > blob.point_step) {
      throw InputError(name, "corrupt PLY (field '" + f.name + "' has an invalid layout)");
    }
  }

  const auto* fx = FindField(blob, {"x"});
  const auto* fy = FindField(blob, {"y"});
  const auto* fz = FindField(blob, {"z"});
  if (!fx || !fy || !fz) throw InputError(name, "PLY vertices lack x, y or z");
  const auto* fnx = FindField(blob, {"normal_x", "nx"});
  const auto* fny = FindField(blob, {"normal_y", "ny"});
  const auto* fnz = FindField(blob, {"normal_z", "nz"});
  const auto* frgb = FindField(blob, {"rgb", "rgba"});
  const auto* fr = FindField(blob, {"red", "r"});
  const auto* fg = FindField(blob, {"green", "g"});
  const auto* fb = FindField(blob, {"blue", "b"});
  const auto* frad = FindField(blob, {"radius", "scale"});

  PointCloud cloud;
  cloud.positions.resize(n);
  const bool normals = fnx && fny && fnz;
  const bool packed = frgb != nullptr;
  const bool colors = packed || (fr && fg && fb);
  if (normals) cloud.normals.resize(n);
  if (colors) cloud.colors.resize(n);
  if (frad) cloud.radii.resize(n);
  for (size_t i = 0; i < n; ++i) {
    cloud.positions[i] = Eigen::Vector3d(FieldValue(blob, *fx, i), FieldValue(blob, *fy, i),
                                         FieldValue(blob, *fz, i))
                             .cast<float>();
    if (normals) {
      cloud.normals[i] = Eigen::Vector3d(FieldValue(blob, *fnx, i), FieldValue(blob, *fny, i),
                                         FieldValue(blob, *fnz, i))
                             .cast<float>();
    }
    if (packed) {
      std::uint32_t v;  // PCL packs red, green, blue as 0x00RRGGBB
      std::memcpy(&v, blob.data.data() + i * blob.point_step + frgb->offset, sizeof(v));
      cloud.colors[i] = {static_cast<std::uint8_t>((v >> 16) & 0xFF),
                         static_cast<std::uint8_t>((v >> 8) & 0xFF),
                         static_cast<std::uint8_t>(v & 0xFF)};
    } else if (colors) {
      auto c8 = [](double v) {
        return static_cast<std::uint8_t>(std::isfinite(v) ? std::clamp(v, 0.0, 255.0) : 0.0);
      };
      cloud.colors[i] = {c8(FieldValue(blob, *fr, i)), c8(FieldValue(blob, *fg, i)),
                         c8(FieldValue(blob, *fb, i))};
    }
    if (frad) cloud.radii[i] = static_cast<float>(FieldValue(blob, *frad, i));
  }
  for (size_t i = 0; i < n; ++i) {
    if (!cloud.positions[i].allFinite() || (normals && !cloud.normals[i].allFinite()) ||
        (frad && !(std::isfinite(cloud.radii[i]) && cloud.radii[i] >= 0))) {
      throw InputError(name, "vertex " + std::to_string(i) +
                                 " has a non-finite position or normal or an invalid radius");
    }
  }
  return cloud;
}

std::string ReadHead(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::error_code ec;
    throw InputError(path, fs::exists(path, ec) ? "cannot open" : "no such file");
  }
  std::string head(kMaxHeaderBytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  return head;
}

template <typename T>
void PutLE(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

}  // namespace

PointCloud ReadPly(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError(path, fs::exists(path, ec) ? "not a file" : "no such file");
  }
  const std::string head = ReadHead(path);
  const std::uint64_t size = fs::file_size(path, ec);
  if (ec) throw InputError(path, "cannot stat (" + ec.message() + ")");
  if (size == 0) throw InputError(path, "empty file");
  const PlyHeader header = ValidateHeader(head, size, path);
  return ReadWithPcl(path, header, path);
}

PointCloud ParsePly(const std::string& bytes, const fs::path& name) {
  const PlyHeader header =
      ValidateHeader(std::string_view(bytes).substr(0, kMaxHeaderBytes), bytes.size(), name);
  // PCL reads files only: parse a private temporary copy.
  static std::atomic<int> counter{0};
  const fs::path tmp = fs::temp_directory_path() / ("hdribr_parse_" + std::to_string(::getpid()) +
                                                    "_" + std::to_string(counter++) + ".ply");
  struct Remove {
    fs::path p;
    ~Remove() {
      std::error_code ec;
      fs::remove(p, ec);
    }
  } remove{tmp};
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw InputError(tmp, "cannot write temporary file");
  }
  return ReadWithPcl(tmp, header, name);
}

void WritePly(const fs::path& path, const PointCloud& cloud, bool binary) {
  if (!cloud.IsConsistent()) {
    throw UsageError("WritePly: " + path.string() + ": point attributes are inconsistent");
  }
  const size_t n = cloud.size();
  std::string out;
  out += "ply\n";
  out += binary ? "format binary_little_endian 1.0\n" : "format ascii 1.0\n";
  out += "comment written by hdribr\n";
  out += "element vertex " + std::to_string(n) + "\n";
  out += "property float x\nproperty float y\nproperty float z\n";
  if (cloud.HasNormals()) out += "property float nx\nproperty float ny\nproperty float nz\n";
  if (cloud.HasColors()) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (cloud.HasRadii()) out += "property float radius\n";
  out += "end_header\n";
  char buf[64];
  for (size_t i = 0; i < n; ++i) {
    if (binary) {
      for (int k = 0; k < 3; ++k) PutLE<float>(out, cloud.positions[i][k]);
      if (cloud.HasNormals()) {
        for (int k = 0; k < 3; ++k) PutLE<float>(out, cloud.normals[i][k]);
      }
      if (cloud.HasColors()) out.append(reinterpret_cast<const char*>(cloud.colors[i].data()), 3);
      if (cloud.HasRadii()) PutLE<float>(out, cloud.radii[i]);
    } else {
      const auto& p = cloud.positions[i];
      std::snprintf(buf, sizeof(buf), "%.9g %.9g %.9g", p.x(), p.y(), p.z());
      out += buf;
      if (cloud.HasNormals()) {
        const auto& v = cloud.normals[i];
        std::snprintf(buf, sizeof(buf), " %.9g %.9g %.9g", v.x(), v.y(), v.z());
        out += buf;
      }
      if (cloud.HasColors()) {
        const auto& c = cloud.colors[i];
        std::snprintf(buf, sizeof(buf), " %d %d %d", c[0], c[1], c[2]);
        out += buf;
      }
      if (cloud.HasRadii()) {
        std::snprintf(buf, sizeof(buf), " %.9g", cloud.radii[i]);
        out += buf;
      }
      out += "\n";
    }
  }
  WriteFileAtomic(path, out);
}

}  // namespace hdribr
