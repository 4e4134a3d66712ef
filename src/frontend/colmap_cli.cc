#include "frontend/colmap_cli.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/error.h"

extern char** environ;

namespace hdribr {
namespace fs = std::filesystem;

std::string ColmapCapabilities::Pick(const std::vector<std::string>& candidates) const {
  for (const auto& c : candidates) {
    if (options.count(c)) return c;
  }
  return "";
}

void ParseColmapBanner(const std::string& text, ColmapCapabilities& caps) {
  static const std::regex banner(R"(COLMAP\s+([0-9][0-9.]*[0-9A-Za-z.-]*)[^\n]*)");
  std::smatch m;
  if (std::regex_search(text, m, banner)) {
    caps.version = m[1];
    const std::string line = m[0];
    caps.has_cuda = line.find("with CUDA") != std::string::npos;
  }
}

void ParseColmapOptions(const std::string& help_text, ColmapCapabilities& caps) {
  static const std::regex option(R"(--([A-Za-z_]+\.[A-Za-z_0-9]+))");
  for (auto it = std::sregex_iterator(help_text.begin(), help_text.end(), option);
       it != std::sregex_iterator(); ++it) {
    caps.options.insert((*it)[1]);
  }
}

std::optional<fs::path> FindExecutable(const std::string& name) {
  if (name.find('/') != std::string::npos) {
    if (::access(name.c_str(), X_OK) == 0) return fs::absolute(name);
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  if (!path) return std::nullopt;
  std::stringstream ss(path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    if (dir.empty()) continue;
    const fs::path candidate = fs::path(dir) / name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
  }
  return std::nullopt;
}

std::optional<ColmapProgress> ParseColmapProgressLine(const std::string& line, long num_images) {
  // mapper: "Registering image #12 (5)" -> 5 registered of num_images.
  static const std::regex reg(R"(Registering image #\d+ \((\d+)\))");
  // exhaustive matcher: "Matching block [2/3, 1/3]".
  static const std::regex block2(R"(\[(\d+)/(\d+),\s*(\d+)/(\d+)\])");
  // extractor, sequential matcher, undistorter: "Processed file [3/23]", "[3/23]".
  static const std::regex one(R"(\[(\d+)/(\d+)\])");
  std::smatch m;
  if (std::regex_search(line, m, reg)) {
    return ColmapProgress{std::stol(m[1]), num_images};
  }
  if (std::regex_search(line, m, block2)) {
    const long i = std::stol(m[1]), n = std::stol(m[2]), j = std::stol(m[3]), k = std::stol(m[4]);
    return ColmapProgress{(i - 1) * k + j, n * k};
  }
  if (std::regex_search(line, m, one)) {
    return ColmapProgress{std::stol(m[1]), std::stol(m[2])};
  }
  return std::nullopt;
}

int RunLogged(const fs::path& exe, const std::vector<std::string>& args, const fs::path& log_path,
              const std::function<void(const std::string&)>& on_line) {
  std::ofstream log(log_path, std::ios::app);
  log << "$ " << exe.string();
  for (const auto& a : args) log << ' ' << a;
  log << "\n" << std::flush;

  int fds[2];
  if (::pipe(fds) != 0) return 127;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  posix_spawn_file_actions_addclose(&actions, fds[1]);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);

  std::vector<std::string> argv_s;
  argv_s.push_back(exe.string());
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : argv_s) argv.push_back(s.data());
  argv.push_back(nullptr);

  pid_t pid = 0;
  const int rc = posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    log << "could not start: " << std::strerror(rc) << "\n";
    return 127;
  }
  std::string line;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof(buf));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    log.write(buf, n);
    for (ssize_t i = 0; i < n; ++i) {
      if (buf[i] == '\n' || buf[i] == '\r') {
        if (!line.empty() && on_line) on_line(line);
        line.clear();
      } else {
        line.push_back(buf[i]);
      }
    }
  }
  if (!line.empty() && on_line) on_line(line);
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  log.flush();
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 1;
}

std::string LastLines(const fs::path& path, int n) {
  std::ifstream in(path);
  std::deque<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    // Keep only the part after the last carriage return (progress lines).
    const size_t cr = line.find_last_of('\r');
    if (cr != std::string::npos) line = line.substr(cr + 1);
    if (line.empty()) continue;
    lines.push_back(line);
    if (static_cast<int>(lines.size()) > n) lines.pop_front();
  }
  std::string out;
  for (const auto& l : lines) out += "  | " + l + "\n";
  return out;
}

ColmapCapabilities ProbeColmap(const fs::path& exe) {
  ColmapCapabilities caps;
  const fs::path log =
      fs::temp_directory_path() / ("hdribr_colmap_probe_" + std::to_string(::getpid()) + ".txt");
  for (const char* cmd :
       {"feature_extractor", "exhaustive_matcher", "sequential_matcher", "vocab_tree_matcher",
        "matches_importer", "mapper", "image_undistorter"}) {
    std::string text;
    RunLogged(exe, {cmd, "-h"}, log, [&](const std::string& l) { text += l + "\n"; });
    if (caps.version.empty()) ParseColmapBanner(text, caps);
    ParseColmapOptions(text, caps);
  }
  std::error_code ec;
  fs::remove(log, ec);
  return caps;
}

}  // namespace hdribr
