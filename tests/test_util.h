// Helpers shared by the tests: temporary folders, shared datasets, running the CLI.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>

namespace hdribr::test {

// A fresh empty folder under the build tree's test_tmp/, unique per test.
std::filesystem::path TempDir(const std::string& tag = "");
// ../shared/datasets/<name>, or an empty path when absent (callers GTEST_SKIP with a message).
std::filesystem::path SharedDataset(const std::string& name);

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};
// Runs a shell command line, capturing its output.
CommandResult RunCommand(const std::string& command_line);

// Shared fixtures: a folder that the tests of several processes read (CTest runs each test in
// a process of its own), made once per CTest run into the build tree's test_fixtures/NAME by
// the fixture's setup test, TEST(Fixture, NAME), which CTest runs first (hdribr_fixture in
// tests/CMakeLists.txt). `make(dir)` writes it into the empty folder `dir`; it may use gtest
// assertions, and a fixture whose making fails fatally, throws or skips is not kept. The folder
// appears complete or not at all (made beside it, then renamed), and is read-only by
// convention: the tests that read it write their outputs elsewhere.
using FixtureMaker = std::function<void(const std::filesystem::path& dir)>;
// The fixture's folder; made first when absent (a test run alone, without its setup test).
std::filesystem::path SharedFixture(const std::string& name, const FixtureMaker& make);
// Makes the fixture afresh, replacing the one of an earlier run: the setup test's body.
void RemakeSharedFixture(const std::string& name, const FixtureMaker& make);

}  // namespace hdribr::test

// Skips the current test with a clear message when a shared dataset is absent.
#define HDRIBR_REQUIRE_DATASET(var, name)                                              \
  const std::filesystem::path var = ::hdribr::test::SharedDataset(name);               \
  if (var.empty())                                                                     \
  GTEST_SKIP() << "shared dataset '" << name << "' is absent at " << HDRIBR_SHARED_DIR \
               << "/datasets: skipping"
