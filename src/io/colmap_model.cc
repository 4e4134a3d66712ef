#include "io/colmap_model.h"

#include <system_error>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/colmap_model_internal.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

bool IsFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// Throws InputError unless `dir` is a folder.
void CheckModelFolder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw InputError(dir, fs::exists(dir, ec) ? "not a folder" : "no such model folder");
  }
}

}  // namespace

ColmapModel ReadColmapCameras(const fs::path& dir) {
  CheckModelFolder(dir);
  if (IsFile(dir / "points3D.txt") || IsFile(dir / "points3D.bin")) return ReadColmapModel(dir);
  return ReadColmapText(dir, false);
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
  const ColmapTextFiles f = SerializeColmapModelText(model);
  WriteFileAtomic(dir / "cameras.txt", f.cameras);
  WriteFileAtomic(dir / "images.txt", f.images);
  WriteFileAtomic(dir / "points3D.txt", f.points3d);
}

bool IsColmapModelDir(const fs::path& dir) {
  const bool bin =
      IsFile(dir / "cameras.bin") && IsFile(dir / "images.bin") && IsFile(dir / "points3D.bin");
  const bool txt =
      IsFile(dir / "cameras.txt") && IsFile(dir / "images.txt") && IsFile(dir / "points3D.txt");
  return bin || txt;
}

}  // namespace hdribr
