#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/colmap_model_internal.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kInvalidPoint3DId = std::numeric_limits<std::uint64_t>::max();

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
    m.cameras[id] = MakeColmapCamera(
        id, model_id, "", static_cast<std::int64_t>(std::min<std::uint64_t>(width, 1u << 30)),
        static_cast<std::int64_t>(std::min<std::uint64_t>(height, 1u << 30)), std::move(params),
        r.file(), "");
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
    CheckColmapPose(image, r.file(), "");
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
  CheckColmapReferences(m, dir / "images.bin", dir / "points3D.bin");
  return m;
}

ColmapModel ReadColmapModelBinary(const fs::path& dir) {
  const std::string cameras = ReadFileToString(dir / "cameras.bin");
  const std::string images = ReadFileToString(dir / "images.bin");
  const std::string points = ReadFileToString(dir / "points3D.bin");
  return ParseColmapModelBinary(cameras, images, points, dir);
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

}  // namespace hdribr
