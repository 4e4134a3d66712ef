// The stage runner of `Reconstruct` with a stub `colmap` (a shell script that records its calls
// and writes what the next stage reads): which stages run, which resume from their markers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <string>
#include <vector>

#include "frontend/reconstruct.h"
#include "io/atomic_file.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;

// The stub: answers `-h` with a banner and one option; records every other call (its command)
// in calls.txt beside it; the mapper copies model/ into <output>/0, the undistorter into
// <output>/sparse.
constexpr const char* kStub = R"sh(#!/bin/sh
here=$(dirname "$0")
if [ "$2" = "-h" ]; then
  echo "COLMAP 3.8 (Commit stub on stub without CUDA)"
  echo "  --ImageReader.camera_model arg (=SIMPLE_RADIAL)"
  exit 0
fi
echo "$1" >> "$here/calls.txt"
out=""
prev=""
for a in "$@"; do
  [ "$prev" = "--output_path" ] && out="$a"
  prev="$a"
done
case "$1" in
  mapper) mkdir -p "$out/0" && cp "$here/model/"* "$out/0/" ;;
  image_undistorter) mkdir -p "$out/sparse" "$out/images" && cp "$here/model/"* "$out/sparse/" ;;
esac
exit 0
)sh";

class StageRunner : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::TempDir("stage_runner");
    fs::create_directories(dir_ / "photos");
    for (const char* name : {"a.jpg", "b.jpg"}) {
      cv::imwrite((dir_ / "photos" / name).string(), cv::Mat(48, 64, CV_8UC3, cv::Scalar(90)));
    }
    // Two registered photos and 200 points on a plane in front of them.
    fs::create_directories(dir_ / "stub/model");
    WriteFileAtomic(dir_ / "stub/model/cameras.txt", "1 PINHOLE 64 48 50 50 32 24\n");
    WriteFileAtomic(dir_ / "stub/model/images.txt",
                    "1 1 0 0 0 0 0 0 1 a.jpg\n\n2 1 0 0 0 -0.5 0 0 1 b.jpg\n\n");
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1, 1);
    std::string points;
    for (int i = 1; i <= 200; ++i) {
      points += std::to_string(i) + " " + std::to_string(u(rng)) + " " + std::to_string(u(rng)) +
                " 4 128 128 128 0.5\n";
    }
    WriteFileAtomic(dir_ / "stub/model/points3D.txt", points);
    WriteFileAtomic(dir_ / "stub/colmap", kStub);
    fs::permissions(dir_ / "stub/colmap", fs::perms::owner_all);
    options_.photos = dir_ / "photos";
    options_.workspace = dir_ / "workspace";
    options_.colmap = (dir_ / "stub/colmap").string();
    options_.dense = "none";
    options_.threads = 1;
  }

  // The colmap commands the last calls ran, and clears the record.
  std::vector<std::string> Calls() {
    std::vector<std::string> calls;
    std::ifstream in(dir_ / "stub/calls.txt");
    for (std::string line; std::getline(in, line);) calls.push_back(line);
    fs::remove(dir_ / "stub/calls.txt");
    return calls;
  }
  // The stages that ran in the last report.
  static std::vector<std::string> Ran(const ReconstructReport& report) {
    std::vector<std::string> ran;
    for (const StageTime& t : report.times) {
      if (t.stage.find('.') == std::string::npos) ran.push_back(t.stage);
    }
    return ran;
  }

  fs::path dir_;
  ReconstructOptions options_;
};

const std::vector<std::string> kColmapCalls = {"feature_extractor", "exhaustive_matcher", "mapper",
                                               "image_undistorter"};

TEST_F(StageRunner, RunsEveryStageThenResumesFromTheMarkers) {
  const ReconstructReport first = Reconstruct(options_);
  EXPECT_EQ(Ran(first), ReconstructStages());
  EXPECT_EQ(Calls(), kColmapCalls);
  EXPECT_EQ(first.num_registered, 2);
  EXPECT_GT(first.num_points, 100u);
  for (const std::string& stage : ReconstructStages()) {
    EXPECT_TRUE(fs::exists(options_.workspace / "logs" / (stage + ".done"))) << stage;
  }
  EXPECT_NE(ReadFileToString(options_.workspace / "logs/dense.done").find("dense=none\n"),
            std::string::npos);

  const ReconstructReport again = Reconstruct(options_);
  EXPECT_TRUE(Ran(again).empty());
  EXPECT_TRUE(Calls().empty());
  EXPECT_EQ(again.num_registered, 2);
  EXPECT_EQ(again.num_points, first.num_points);

  options_.force = true;
  EXPECT_EQ(Ran(Reconstruct(options_)), ReconstructStages());
  EXPECT_EQ(Calls(), kColmapCalls);
}

TEST_F(StageRunner, RedoesAChangedStageAndTheOnesAfterIt) {
  Reconstruct(options_);
  Calls();
  // A dense-stage setting: the dense stage alone, no colmap call.
  options_.attribute_options.outlier_stddev = 3.0;
  EXPECT_EQ(Ran(Reconstruct(options_)), std::vector<std::string>{"dense"});
  EXPECT_TRUE(Calls().empty());
  // An undistortion setting: it and the stages after it.
  options_.undistort_max_size = 32;
  EXPECT_EQ(Ran(Reconstruct(options_)),
            (std::vector<std::string>{"undistortion", "series", "dense"}));
  EXPECT_EQ(Calls(), std::vector<std::string>{"image_undistorter"});
  // A features setting: everything.
  options_.max_features = 100;
  EXPECT_EQ(Ran(Reconstruct(options_)), ReconstructStages());
  EXPECT_EQ(Calls(), kColmapCalls);
}

TEST_F(StageRunner, AnEmptyMarkerCountsAsDoneAndAMissingOneRedoesFromThere) {
  Reconstruct(options_);
  Calls();
  // Markers of an older workspace record no settings.
  WriteFileAtomic(options_.workspace / "logs/features.done", "");
  EXPECT_TRUE(Ran(Reconstruct(options_)).empty());
  fs::remove(options_.workspace / "logs/mapping.done");
  EXPECT_EQ(Ran(Reconstruct(options_)),
            (std::vector<std::string>{"mapping", "undistortion", "series", "dense"}));
  EXPECT_EQ(Calls(), (std::vector<std::string>{"mapper", "image_undistorter"}));
}

}  // namespace
}  // namespace hdribr
