#include "io/workspace.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/core.hpp>

#include "core/error.h"
#include "io/colmap_model.h"
#include "io/exif.h"
#include "io/image.h"
#include "io/io_test_util.h"
#include "io/ply.h"
#include "io/series_json.h"
#include "test_util.h"
#include "workspace/workspace_fixture.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;

TEST(Workspace, LoadsFixture) {
  const fs::path dir = test::TempDir();
  test::MakeWorkspace(dir);
  const WorkspaceLayout layout = DetectWorkspace(dir);
  EXPECT_EQ(layout.kind, "hdribr");
  const Scene scene = LoadWorkspace(dir);
  ASSERT_EQ(scene.photos.size(), 4u);
  EXPECT_EQ(scene.photos[0].id, 2);
  EXPECT_EQ(scene.photos[3].id, 11);
  EXPECT_EQ(scene.cameras.size(), 2u);
  ASSERT_EQ(scene.series.size(), 2u);
  EXPECT_NEAR(scene.series[1].relative_exposure / scene.series[0].relative_exposure, 4.0, 1e-9);
  EXPECT_EQ(scene.photos[1].series_id, 1);
  EXPECT_EQ(scene.points.size(), 200u);
  EXPECT_TRUE(scene.points.HasNormals());
  EXPECT_TRUE(scene.points.HasRadii());
  EXPECT_NEAR(scene.scene_scale, 3.0, 0.15);
  EXPECT_TRUE(ValidateScene(scene).empty());
}

// Outputs inside the photo or model folder are refused (the next load would read them); the
// workspace root and folders beside it are fine, whatever the spelling of the path.
TEST(Workspace, OutputsInsideInputFoldersAreRefused) {
  const fs::path dir = test::TempDir();
  test::MakeWorkspace(dir);
  const WorkspaceLayout layout = DetectWorkspace(dir);
  for (const fs::path& out :
       {layout.images_dir / "new.png", layout.images_dir, layout.images_dir / "sub" / "a.exr",
        dir / "sparse" / ".." / "images" / "x.png", layout.sparse_dir / "frames"}) {
    EXPECT_THROW(CheckOutsideInputs(dir, out), UsageError) << out;
  }
  for (const fs::path& out : {dir / "view.png", dir / "hdr", dir / "images_out" / "a.png",
                              dir.parent_path() / "elsewhere.png", fs::path()}) {
    EXPECT_NO_THROW(CheckOutsideInputs(dir, out)) << out;
  }
  try {
    CheckOutsideInputs(dir, layout.images_dir / "new.png");
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("new.png: inside the workspace's input folder"),
              std::string::npos)
        << e.what();
  }
}

TEST(Workspace, GroupsFromExifWithoutSeriesJson) {
  const fs::path dir = test::TempDir();
  test::FixtureOptions opt;
  opt.write_series_json = false;
  test::MakeWorkspace(dir, opt);
  const Scene scene = LoadWorkspace(dir);
  ASSERT_EQ(scene.series.size(), 2u);
  EXPECT_EQ(scene.series[0].photo_indices, std::vector<int>({0, 2}));
  EXPECT_DOUBLE_EQ(*scene.photos[1].exposure.time_s, 1.0 / 25);
}

TEST(Workspace, SparsePointsUsedWithoutPly) {
  const fs::path dir = test::TempDir();
  test::FixtureOptions opt;
  opt.write_points_ply = false;
  test::MakeWorkspace(dir, opt);
  const Scene scene = LoadWorkspace(dir);
  EXPECT_TRUE(scene.points.empty());
  const auto problems = ValidateScene(scene);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("no points"), std::string::npos);
}

TEST(Workspace, DistortedCameraIsRefusedWithHint) {
  const fs::path dir = test::TempDir();
  test::FixtureOptions opt;
  opt.distorted_camera = true;
  test::MakeWorkspace(dir, opt);
  try {
    LoadWorkspace(dir);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("image_undistorter"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("sparse"), std::string::npos) << e.what();
  }
}

TEST(Workspace, ValidationFindsMissingAndMisSizedPhotos) {
  const fs::path dir = test::TempDir();
  test::MakeWorkspace(dir);
  fs::remove(dir / "images" / "p1.jpg");
  WriteImage(dir / "images" / "p2.jpg", cv::Mat(10, 10, CV_8UC3, cv::Scalar(1, 2, 3)));
  const Scene scene = LoadWorkspace(dir);
  const auto problems = ValidateScene(scene);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_NE(problems[0].find("p1.jpg: photo file is missing"), std::string::npos);
  EXPECT_NE(problems[1].find("p2.jpg: image is 10x10, not the shape of camera 7 (80x60)"),
            std::string::npos);
  // The camera's frame at another scale is no problem (the renderer samples it by its size).
  WriteImage(dir / "images" / "p2.jpg", cv::Mat(30, 40, CV_8UC3, cv::Scalar(1, 2, 3)));
  EXPECT_EQ(ValidateScene(LoadWorkspace(dir)).size(), 1u);
}

TEST(Workspace, MissingFolderAndEmptyFolderAreClearErrors) {
  const fs::path dir = test::TempDir();
  EXPECT_THROW(DetectWorkspace(dir / "nope"), InputError);
  try {
    DetectWorkspace(dir);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no COLMAP model"), std::string::npos);
  }
}

TEST(Workspace, BinarySparseAndOtherLayoutsLoadTheSameScene) {
  const fs::path dir = test::TempDir();
  test::MakeWorkspace(dir / "text");
  const Scene text = LoadWorkspace(dir / "text");

  // Binary model in sparse/0/, points in fused.ply: the COLMAP dense layout.
  test::MakeWorkspace(dir / "dense");
  const ColmapModel model = ReadColmapModel(dir / "dense" / "sparse");
  fs::remove_all(dir / "dense" / "sparse");
  WriteColmapModel(model, dir / "dense" / "sparse" / "0", ColmapFormat::kBinary);
  fs::rename(dir / "dense" / "points.ply", dir / "dense" / "fused.ply");
  fs::remove(dir / "dense" / "series.json");
  const WorkspaceLayout layout = DetectWorkspace(dir / "dense");
  EXPECT_EQ(layout.kind, "colmap-dense");
  EXPECT_EQ(layout.sparse_dir, dir / "dense" / "sparse" / "0");
  const Scene dense = LoadWorkspace(dir / "dense");
  ASSERT_EQ(dense.photos.size(), text.photos.size());
  for (size_t i = 0; i < dense.photos.size(); ++i) {
    EXPECT_EQ(dense.photos[i].name, text.photos[i].name);
    EXPECT_EQ(dense.photos[i].cam_from_world.translation,
              text.photos[i].cam_from_world.translation);
    EXPECT_EQ(dense.photos[i].series_id, text.photos[i].series_id);
  }
  EXPECT_EQ(dense.points.size(), text.points.size());
  EXPECT_EQ(dense.series.size(), 2u);
  EXPECT_TRUE(ValidateScene(dense).empty());
}

// Each corrupt input is an InputError naming the file, and nothing in the workspace changes.
TEST(Workspace, CorruptInputsNameTheFileAndAreLeftUntouched) {
  const fs::path dir = test::TempDir();
  auto expect_error = [&](const fs::path& ws, const fs::path& file, const std::string& needle) {
    const auto before = test::Snapshot(ws);
    try {
      LoadWorkspace(ws);
      ADD_FAILURE() << "no error for " << file;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
    EXPECT_EQ(test::Snapshot(ws), before);
  };

  test::MakeWorkspace(dir / "ply");
  fs::resize_file(dir / "ply" / "points.ply", fs::file_size(dir / "ply" / "points.ply") - 10);
  expect_error(dir / "ply", dir / "ply" / "points.ply", "truncated");

  test::MakeWorkspace(dir / "empty_ply");
  WritePly(dir / "empty_ply" / "points.ply", PointCloud{});
  expect_error(dir / "empty_ply", dir / "empty_ply" / "points.ply", "no vertices");

  test::MakeWorkspace(dir / "bin");
  const ColmapModel model = ReadColmapModel(dir / "bin" / "sparse");
  WriteColmapModel(model, dir / "bin" / "sparse", ColmapFormat::kBinary);
  fs::resize_file(dir / "bin" / "sparse" / "images.bin", 100);
  expect_error(dir / "bin", dir / "bin" / "sparse" / "images.bin", "truncated");

  test::MakeWorkspace(dir / "quat");
  ColmapModel bad = model;
  bad.images.begin()->second.cam_from_world.rotation.coeffs() << 0.5, 0.5, 0.5, 0.6;
  WriteColmapModel(bad, dir / "quat" / "sparse", ColmapFormat::kText);
  expect_error(dir / "quat", dir / "quat" / "sparse" / "images.txt", "not a rotation");
}

TEST(Workspace, CorruptPhotoIsAProblemLineAndMissingExifIsTolerated) {
  const fs::path dir = test::TempDir();
  test::FixtureOptions opt;
  opt.write_series_json = false;
  test::MakeWorkspace(dir, opt);
  // p0: truncated JPEG; p1: valid JPEG without EXIF.
  fs::resize_file(dir / "images" / "p0.jpg", fs::file_size(dir / "images" / "p0.jpg") / 2);
  WriteImage(dir / "images" / "p1.jpg", cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)));
  const Scene scene = LoadWorkspace(dir);
  EXPECT_FALSE(scene.photos[1].exposure.time_s.has_value());
  EXPECT_DOUBLE_EQ(scene.photos[1].exposure.Relative(), 1.0);
  const auto problems = ValidateScene(scene);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find((dir / "images" / "p0.jpg").string() + ": corrupt JPEG"),
            std::string::npos)
      << problems[0];
}

TEST(SeriesJson, RoundTripAndBadInput) {
  const fs::path dir = test::TempDir();
  test::MakeWorkspace(dir);
  Scene scene = LoadWorkspace(dir);
  const fs::path copy = dir / "copy.json";
  WriteSeriesJson(copy, scene.series, scene.photos);
  std::vector<Photo> photos = scene.photos;
  const auto again = ReadSeriesJson(copy, photos);
  ASSERT_EQ(again.size(), scene.series.size());
  for (size_t i = 0; i < again.size(); ++i) {
    EXPECT_EQ(again[i].photo_indices, scene.series[i].photo_indices);
    EXPECT_NEAR(again[i].relative_exposure, scene.series[i].relative_exposure, 1e-12);
  }

  auto expect_error = [&](const std::string& text, const std::string& needle) {
    const fs::path bad = dir / "bad.json";
    std::ofstream(bad) << text;
    std::vector<Photo> ph = scene.photos;
    try {
      ReadSeriesJson(bad, ph);
      ADD_FAILURE() << "no error for " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
    }
  };
  expect_error("{not json", "invalid JSON");
  expect_error(R"({"series": [{"photos": ["nope.jpg"]}]})", "unknown photo 'nope.jpg'");
  expect_error(R"({"series": [{"photos": ["p0.jpg","p1.jpg","p2.jpg"]},
                              {"photos": ["p3.jpg","p0.jpg"]}]})",
               "listed in two series");
  expect_error(R"({"series": [{"photos": ["p0.jpg","p1.jpg","p2.jpg"]}]})",
               "'p3.jpg' is in no series");
  expect_error(R"({"series": [{"photos": ["p0.jpg","p1.jpg","p2.jpg","p3.jpg"],
                               "relative_exposure": -1}]})",
               "positive");
}

}  // namespace
}  // namespace hdribr
