// `hdribr view --soak N` under Xvfb: 10,000 frames alternating a camera orbit step (full
// re-render) and an exposure step (tone map only) in a tiny window; resident memory and the
// number of live GL objects must stay flat after the warm-up. Skips without xvfb-run.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "support/cli_capture.h"

namespace hdribr {
namespace {
using test::Exe;

class ViewerSoakTest : public test::SmallCaptureTest<1> {
 protected:
  void SetUp() override {
    if (!test::HaveXvfb()) GTEST_SKIP() << "xvfb-run is not installed: skipping the soak test";
  }
};

struct SoakLine {
  int frames = 0, warm_up = 0;
  long rss_start_kb = 0, rss_end_kb = 0;
  int gl_start = 0, gl_end = 0;
};

// Parses "soak: frames F (warm-up W), rss_kb start S end E, gl_objects start A end B".
bool ParseSoakLine(const std::string& output, SoakLine& s) {
  const size_t at = output.find("soak: ");
  if (at == std::string::npos) return false;
  return std::sscanf(output.c_str() + at,
                     "soak: frames %d (warm-up %d), rss_kb start %ld end %ld, gl_objects start %d "
                     "end %d",
                     &s.frames, &s.warm_up, &s.rss_start_kb, &s.rss_end_kb, &s.gl_start,
                     &s.gl_end) == 6;
}

TEST_F(ViewerSoakTest, MemoryAndGlObjectsStayFlat) {
  const int frames = 10000;
  const auto r =
      test::RunUnderXvfb(Exe() + " view " + Ws() + " --hdr ldr --width 64 --height 48 --soak " +
                         std::to_string(frames));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  SoakLine s;
  ASSERT_TRUE(ParseSoakLine(r.output, s)) << r.output;
  std::printf("soak: %d frames, RSS %ld -> %ld kB, GL objects %d -> %d\n", s.frames, s.rss_start_kb,
              s.rss_end_kb, s.gl_start, s.gl_end);
  EXPECT_EQ(s.frames, frames);
  EXPECT_GT(s.rss_start_kb, 0);
  EXPECT_LT(s.rss_end_kb - s.rss_start_kb, 8 * 1024);  // kB; allocator noise only
  EXPECT_GT(s.gl_start, 0);
  EXPECT_EQ(s.gl_end, s.gl_start);
}

}  // namespace
}  // namespace hdribr
