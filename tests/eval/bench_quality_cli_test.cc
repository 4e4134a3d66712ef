// `hdribr bench quality` end to end on a one-capture manifest (its GT-geometry screen, which
// needs no reconstruction): the table and JSON, resuming from what a run left, and the errors
// that stop it before any work.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "support/exe.h"
#include "test_util.h"

namespace hdribr {
namespace {
using test::Exe;

namespace fs = std::filesystem;

fs::path WriteManifest(const fs::path& dir) {
  const fs::path manifest = dir / "suite.json";
  std::ofstream(manifest) << R"({"format": "hdribr-quality-suite", "version": 1, "captures": [
    {"name": "tiny", "split": "check", "quick": true,
     "synth": {"scene": "arches", "size": "120x90", "series": 2, "views": 5, "novel_views": 2},
     "eval": ["--series", "1"]},
    {"name": "absent", "split": "tune", "photos": "no-such-dataset/images"}]})";
  return manifest;
}

TEST(BenchQualityCli, GtScreenResumesAndReports) {
  const fs::path dir = test::TempDir("bench_quality");
  const fs::path manifest = WriteManifest(dir);
  const std::string cmd = Exe() + " bench quality --manifest " + manifest.string() + " --dir " +
                          (dir / "work").string() + " --gt-only --json " +
                          (dir / "q.json").string();
  auto r = test::RunCommand(cmd);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("tiny: synth"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\nworst "), std::string::npos) << r.output;  // the split's rows
  const auto j = nlohmann::json::parse(std::ifstream(dir / "q.json"));
  ASSERT_EQ(j.at("captures").size(), 1u);  // the real capture is not part of the GT screen
  const auto& f = j.at("captures")[0];
  EXPECT_EQ(f.at("name"), "tiny");
  // Figures on the GT geometry, in their units: dB, a share, a median |ln ratio|.
  EXPECT_GT(f.at("gt_own_psnr_db").get<double>(), 20.0);
  EXPECT_GT(f.at("novel_psnr_db").get<double>(), 15.0);
  EXPECT_GT(f.at("depth_accuracy").get<double>(), 0.8);
  EXPECT_LE(f.at("depth_accuracy").get<double>(), 1.0);
  EXPECT_GT(f.at("hdr_median_abs_log_ratio").get<double>(), 0.0);
  EXPECT_LT(f.at("hdr_median_abs_log_ratio").get<double>(), 0.3);
  EXPECT_FALSE(f.contains("psnr_db"));  // no reconstruction, no leave-one-out on it
  // A second run reuses the capture and the evaluations: no stage runs again.
  r = test::RunCommand(cmd);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("tiny: synth"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("GT novel views"), std::string::npos) << r.output;
  EXPECT_EQ(nlohmann::json::parse(std::ifstream(dir / "q.json")).at("captures")[0], f);
}

TEST(BenchQualityCli, BadSelectionsAreOneLineBeforeAnyWork) {
  const fs::path dir = test::TempDir("bench_quality_errors");
  const fs::path manifest = WriteManifest(dir);
  const std::string base = Exe() + " bench quality --manifest " + manifest.string() + " --dir " +
                           (dir / "work").string();
  for (const std::string& args :
       {std::string(" --split train"), std::string(" --only nope"), std::string(" --tag a/b"),
        std::string(" --render-args '--k-best x'")}) {
    const auto r = test::RunCommand(base + args);
    EXPECT_EQ(r.exit_code, 64) << args << ": " << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << r.output;
  }
  // The real capture whose photos are absent is skipped with a warning; alone, it is an error.
  const auto r = test::RunCommand(base + " --only absent --datasets " + dir.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("absent"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "work" / "tiny"));
  const auto bad =
      test::RunCommand(Exe() + " bench quality --manifest " + (dir / "none.json").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("none.json"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace hdribr
