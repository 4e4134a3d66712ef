// The standalone depth benchmark (hdribr-bench-depth, carried to GPU machines by
// .ci/gpu-bench): it runs, its JSON holds every configuration, bad input gets one error line,
// and it needs no shared library beyond those the bundle carries or the GPU machine has.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "test_util.h"

namespace hdribr {
namespace {

std::string Exe() { return HDRIBR_BENCH_DEPTH_EXE; }

TEST(BenchDepthCli, StandaloneRunsEveryConfiguration) {
  const auto json = test::TempDir("bench_depth_cli") / "bench.json";
  const auto r = test::RunCommand(Exe() +
                                  " bench depth --sizes 64x48,40x40 --points 3000 --frames 1"
                                  " --modes plain,marroquim,lechelek --rasters compute,pipeline"
                                  " --json " +
                                  json.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("lechelek/marroquim (compute raster) 64x48 3000 points"),
            std::string::npos)
      << r.output;
  std::ifstream in(json);
  const nlohmann::json doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc["benchmark"], "depth");
  EXPECT_FALSE(doc["renderer"].get<std::string>().empty());
  const std::string platform = doc["egl_platform"].get<std::string>();
  EXPECT_TRUE(platform == "surfaceless" || platform == "device" || platform == "default")
      << platform;
  ASSERT_EQ(doc["results"].size(), 2u * 3u * 2u);  // sizes x modes x rasters
  std::set<std::string> seen;
  for (const auto& res : doc["results"]) {
    seen.insert(res["mode"].get<std::string>() + "/" + res["raster"].get<std::string>() + "/" +
                std::to_string(res["width"].get<int>()));
    EXPECT_EQ(res["points"], 3000);
    EXPECT_GT(res["wall_ms"].get<double>(), 0.0);
    EXPECT_GT(res["gpu_ms"]["total"].get<double>(), 0.0);
  }
  EXPECT_EQ(seen.size(), 12u);
  EXPECT_EQ(doc["lechelek_over_marroquim"].size(), 4u);  // sizes x rasters
}

TEST(BenchDepthCli, BadSizeIsOneErrorLineAndNoJson) {
  const auto json = test::TempDir("bench_depth_cli_bad") / "bench.json";
  const auto r =
      test::RunCommand(Exe() + " bench depth --sizes 64x --points 100 --json " + json.string());
  EXPECT_EQ(r.exit_code, 64) << r.output;
  EXPECT_NE(r.output.find("error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("64x"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(std::filesystem::exists(json));
}

// .ci/gpu-bench carries the executable's libraries except glibc, the C++ runtime and GL/EGL
// (glvnd): a new dependency would make the bundle fail on the GPU machine, so it must be
// deliberate (added here and checked there).
TEST(BenchDepthCli, NeedsOnlyTheBundledLibraries) {
  const auto r = test::RunCommand("objdump -p " + Exe());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::set<std::string> allowed = {"libepoxy.so.0",       "libEGL.so.1", "libglfw.so.3",
                                         "libspdlog.so.1.10",   "libfmt.so.9", "libstdc++.so.6",
                                         "libgcc_s.so.1",       "libm.so.6",   "libc.so.6",
                                         "ld-linux-x86-64.so.2"};
  const std::regex needed(R"(NEEDED\s+(\S+))");
  std::set<std::string> found;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_search(line, m, needed)) found.insert(m[1].str());
  }
  EXPECT_TRUE(found.count("libepoxy.so.0")) << r.output;
  for (const auto& lib : found) EXPECT_TRUE(allowed.count(lib)) << "unexpected NEEDED " << lib;
}

}  // namespace
}  // namespace hdribr
