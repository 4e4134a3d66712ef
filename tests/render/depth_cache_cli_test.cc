// The depth-map cache end to end: `hdribr render` twice on a fresh workspace reuses the photos'
// depth maps and writes the same bytes; --no-depth-cache and an unwritable cache folder render
// the same too; `hdr` and `eval` use the cache; every rendering subcommand has the flag.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/depth_map_cache.h"
#include "io/exr.h"
#include "support/cli_capture.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;
using test::Exe;

std::string Bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

bool SameFloats(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

size_t CacheFiles(const fs::path& dir) {
  if (!fs::is_directory(dir)) return 0;
  return static_cast<size_t>(std::distance(fs::directory_iterator(dir), {}));
}

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(DepthCacheCliTest, SecondRenderReusesTheDepthMapsAndWritesTheSameBytes) {
  const fs::path ws = test::WriteSmallCapture("", 1) / "workspace";
  const fs::path cache = DepthMapCacheDir(ws);
  const fs::path out = test::TempDir("out");
  const auto render = [&](const std::string& name, const std::string& flags) {
    const auto r = test::RunCommand(Exe() + " render " + ws.string() +
                                    " --camera s0_v01.jpg --exclude s0_v01.jpg " + flags +
                                    " --out " + (out / name).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return r.output;
  };

  std::string log = render("cold.exr", "");
  EXPECT_TRUE(Has(log, "photo depth maps: 4 computed in")) << log;
  EXPECT_TRUE(Has(log, "cached to " + cache.string() + "/")) << log;
  EXPECT_FALSE(Has(log, "from cache")) << log;
  EXPECT_EQ(CacheFiles(cache), 1u);
  log = render("warm.exr", "");
  EXPECT_TRUE(Has(log, "photo depth maps: 4 from cache " + cache.string() + "/")) << log;
  EXPECT_FALSE(Has(log, "computed in")) << log;
  EXPECT_TRUE(SameFloats(ReadExr(out / "warm.exr"), ReadExr(out / "cold.exr")));
  render("cold.png", "--no-depth-cache");
  render("warm.png", "");
  EXPECT_EQ(Bytes(out / "warm.png"), Bytes(out / "cold.png"));

  log = render("none.exr", "--no-depth-cache");
  EXPECT_TRUE(Has(log, "photo depth maps: 4 computed in")) << log;
  EXPECT_TRUE(Has(log, "(no cache)")) << log;
  EXPECT_TRUE(SameFloats(ReadExr(out / "none.exr"), ReadExr(out / "cold.exr")));

  // Another depth mode is another key: computed, cached beside the first.
  log = render("plain.exr", "--depth-mode plain");
  EXPECT_TRUE(Has(log, "cached to")) << log;
  EXPECT_EQ(CacheFiles(cache), 2u);

  // An unwritable cache (a file where its folder should be): a warning, the same picture.
  fs::remove_all(ws / "cache");
  std::ofstream(ws / "cache") << "in the way";
  log = render("blocked.exr", "");
  EXPECT_TRUE(Has(log, "warning photo depth maps: not cached (")) << log;
  EXPECT_TRUE(SameFloats(ReadExr(out / "blocked.exr"), ReadExr(out / "cold.exr")));
  fs::remove(ws / "cache");
}

TEST(DepthCacheCliTest, HdrAndEvalUseTheCache) {
  const fs::path ws = test::WriteSmallCapture("", 2) / "workspace";
  const fs::path out = test::TempDir("out");
  const std::string hdr =
      Exe() + " hdr " + ws.string() + " --no-aligned --out " + (out / "hdr").string();
  auto r = test::RunCommand(hdr);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(Has(r.output, "cached to " + DepthMapCacheDir(ws).string())) << r.output;
  r = test::RunCommand(hdr);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(Has(r.output, "photo depth maps: 8 from cache")) << r.output;
  r = test::RunCommand(Exe() + " eval " + ws.string() +
                       " --leave-one-out --no-baselines --photos s1_v00.jpg");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(Has(r.output, "photo depth maps: 8 from cache")) << r.output;
  r = test::RunCommand(hdr + " --no-depth-cache");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(Has(r.output, "(no cache)")) << r.output;
}

TEST(DepthCacheCliTest, EveryRenderingCommandHasTheFlag) {
  for (const std::string command : {"render", "eval", "view", "hdr"}) {
    const auto r = test::RunCommand(Exe() + " " + command + " --help");
    EXPECT_EQ(r.exit_code, 0) << command << ": " << r.output;
    EXPECT_TRUE(Has(r.output, "--no-depth-cache")) << command << ": " << r.output;
  }
}

}  // namespace
}  // namespace hdribr
