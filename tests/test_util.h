// Helpers shared by the tests: temporary folders, shared datasets, running the CLI.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
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

}  // namespace hdribr::test

// Skips the current test with a clear message when a shared dataset is absent.
#define HDRIBR_REQUIRE_DATASET(var, name)                                              \
  const std::filesystem::path var = ::hdribr::test::SharedDataset(name);               \
  if (var.empty())                                                                     \
  GTEST_SKIP() << "shared dataset '" << name << "' is absent at " << HDRIBR_SHARED_DIR \
               << "/datasets: skipping"
