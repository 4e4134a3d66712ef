// Small synthetic captures for the tests' shared fixtures and private captures.
// Header-only: the including test links hdribr_synth.
#pragma once

#include <filesystem>

#include "synth/capture.h"

namespace hdribr::test {

// The size of a test capture: series x views photos of width x height, and novel views.
struct TestCaptureSize {
  int series = 1;
  int views = 4;
  int width = 128;
  int height = 96;
  int novel = 1;
};

// Writes a capture of the default scene of that size into `dir` (2 threads).
inline void WriteTestCapture(const std::filesystem::path& dir, const TestCaptureSize& size) {
  synth::CaptureOptions opt;
  opt.series = size.series;
  opt.views = size.views;
  opt.width = size.width;
  opt.height = size.height;
  opt.novel_views = size.novel;
  opt.threads = 2;
  synth::WriteCapture(opt, dir);
}

}  // namespace hdribr::test
