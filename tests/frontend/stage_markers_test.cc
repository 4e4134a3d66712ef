#include "frontend/stage_markers.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace hdribr {
namespace {

// The names of a settings text, in order.
std::vector<std::string> Names(const std::string& settings) {
  std::vector<std::string> names;
  std::istringstream in(settings);
  for (std::string line; std::getline(in, line);) names.push_back(line.substr(0, line.find('=')));
  return names;
}

std::string Settings(const ReconstructOptions& options, const std::string& stage,
                     const std::string& dense_mode = "cpu") {
  const std::vector<InputPhoto> photos = {{"a.jpg", {}, 0, 0}, {"b.jpg", {}, 0, 0}};
  return StageSettings({options, photos, "exhaustive", dense_mode}, stage);
}

// The markers of existing workspaces hold these names in this order: a renamed or reordered
// setting would redo their stages.
TEST(StageMarkers, NameEverySettingInTheirRecordedOrder) {
  const ReconstructOptions o;
  EXPECT_EQ(Names(Settings(o, "features")),
            (std::vector<std::string>{"photos", "camera-model", "max-features", "sift-size"}));
  EXPECT_EQ(Names(Settings(o, "matching")), (std::vector<std::string>{"matching", "vocab-tree"}));
  EXPECT_EQ(Names(Settings(o, "undistortion")), std::vector<std::string>{"image-size"});
  EXPECT_EQ(Settings(o, "mapping"), "");
  EXPECT_EQ(Settings(o, "series"), "");
  const std::vector<std::string> common = {
      "dense",           "outlier-neighbors", "outlier-stddev",
      "cleanup-version", "normal-neighbors",  "radius-neighbors"};
  EXPECT_EQ(Names(Settings(o, "dense", "none")), common);
  EXPECT_EQ(Names(Settings(o, "dense", "colmap")), common);
  std::vector<std::string> ours = common;
  for (const char* n : {"dense-version", "dense-size", "dense-neighbors", "fusion-consistency",
                        "fusion-min-consistent", "fusion-single-ncc", "fusion-max-normal-error"}) {
    ours.push_back(n);
  }
  std::vector<std::string> sweep = ours;
  for (const char* n : {"dense-depths", "sweep-window-radius", "sweep-min-ncc"}) sweep.push_back(n);
  EXPECT_EQ(Names(Settings(o, "dense", "sweep")), sweep);
  std::vector<std::string> patch_match = ours;
  for (const char* n :
       {"window-radius", "window-step", "sigma-color", "dense-levels", "coarse-iterations",
        "dense-iterations", "dense-geom-iterations", "geom-weight", "geom-max-error", "best-views",
        "dense-min-ncc", "min-texture", "seed-radius", "coarse-fill"}) {
    patch_match.push_back(n);
  }
  EXPECT_EQ(Names(Settings(o, "dense", "cpu")), patch_match);
}

TEST(StageMarkers, RecordTheValuesThatRun) {
  ReconstructOptions o;
  o.camera_model = "PINHOLE";
  o.max_features = 1234;
  o.vocab_tree = "/trees/tree.bin";
  o.dense_options.max_size = 0;
  o.attribute_options.outlier_stddev = 2.5;
  const std::string features = Settings(o, "features");
  EXPECT_NE(features.find("camera-model=PINHOLE\n"), std::string::npos) << features;
  EXPECT_NE(features.find("max-features=1234\n"), std::string::npos) << features;
  EXPECT_EQ(features.rfind("photos=2 (", 0), 0u) << features;
  EXPECT_EQ(Settings(o, "matching"), "matching=exhaustive\nvocab-tree=/trees/tree.bin\n");
  const std::string dense = Settings(o, "dense", "sweep");
  EXPECT_EQ(dense.rfind("dense=sweep\n", 0), 0u) << dense;
  EXPECT_NE(dense.find("outlier-stddev=2.5\n"), std::string::npos) << dense;
  EXPECT_NE(dense.find("dense-size=auto\n"), std::string::npos) << dense;
  o.dense_options.max_size = 640;
  EXPECT_NE(Settings(o, "dense", "sweep").find("dense-size=640\n"), std::string::npos);
}

TEST(StageMarkers, ChangeWithTheOptionsOfTheirStageOnly) {
  const ReconstructOptions before;
  ReconstructOptions after = before;
  after.dense_options.patch_match.window_radius =
      before.dense_options.patch_match.window_radius + 1;
  for (const char* stage : {"features", "matching", "mapping", "undistortion", "series"}) {
    EXPECT_EQ(Settings(before, stage), Settings(after, stage)) << stage;
  }
  EXPECT_EQ(Settings(before, "dense", "sweep"), Settings(after, "dense", "sweep"));
  const std::string a = Settings(before, "dense"), b = Settings(after, "dense");
  ASSERT_NE(a, b);
  const int r = before.dense_options.patch_match.window_radius;
  EXPECT_EQ(ChangedSettings(a, b),
            "window-radius " + std::to_string(r) + " -> " + std::to_string(r + 1));
  // A different photo set redoes the features.
  const std::vector<InputPhoto> one = {{"a.jpg", {}, 0, 0}};
  const std::vector<InputPhoto> renamed = {{"c.jpg", {}, 0, 0}};
  EXPECT_NE(StageSettings({before, one, "exhaustive", "cpu"}, "features"),
            StageSettings({before, renamed, "exhaustive", "cpu"}, "features"));
}

TEST(StageMarkers, ListChangedAddedAndRemovedSettings) {
  EXPECT_EQ(ChangedSettings("a=1\nb=2\n", "a=1\nb=2\n"), "");
  EXPECT_EQ(ChangedSettings("a=1\nb=2\n", "a=1\nb=3\nc=4\n"), "b 2 -> 3, c (none) -> 4");
  EXPECT_EQ(ChangedSettings("dense=cpu\nx=1\n", "dense=sweep\n"),
            "dense cpu -> sweep, x 1 -> (none)");
}

TEST(StageMarkers, SkipAStageWhenTheMarkerRecordsTheSameSettingsOrNone) {
  EXPECT_TRUE(MarkerCurrent("a=1\n", "a=1\n"));
  EXPECT_TRUE(MarkerCurrent("", "a=1\n"));  // a workspace from before the settings
  EXPECT_FALSE(MarkerCurrent("a=1\n", "a=2\n"));
  EXPECT_FALSE(MarkerCurrent("a=1\n", ""));
}

}  // namespace
}  // namespace hdribr
