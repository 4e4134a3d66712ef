#include "io/atomic_file.h"

#include <unistd.h>
#include <atomic>
#include <fstream>
#include <sstream>
#include <system_error>

#include "core/error.h"

namespace hdribr {
namespace fs = std::filesystem;

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)) {
  static std::atomic<int> counter{0};
  const std::string tag = ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
  // Keep the extension last so that OpenCV/OpenEXR pick the codec from it.
  temp_ =
      target_.parent_path() / ("." + target_.stem().string() + tag + target_.extension().string());
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

void AtomicFile::Commit() {
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) throw InputError(target_, "cannot write (" + ec.message() + ")");
  committed_ = true;
}

void WriteFileAtomic(const fs::path& target, const std::string& contents) {
  AtomicFile file(target);
  {
    std::ofstream out(file.temp_path(), std::ios::binary);
    if (!out) throw InputError(target, "cannot open for writing");
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) throw InputError(target, "write failed");
  }
  file.Commit();
}

std::string ReadFileToString(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, fs::exists(path) ? "cannot open" : "no such file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace hdribr
