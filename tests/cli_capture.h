// Shared set-up of the CLI integration tests (render, view, hdr CLI tests): one small
// synthetic capture per test suite, the hdribr executable, and xvfb-run for the viewer.
// Header-only: the including test links hdribr_synth and defines HDRIBR_EXE (hdribr_test).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "synth/capture.h"
#include "test_util.h"

namespace hdribr::test {

// Size of the photos of WriteSmallCapture.
inline constexpr int kSmallCaptureWidth = 128;
inline constexpr int kSmallCaptureHeight = 96;

// A 128x96 capture of `series` exposure series x 4 views and one novel view, in a fresh
// TempDir(tag); returns its folder (the workspace is <folder>/workspace).
inline std::filesystem::path WriteSmallCapture(const std::string& tag, int series) {
  const std::filesystem::path dir = TempDir(tag) / "capture";
  synth::CaptureOptions opt;
  opt.series = series;
  opt.views = 4;
  opt.width = kSmallCaptureWidth;
  opt.height = kSmallCaptureHeight;
  opt.novel_views = 1;
  opt.threads = 2;
  synth::WriteCapture(opt, dir);
  return dir;
}

inline bool HaveXvfb() { return std::system("command -v xvfb-run > /dev/null 2>&1") == 0; }

// `command_line` run under a fresh Xvfb server (640x480x24).
inline CommandResult RunUnderXvfb(const std::string& command_line) {
  return RunCommand("xvfb-run -a -s '-screen 0 640x480x24' " + command_line);
}

// Fixture base: the suite's small capture with `kSeries` series, written once per process.
template <int kSeries>
class SmallCaptureTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(WriteSmallCapture("cli_capture", kSeries));
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string Exe() { return HDRIBR_EXE; }
  static const std::filesystem::path& Dir() { return *dir_; }
  static std::string Ws() { return (*dir_ / "workspace").string(); }

 private:
  static inline std::filesystem::path* dir_ = nullptr;
};

}  // namespace hdribr::test
