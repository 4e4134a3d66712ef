// Atomic output: write to a temporary sibling, then rename over the target on Commit().
#pragma once

#include <filesystem>

namespace hdribr {

// Usage: AtomicFile f(out); write to f.temp_path(); f.Commit();  If Commit() is never called
// (an exception), the temporary file is removed and the target is left untouched.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Temporary path in the target's folder, keeping the target's extension (codecs pick the
  // format from it).
  const std::filesystem::path& temp_path() const { return temp_; }
  const std::filesystem::path& target() const { return target_; }
  // Renames the temporary file over the target. Throws InputError if it cannot.
  void Commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  bool committed_ = false;
};

// Atomically replaces `target` with `contents`.
void WriteFileAtomic(const std::filesystem::path& target, const std::string& contents);
// Reads a whole file; throws InputError naming the file if it cannot.
std::string ReadFileToString(const std::filesystem::path& path);

}  // namespace hdribr
