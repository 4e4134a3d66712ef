// `hdribr reconstruct` end to end with the real colmap: bad input, and a synthetic capture
// against its ground truth (the monstree photos: reconstruct_monstree_test.cc).
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "eval/camera_accuracy.h"
#include "eval/cloud_accuracy.h"
#include "frontend/dense_mvs.h"
#include "io/atomic_file.h"
#include "io/colmap_model.h"
#include "io/ply.h"
#include "support/exe.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;
using test::Exe;

int CountLines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST(ReconstructCli, MissingPhotoFolderIsOneClearError) {
  const fs::path dir = test::TempDir("rec_missing");
  const auto r = test::RunCommand(Exe() + " -q reconstruct " + (dir / "nope").string() + " " +
                                  (dir / "ws").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("photo folder does not exist"), std::string::npos) << r.output;
  EXPECT_EQ(CountLines(r.output), 1) << r.output;
  EXPECT_FALSE(fs::exists(dir / "ws"));
}

TEST(ReconstructCli, EmptyPhotoFolderIsOneClearError) {
  const fs::path dir = test::TempDir("rec_empty");
  fs::create_directories(dir / "photos");
  const auto r = test::RunCommand(Exe() + " -q reconstruct " + (dir / "photos").string() + " " +
                                  (dir / "ws").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no photos found"), std::string::npos) << r.output;
  EXPECT_EQ(CountLines(r.output), 1) << r.output;
}

TEST(ReconstructCli, MissingColmapIsOneClearError) {
  HDRIBR_REQUIRE_DATASET(monstree, "monstree");
  const fs::path dir = test::TempDir("rec_nocolmap");
  const auto r = test::RunCommand("PATH=/nonexistent " + Exe() + " -q reconstruct " +
                                  (monstree / "images").string() + " " + (dir / "ws").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("COLMAP executable not found"), std::string::npos) << r.output;
  EXPECT_EQ(CountLines(r.output), 1) << r.output;
}

TEST(ReconstructCli, BadOptionsAreRefusedBeforeAnyWork) {
  // Refused up front, before COLMAP runs or a workspace is made.
  const fs::path dir = test::TempDir("rec_badopt");
  fs::create_directories(dir / "photos");
  for (const std::string bad :
       {"--max-features 0", "--dense-size -1", "--image-size 0", "--threads -1", "--dense-depths 1",
        "--dense foo", "--matching foo", "--dense-levels 0"}) {
    const auto r = test::RunCommand(Exe() + " -q reconstruct " + (dir / "photos").string() + " " +
                                    (dir / "ws").string() + " " + bad);
    EXPECT_EQ(r.exit_code, 64) << bad << ": " << r.output;
    EXPECT_NE(r.output.find(bad.substr(0, bad.find(' '))), std::string::npos) << r.output;
    EXPECT_EQ(CountLines(r.output), 1) << r.output;
    EXPECT_FALSE(fs::exists(dir / "ws")) << bad;
  }
  const auto r = test::RunCommand(Exe() + " -q reconstruct " + (dir / "photos").string() + " " +
                                  (dir / "ws").string() + " --matching vocab_tree");
  EXPECT_EQ(r.exit_code, 64) << r.output;
  EXPECT_NE(r.output.find("--vocab-tree is needed"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "ws"));
}

TEST(ReconstructCli, SyntheticCaptureMatchesGroundTruth) {
  const fs::path dir = test::TempDir("rec_synth");
  const auto s = test::RunCommand(Exe() + " -q synth " + (dir / "cap").string() +
                                  " --series 3 --views 8 --size 400x300 --novel 0");
  ASSERT_EQ(s.exit_code, 0) << s.output;
  const fs::path ws = dir / "ws";
  const auto r = test::RunCommand(Exe() + " reconstruct " + (dir / "cap/photos").string() + " " +
                                  ws.string() + " --dense-size 300 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::cout << r.output.substr(r.output.size() > 3000 ? r.output.size() - 3000 : 0) << "\n";

  // All photos registered; centres within 1% of the scene size after similarity alignment.
  const ColmapModel gt = ReadColmapModel(dir / "cap/gt");
  const ColmapModel rec = ReadColmapModel(ws / "sparse");
  EXPECT_EQ(rec.images.size(), gt.images.size());
  const eval::CameraAccuracy cameras = eval::CompareCameras(rec, gt);
  const SimilarityAlignment& align = cameras.alignment;
  const PointCloud gt_points = ReadPly(dir / "cap/gt/points.ply");
  Bounds b;
  for (const auto& p : gt_points.positions) b.Extend(p.cast<double>());
  const double scene = b.Diagonal();
  std::cout << eval::FormatCameraAccuracy(cameras) << "camera centre error: max "
            << align.max / scene * 100 << "% of the scene size " << scene << "\n";
  EXPECT_LT(align.max, 0.01 * scene);

  // Dense cloud: accuracy and completeness at 1% of the scene size, asserted a little under
  // the figures measured (docs/decisions/0026). They are asserted after the ICP refinement of
  // the cameras' alignment: the centres of an arc of views leave a rotation about its chord,
  // different in every COLMAP run, that moves the unrefined figures whatever the dense stage
  // does.
  const PointCloud dense = ReadPly(ws / "points.ply");
  ASSERT_TRUE(dense.HasNormals() && dense.HasRadii());
  const eval::CloudAccuracy cloud =
      eval::CompareClouds(dense, align.dst_from_src, gt_points, 0.01 * scene);
  std::cout << dense.size() << " points, " << eval::FormatCloudAccuracy(cloud);
  EXPECT_GE(cloud.refined.accuracy, 0.98);
  EXPECT_GE(cloud.refined.completeness, 0.955);
  EXPECT_LT(cloud.refinement_deg, 3.0);

  // The workspace loads, and a second run skips every finished stage.
  const auto inspect = test::RunCommand(Exe() + " -q inspect " + ws.string());
  EXPECT_EQ(inspect.exit_code, 0) << inspect.output;
  const auto again = test::RunCommand(Exe() + " reconstruct " + (dir / "cap/photos").string() +
                                      " " + ws.string() + " --dense-size 300 2>&1");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("dense: done before, skipped"), std::string::npos) << again.output;

  // Multi-view stereo that keeps nothing (no depth reaches an NCC of 1; at a third of the
  // size, a ninth of the pixels to match, since it keeps nothing at any size): the workspace
  // keeps the sparse points, says so, and renders them with the background. The changed options
  // redo the dense stage alone, as does a marker written before the densifier's version was
  // recorded (its line removed here).
  const fs::path bare = dir / "ws_bare";
  fs::copy(ws, bare, fs::copy_options::recursive);
  const fs::path marker = bare / "logs/dense.done";
  const std::string version_line = "dense-version=" + std::to_string(kDenseVersion) + "\n";
  std::string settings = ReadFileToString(marker);
  const size_t at = settings.find(version_line);
  ASSERT_NE(at, std::string::npos) << settings;
  WriteFileAtomic(marker, settings.erase(at, version_line.size()));
  const auto none = test::RunCommand(Exe() + " reconstruct " + (dir / "cap/photos").string() + " " +
                                     bare.string() + " --dense-size 100 --dense-min-ncc 1 2>&1");
  ASSERT_EQ(none.exit_code, 0) << none.output;
  EXPECT_NE(none.output.find("undistortion: done before, skipped"), std::string::npos)
      << none.output;
  EXPECT_NE(none.output.find("dense: redone, its options changed: dense-min-ncc 0.3 -> 1, "
                             "dense-size 300 -> 100, dense-version (none) -> " +
                             std::to_string(kDenseVersion) + "\n"),
            std::string::npos)
      << none.output;
  EXPECT_NE(none.output.find("the workspace keeps the sparse points"), std::string::npos)
      << none.output;
  const size_t sparse_points = rec.points3d.size();
  const PointCloud kept = ReadPly(bare / "points.ply");
  std::cout << "no dense points: " << kept.size() << " of " << sparse_points
            << " sparse points kept\n";
  EXPECT_GT(kept.size(), sparse_points / 2);
  EXPECT_LE(kept.size(), sparse_points);
  const fs::path png = dir / "bare.png";
  const auto render = test::RunCommand(Exe() + " render " + bare.string() + " --camera " +
                                       rec.images.begin()->second.name + " --no-fill --out " +
                                       png.string() + " 2>&1");
  ASSERT_EQ(render.exit_code, 0) << render.output;
  const cv::Mat rgba = cv::imread(png.string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(rgba.channels(), 4);
  std::vector<cv::Mat> ch;
  cv::split(rgba, ch);
  const double valid = cv::countNonZero(ch[3]) / static_cast<double>(rgba.total());
  std::cout << "render of the sparse workspace: " << valid * 100 << "% of the frame\n";
  EXPECT_GT(valid, 0.9);  // the sparse points' splats and the background sphere

  // Fewer photos in the folder (one exposure series of the three, so that COLMAP's second run
  // matches 8 photos, not 23): the photo set changed, so every stage is redone, on the new set.
  const fs::path fewer = dir / "fewer";
  fs::create_directories(fewer);
  for (const auto& e : fs::directory_iterator(dir / "cap/photos")) {
    if (e.path().filename().string().rfind("s1_", 0) == 0) fs::copy(e.path(), fewer);
  }
  const auto redo = test::RunCommand(Exe() + " reconstruct " + fewer.string() + " " +
                                     bare.string() + " --dense none 2>&1");
  ASSERT_EQ(redo.exit_code, 0) << redo.output;
  EXPECT_NE(redo.output.find("features: redone, its options changed: photos 24 ("),
            std::string::npos)
      << redo.output;
  EXPECT_NE(redo.output.find("registered 8/8 photos"), std::string::npos) << redo.output;
}

}  // namespace
}  // namespace hdribr
