// Small synthetic captures for the tests' shared fixtures and private captures.
// Header-only: the including test links hdribr_synth.
#pragma once

#include <cstdint>
#include <filesystem>

#include "synth/capture.h"

namespace hdribr::test {

// The size of a test capture: series x views photos of width x height, novel views, and the
// seed of the scene's random layout and noise.
struct TestCaptureSize {
  int series = 1;
  int views = 4;
  int width = 128;
  int height = 96;
  int novel = 1;
  std::uint64_t seed = synth::CaptureOptions().seed;
};

// The capture options of the default scene of that size (2 threads: the bytes do not depend on
// the thread count).
inline synth::CaptureOptions TestCaptureOptions(const TestCaptureSize& size) {
  synth::CaptureOptions opt;
  opt.series = size.series;
  opt.views = size.views;
  opt.width = size.width;
  opt.height = size.height;
  opt.novel_views = size.novel;
  opt.seed = size.seed;
  opt.threads = 2;
  return opt;
}

// Writes a capture of the default scene of that size into `dir`.
inline void WriteTestCapture(const std::filesystem::path& dir, const TestCaptureSize& size) {
  synth::WriteCapture(TestCaptureOptions(size), dir);
}

}  // namespace hdribr::test
