// Driving the `colmap` executable: finding it, probing its options, running it with a log.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace hdribr {

// What one `colmap` build offers, parsed from its help output (never assumed).
struct ColmapCapabilities {
  std::string version;            // "3.8", empty when not found
  bool has_cuda = false;          // "with CUDA" in the banner
  std::set<std::string> options;  // option names without "--", e.g. "SiftExtraction.use_gpu"

  // First candidate present in `options`, or "" (the option is then not passed at all).
  std::string Pick(const std::vector<std::string>& candidates) const;
};

// Parses the banner line ("COLMAP 3.8 (Commit ... with CUDA)") of any colmap output.
void ParseColmapBanner(const std::string& text, ColmapCapabilities& caps);
// Adds every "--Name.option" found in a `colmap <command> -h` output to caps.options.
void ParseColmapOptions(const std::string& help_text, ColmapCapabilities& caps);

// Absolute path of an executable found in PATH, or nullopt.
std::optional<std::filesystem::path> FindExecutable(const std::string& name);

// Progress parsed from a line of colmap output: done/total, or nullopt.
struct ColmapProgress {
  long done = 0;
  long total = 0;
};
std::optional<ColmapProgress> ParseColmapProgressLine(const std::string& line, long num_images);

// Runs a process with stdout+stderr appended to log_path; calls on_line for each output line
// (from a reader thread). Returns the exit status (128+signal when killed, 127 when it could
// not be started).
int RunLogged(const std::filesystem::path& exe, const std::vector<std::string>& args,
              const std::filesystem::path& log_path,
              const std::function<void(const std::string&)>& on_line);

// The last n lines of a text file (for error messages).
std::string LastLines(const std::filesystem::path& path, int n);

// Probes `colmap -h`, `colmap feature_extractor -h`, matchers' and mapper's help.
ColmapCapabilities ProbeColmap(const std::filesystem::path& exe);

}  // namespace hdribr
