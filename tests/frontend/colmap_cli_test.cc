#include "frontend/colmap_cli.h"

#include <gtest/gtest.h>

#include <fstream>

#include "test_util.h"

namespace hdribr {
namespace {

TEST(ColmapCli, ParsesBannerWithoutCuda) {
  ColmapCapabilities caps;
  ParseColmapBanner("COLMAP 3.8 (Commit Unknown on Unknown without CUDA)\n\nOptions...", caps);
  EXPECT_EQ(caps.version, "3.8");
  EXPECT_FALSE(caps.has_cuda);
}

TEST(ColmapCli, ParsesBannerWithCuda) {
  ColmapCapabilities caps;
  ParseColmapBanner("COLMAP 4.0.1 (Commit 1a2b3c on 2025-01-01 with CUDA)", caps);
  EXPECT_EQ(caps.version, "4.0.1");
  EXPECT_TRUE(caps.has_cuda);
}

TEST(ColmapCli, PicksTheOptionNamesThisColmapHas) {
  // 3.x names.
  ColmapCapabilities v3;
  ParseColmapOptions(
      "  --database_path arg\n  --SiftExtraction.use_gpu arg (=1)\n"
      "  --SiftExtraction.max_num_features arg (=8192)\n  --ImageReader.single_camera arg (=0)\n",
      v3);
  EXPECT_EQ(v3.Pick({"FeatureExtraction.use_gpu", "SiftExtraction.use_gpu"}),
            "SiftExtraction.use_gpu");
  EXPECT_EQ(v3.Pick({"SiftExtraction.max_num_features", "FeatureExtraction.max_num_features"}),
            "SiftExtraction.max_num_features");
  EXPECT_TRUE(v3.options.count("ImageReader.single_camera"));
  EXPECT_FALSE(v3.options.count("database_path"));  // plain options are not Section.name
  // 4.x names.
  ColmapCapabilities v4;
  ParseColmapOptions(
      "  --FeatureExtraction.use_gpu arg (=1)\n  --FeatureExtraction.num_threads arg (=-1)\n"
      "  --SiftExtraction.max_num_features arg (=8192)\n",
      v4);
  EXPECT_EQ(v4.Pick({"SiftExtraction.use_gpu", "FeatureExtraction.use_gpu"}),
            "FeatureExtraction.use_gpu");
  EXPECT_EQ(v4.Pick({"SiftExtraction.num_threads", "FeatureExtraction.num_threads"}),
            "FeatureExtraction.num_threads");
  EXPECT_EQ(v4.Pick({"Nope.option"}), "");
}

TEST(ColmapCli, ParsesProgressLines) {
  auto p = ParseColmapProgressLine("Processed file [12/23]", 23);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->done, 12);
  EXPECT_EQ(p->total, 23);
  p = ParseColmapProgressLine("Matching block [2/3, 1/3]", 30);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->done, 4);
  EXPECT_EQ(p->total, 9);
  p = ParseColmapProgressLine("Registering image #7 (5)", 48);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->done, 5);
  EXPECT_EQ(p->total, 48);
  EXPECT_FALSE(ParseColmapProgressLine("Elapsed time: 0.5 [minutes]", 10));
}

TEST(ColmapCli, FindsExecutablesInPath) {
  EXPECT_TRUE(FindExecutable("sh"));
  EXPECT_FALSE(FindExecutable("no_such_program_hdribr_test"));
}

TEST(ColmapCli, RunLoggedCapturesOutputAndStatus) {
  const auto dir = test::TempDir("runlogged");
  const auto log = dir / "log.txt";
  std::vector<std::string> lines;
  const int rc = RunLogged("/bin/sh", {"-c", "echo one; echo two 1>&2; exit 3"}, log,
                           [&](const std::string& l) { lines.push_back(l); });
  EXPECT_EQ(rc, 3);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "one");
  EXPECT_EQ(lines[1], "two");
  EXPECT_NE(LastLines(log, 1).find("two"), std::string::npos);
  EXPECT_EQ(RunLogged(dir / "missing_exe", {}, log, {}), 127);
}

}  // namespace
}  // namespace hdribr
