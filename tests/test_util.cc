#include "test_util.h"

#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cstdio>
#include <exception>
#include <system_error>

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

namespace {

fs::path SharedFixturePath(const std::string& name) {
  return fs::path(HDRIBR_TEST_FIXTURES) / name;
}

// Makes it in a folder of this process beside its place, then renames that into place; when
// another process made it meanwhile, its copy is kept and this one removed.
void MakeSharedFixture(const std::string& name, const FixtureMaker& make) {
  const fs::path dir = SharedFixturePath(name);
  const fs::path partial = dir.parent_path() / ("." + name + ".partial" + std::to_string(getpid()));
  fs::remove_all(partial);
  fs::create_directories(partial);
  bool made = false;
  try {
    make(partial);
    made = !::testing::Test::HasFatalFailure() && !::testing::Test::IsSkipped();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "shared fixture " << name << ": " << e.what();
  }
  std::error_code ec;
  if (made) fs::rename(partial, dir, ec);
  if (!made || ec) fs::remove_all(partial);
}

}  // namespace

fs::path SharedFixture(const std::string& name, const FixtureMaker& make) {
  const fs::path dir = SharedFixturePath(name);
  if (!fs::is_directory(dir)) MakeSharedFixture(name, make);
  EXPECT_TRUE(fs::is_directory(dir)) << "shared fixture " << name << " could not be made";
  return dir;
}

void RemakeSharedFixture(const std::string& name, const FixtureMaker& make) {
  fs::remove_all(SharedFixturePath(name));
  MakeSharedFixture(name, make);
  if (::testing::Test::IsSkipped()) return;
  EXPECT_TRUE(fs::is_directory(SharedFixturePath(name)))
      << "shared fixture " << name << " was not made";
}

}  // namespace hdribr::test
