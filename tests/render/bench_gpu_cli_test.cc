// The standalone GPU benchmarks (hdribr-bench-gpu: `bench depth` and `bench render`, carried to
// GPU machines by .ci/gpu-bench): each runs, its JSON holds every configuration, bad input gets
// one error line, and it needs no shared library beyond those the bundle carries or the GPU
// machine has.
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

std::string BenchGpuExe() { return HDRIBR_BENCH_GPU_EXE; }

TEST(BenchGpuCli, DepthRunsEveryConfiguration) {
  const auto json = test::TempDir("bench_gpu_cli_depth") / "bench.json";
  const auto r = test::RunCommand(BenchGpuExe() +
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
    EXPECT_EQ(res["points_drawn"], 3000);  // --detail 1: every point
    EXPECT_GT(res["wall_ms"].get<double>(), 0.0);
    EXPECT_GT(res["gpu_ms"]["total"].get<double>(), 0.0);
  }
  EXPECT_EQ(seen.size(), 12u);
  EXPECT_EQ(doc["lechelek_over_marroquim"].size(), 4u);  // sizes x rasters
}

TEST(BenchGpuCli, RenderRunsEveryConfiguration) {
  const auto json = test::TempDir("bench_gpu_cli_render") / "bench.json";
  const auto r = test::RunCommand(BenchGpuExe() +
                                  " bench render --sizes 64x48 --photos 3,5 --k-best 0,2"
                                  " --candidates 0,4 --points 3000 --photo-size 64x48 --frames 1"
                                  " --json " +
                                  json.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(json);
  const nlohmann::json doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc["benchmark"], "render");
  EXPECT_FALSE(doc["egl_platform"].get<std::string>().empty());
  ASSERT_EQ(doc["results"].size(), 2u * 2u * 2u);  // photo counts x K x caps
  for (const auto& res : doc["results"]) {
    EXPECT_GT(res["depth_ms"].get<double>(), 0.0);
    EXPECT_GT(res["blend_ms"].get<double>(), 0.0);
    EXPECT_GT(res["fill_ms"].get<double>(), 0.0);         // the fill is on by default
    EXPECT_GT(res["valid_percent"].get<double>(), 50.0);  // the dome fills the view
  }
}

TEST(BenchGpuCli, BadSizeIsOneErrorLineAndNoJson) {
  const auto json = test::TempDir("bench_gpu_cli_bad") / "bench.json";
  const auto r = test::RunCommand(BenchGpuExe() + " bench depth --sizes 64x --points 100 --json " +
                                  json.string());
  EXPECT_EQ(r.exit_code, 64) << r.output;
  EXPECT_NE(r.output.find("error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("64x"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(std::filesystem::exists(json));
}

TEST(BenchGpuCli, DetailOutsideZeroToOneIsOneErrorLine) {
  for (const std::string detail : {"0", "1.5", "-0.25"}) {
    const auto r = test::RunCommand(BenchGpuExe() +
                                    " bench depth --sizes 64x48 --points 100 --detail " + detail);
    EXPECT_EQ(r.exit_code, 64) << r.output;
    EXPECT_NE(r.output.find("error: --detail must be in (0, 1]"), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
}

// .ci/gpu-bench packs the executable with every library ldd resolves for it here, except those
// its `system` pattern leaves to the GPU machine (glibc, the C++ runtime, GL/EGL through
// glvnd). Each library the executable needs must thus be left to the GPU machine or resolve
// here (and so be packed), and so must every library those need in turn.
TEST(BenchGpuCli, BundleHoldsEveryNeededLibrary) {
  std::ifstream script(std::string(HDRIBR_SOURCE_DIR) + "/.ci/gpu-bench");
  ASSERT_TRUE(script) << "no .ci/gpu-bench";
  std::string pattern;
  for (std::string line; std::getline(script, line);) {
    const auto start = line.find("system='");
    if (start != std::string::npos) {
      pattern = line.substr(start + 8, line.rfind('\'') - start - 8);
      break;
    }
  }
  ASSERT_FALSE(pattern.empty()) << "no system='...' pattern in .ci/gpu-bench";
  const std::regex left_to_gpu_machine(pattern, std::regex::extended);  // bash's =~ is ERE

  const auto needed_out = test::RunCommand("objdump -p " + BenchGpuExe());
  ASSERT_EQ(needed_out.exit_code, 0) << needed_out.output;
  const auto ldd_out = test::RunCommand("ldd " + BenchGpuExe());
  ASSERT_EQ(ldd_out.exit_code, 0) << ldd_out.output;
  auto matches = [](const std::string& text, const std::regex& re) {
    std::set<std::string> names;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator();
         ++it) {
      names.insert((*it)[1].str());
    }
    return names;
  };
  const std::set<std::string> needed = matches(needed_out.output, std::regex(R"(NEEDED\s+(\S+))"));
  const std::set<std::string> listed = matches(ldd_out.output, std::regex(R"((\S+) => )"));
  const std::set<std::string> resolved =
      matches(ldd_out.output, std::regex(R"((\S+) => /\S+ \(0x)"));
  EXPECT_TRUE(needed.count("libepoxy.so.0")) << needed_out.output;  // the parsing works
  for (const std::string& lib : needed) {
    EXPECT_TRUE(listed.count(lib) || std::regex_search(lib, left_to_gpu_machine))
        << lib << " is needed but ldd does not list it:\n"
        << ldd_out.output;
  }
  for (const std::string& lib : listed) {
    EXPECT_TRUE(resolved.count(lib) || std::regex_search(lib, left_to_gpu_machine))
        << lib << " is neither packed nor left to the GPU machine:\n"
        << ldd_out.output;
  }
}

}  // namespace
}  // namespace hdribr
