#include "test_util.h"

#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cstdio>

namespace hdribr::test {
namespace fs = std::filesystem;

fs::path TempDir(const std::string& tag) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  // Outside a test (SetUpTestSuite) the folder is per process: CTest runs each test of a
  // suite in its own process, in parallel, and each builds the suite's fixture.
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name()
                          : "suite" + std::to_string(getpid());
  for (char& c : name) {
    if (c == '/') c = '_';
  }
  fs::path dir = fs::path(HDRIBR_TEST_TMP) / (name + tag);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

fs::path SharedDataset(const std::string& name) {
  fs::path p = fs::path(HDRIBR_SHARED_DIR) / "datasets" / name;
  return fs::is_directory(p) ? p : fs::path();
}

CommandResult RunCommand(const std::string& command_line) {
  CommandResult r;
  FILE* pipe = ::popen((command_line + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

}  // namespace hdribr::test
