// The quality suite's manifest (the repository's own and bad ones), its figures read from eval
// reports, and its table's means and worst captures.
#include "eval/quality_suite.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "test_util.h"

namespace hdribr::eval {
namespace {

namespace fs = std::filesystem;

fs::path Write(const fs::path& dir, const std::string& name, const std::string& text) {
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

TEST(QualitySuite, TheRepositorysManifestHoldsBothSplits) {
  const auto captures =
      ReadSuiteManifest(fs::path(HDRIBR_SOURCE_DIR) / "datasets" / "quality-suite.json");
  int synthetic = 0, synthetic_check = 0, real_check = 0, quick = 0;
  std::set<std::string> scenes;
  for (const SuiteCapture& c : captures) {
    quick += c.quick;
    if (c.synth) {
      ++synthetic;
      synthetic_check += c.split == "check";
      scenes.insert(c.synth->scene + "/" + std::to_string(c.synth->seed));
    } else {
      real_check += c.split == "check";
      EXPECT_TRUE(c.photos.is_relative()) << c.name;
    }
  }
  EXPECT_GE(synthetic, 8);
  EXPECT_GE(2 * synthetic_check, synthetic);  // at least half the synthetic scenes are check
  EXPECT_GE(real_check, 1);
  EXPECT_GE(quick, 2);
  EXPECT_EQ(scenes.size(), size_t(synthetic));  // no scene twice
}

TEST(QualitySuite, BadManifestsNameTheFileAndTheProblem) {
  const fs::path dir = test::TempDir("quality_manifest");
  const std::string head = R"({"format": "hdribr-quality-suite", "version": 1, "captures": [)";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{", "not valid JSON"},
      {head + "]}", "lists no capture"},
      {head + R"({"name": "a", "split": "train", "photos": "x"}]})", "split must be tune"},
      {head + R"({"name": "a/b", "split": "tune", "photos": "x"}]})", "is not [A-Za-z0-9_-]+"},
      {head + R"({"name": "a", "split": "tune"}]})", "exactly one of synth and photos"},
      {head + R"({"name": "a", "split": "tune", "synth": {"scene": "moon"}}]})",
       "unknown scene 'moon'"},
      {head + R"({"name": "a", "split": "tune", "photos": "x"},
                 {"name": "a", "split": "check", "photos": "y"}]})",
       "listed twice"},
      {R"({"format": "hdribr-quality-suite", "version": 2, "captures": []})", "version must be 1"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const fs::path file = Write(dir, "m" + std::to_string(i) + ".json", cases[i].first);
    try {
      ReadSuiteManifest(file);
      ADD_FAILURE() << "accepted: " << cases[i].first;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(cases[i].second), std::string::npos) << e.what();
    }
  }
}

TEST(QualitySuite, FiguresFromEvalReportsAndCalibration) {
  const fs::path dir = test::TempDir("quality_figures");
  Write(dir / "loo", "eval.json", R"({"format": "hdribr-eval", "mean": [
      {"method": "hdribr", "psnr_db": 30.5, "ssim": 0.91, "own_psnr_db": 29.0,
       "own_coverage": 0.97},
      {"method": "nearest_photo", "psnr_db": 29.0, "ssim": 0.90}]})");
  Write(dir / "gt_loo", "eval.json", R"({"format": "hdribr-eval", "mean": [
      {"method": "hdribr", "psnr_db": 31.0, "own_psnr_db": 29.75}]})");
  Write(dir / "gt_novel", "eval.json", R"({"format": "hdribr-eval", "mean": [
      {"method": "hdribr", "psnr_db": 33.0}], "depth": {"accuracy": 0.99}})");
  Write(dir / "gt_novel", "eval_hdr.json", R"({"format": "hdribr-eval-hdr", "methods": [
      {"method": "nearest_photo", "median_abs_log_ratio": 0.2},
      {"method": "hdribr", "median_abs_log_ratio": 0.04, "hdr_psnr_db": 36.0}]})");
  CaptureFigures f;
  ReadLeaveOneOut(dir / "loo", f);
  ReadGtLeaveOneOut(dir / "gt_loo", f);
  ReadGtNovel(dir / "gt_novel", f);
  ReadGtNovel(dir / "absent", f);  // leaves what it has
  EXPECT_TRUE(ParseExposureTruth(
      "exposures vs truth (36 photos, up to one factor): calibrated median 0.70 %, max 6.40 %", f));
  EXPECT_FALSE(ParseExposureTruth("no such line", f));
  EXPECT_DOUBLE_EQ(*f.margin(), 1.5);
  EXPECT_DOUBLE_EQ(*f.gap(), 0.75);
  EXPECT_DOUBLE_EQ(*f.own_coverage, 0.97);
  EXPECT_DOUBLE_EQ(*f.novel_psnr, 33.0);
  EXPECT_DOUBLE_EQ(*f.depth_accuracy, 0.99);
  EXPECT_DOUBLE_EQ(*f.hdr_log_ratio, 0.04);
  EXPECT_DOUBLE_EQ(*f.hdr_mulaw_psnr, 36.0);
  EXPECT_DOUBLE_EQ(*f.exposure_median, 0.007);
  EXPECT_DOUBLE_EQ(*f.exposure_max, 0.064);
  EXPECT_FALSE(f.frame_ms);
  // A JSON round trip keeps every figure.
  const CaptureFigures g = FiguresFromJson(FiguresToJson(f));
  EXPECT_EQ(FiguresToJson(g), FiguresToJson(f));
  // A report that is not an eval report is refused by name.
  Write(dir / "bad", "eval.json", R"({"format": "other"})");
  EXPECT_THROW(ReadLeaveOneOut(dir / "bad", f), InputError);
}

TEST(QualitySuite, TableShowsMeanAndWorstOfEachSplit) {
  CaptureFigures a, b, c;
  a.name = "a";
  a.split = b.split = "tune";
  b.name = "b";
  c.name = "c";
  c.split = "check";
  a.psnr = 30;
  a.nearest_psnr = 28;
  b.psnr = 26;
  b.nearest_psnr = 25.5;
  a.frame_ms = 100;
  b.frame_ms = 300;
  c.psnr = 20;
  const std::string table = FormatSuiteTable({a, b, c});
  // tune: mean margin (2 + 0.5) / 2, worst margin b's, worst frame b's (the slower).
  EXPECT_NE(table.find("+1.25"), std::string::npos) << table;
  EXPECT_NE(table.find("+0.50 b"), std::string::npos) << table;
  EXPECT_NE(table.find("300 b"), std::string::npos) << table;
  EXPECT_NE(table.find("20.00 c"), std::string::npos) << table;
  const std::string md = FormatSuiteMarkdown({a, b, c}, "Measured now");
  EXPECT_EQ(md.rfind("Measured now", 0), 0u);
  EXPECT_NE(md.find("| worst | check |"), std::string::npos) << md;
  EXPECT_NE(md.find("| HDR \\|log\\| |"), std::string::npos) << md;  // escaped in a cell
  const auto j = nlohmann::json::parse(FormatSuiteJson({a, b, c}, "p"));
  EXPECT_EQ(j.at("captures").size(), 3u);
  EXPECT_EQ(j.at("splits").at("tune").at("mean").at("margin dB"), "+1.25");
}

}  // namespace
}  // namespace hdribr::eval
