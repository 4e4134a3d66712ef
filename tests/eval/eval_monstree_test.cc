// `hdribr eval` end to end on monstree: the workspace of the shared fixture MonstreeWorkspace
// (tests/monstree_workspace.h), reconstructed once per CTest run by its setup test in
// reconstruct_monstree_test (tests/frontend/CMakeLists.txt).
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "io/atomic_file.h"
#include "io/colmap_model.h"
#include "monstree_workspace.h"
#include "test_util.h"

namespace hdribr {
namespace {

namespace fs = std::filesystem;

// Mean scores by method from eval.json.
std::map<std::string, nlohmann::json> Means(const fs::path& json_path) {
  const nlohmann::json j = nlohmann::json::parse(ReadFileToString(json_path));
  std::map<std::string, nlohmann::json> out;
  for (const auto& m : j.at("mean")) out[m.at("method")] = m;
  return out;
}

// monstree after `hdribr reconstruct`, leave-one-out over every photo at reduced size: with its
// several exposures, each photo is rendered in radiance from all the others and re-exposed at
// its own calibrated exposure (LDR-OE).
TEST(EvalCli, MonstreeEveryPhotoReExposed) {
  HDRIBR_REQUIRE_DATASET(monstree, "monstree");
  const fs::path ws = test::MonstreeWorkspace(monstree);
  const fs::path out = test::TempDir("eval_monstree");
  const auto r = test::RunCommand(std::string(HDRIBR_EXE) + " -q eval " + ws.string() +
                                  " --leave-one-out --series all --size-scale 0.5 --out " +
                                  out.string() + " 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::cout << r.output << "\n";
  const nlohmann::json j = nlohmann::json::parse(ReadFileToString(out / "eval.json"));
  const ColmapModel model = ReadColmapModel(ws / "sparse");
  EXPECT_EQ(j.at("views").size(), model.images.size());  // no photo skipped
  auto mean = Means(out / "eval.json");
  std::cout << "monstree LDR-OE: hdribr " << mean["hdribr"]["psnr_db"] << " dB SSIM "
            << mean["hdribr"]["ssim"] << ", nearest " << mean["nearest_photo"]["psnr_db"]
            << " dB SSIM " << mean["nearest_photo"]["ssim"] << "\n";
  EXPECT_GT(mean["hdribr"]["psnr_db"].get<double>(), 15.0);
  EXPECT_GT(mean["hdribr"]["ssim"].get<double>(), mean["nearest_photo"]["ssim"].get<double>());
  EXPECT_GT(mean["hdribr"]["own_coverage"].get<double>(), 0.9);
}

}  // namespace
}  // namespace hdribr
