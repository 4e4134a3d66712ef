// Shared set-up of the CLI integration tests (render, view, hdr CLI tests): small synthetic
// captures (one per CTest run, shared by the tests that only read it), the hdribr executable,
// and xvfb-run for the viewer.
// Header-only: the including test links hdribr_synth and defines HDRIBR_EXE (hdribr_test).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "support/exe.h"
#include "support/test_capture.h"
#include "test_util.h"

namespace hdribr::test {

// Size of the photos of WriteSmallCapture.
inline constexpr int kSmallCaptureWidth = 128;
inline constexpr int kSmallCaptureHeight = 96;

// A 128x96 capture of `series` exposure series x 4 views and one novel view, into `dir`.
inline void WriteSmallCaptureTo(const std::filesystem::path& dir, int series) {
  WriteTestCapture(dir, {series, 4, kSmallCaptureWidth, kSmallCaptureHeight, 1});
}

// ... in a fresh TempDir(tag), for a test that writes into it; returns its folder (the
// workspace is <folder>/workspace).
inline std::filesystem::path WriteSmallCapture(const std::string& tag, int series) {
  const std::filesystem::path dir = TempDir(tag) / "capture";
  WriteSmallCaptureTo(dir, series);
  return dir;
}

// The same capture shared, read-only, by the tests of every process: the shared fixture
// SmallCapture<series> (test_util.h), whose setup test, in one test executable (hdribr_fixture
// in its CMakeLists.txt), is TEST(Fixture, SmallCapture<series>) calling
// RemakeSmallCaptureFixture(<series>). The capture is <fixture folder>/capture.
inline std::string SmallCaptureFixture(int series) {
  return "SmallCapture" + std::to_string(series);
}
inline FixtureMaker SmallCaptureMaker(int series) {
  return
      [series](const std::filesystem::path& dir) { WriteSmallCaptureTo(dir / "capture", series); };
}
inline void RemakeSmallCaptureFixture(int series) {
  RemakeSharedFixture(SmallCaptureFixture(series), SmallCaptureMaker(series));
}
inline std::filesystem::path SharedSmallCapture(int series) {
  return SharedFixture(SmallCaptureFixture(series), SmallCaptureMaker(series)) / "capture";
}

inline bool HaveXvfb() { return std::system("command -v xvfb-run > /dev/null 2>&1") == 0; }

// `command_line` run under a fresh Xvfb server (640x480x24).
inline CommandResult RunUnderXvfb(const std::string& command_line) {
  return RunCommand("xvfb-run -a -s '-screen 0 640x480x24' " + command_line);
}

// Fixture base: the suite's small capture with `kSeries` series, read-only, shared by the
// tests of every process (SharedSmallCapture): the executables of the suites deriving from it
// require the CTest fixture SmallCapture<kSeries>.
template <int kSeries>
class SmallCaptureTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dir_ = new std::filesystem::path(SharedSmallCapture(kSeries)); }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static const std::filesystem::path& Dir() { return *dir_; }
  static std::string Ws() { return (*dir_ / "workspace").string(); }

 private:
  static inline std::filesystem::path* dir_ = nullptr;
};

}  // namespace hdribr::test
