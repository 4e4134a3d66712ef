// COLMAP TEXT/BINARY reading and writing: round trips, format preference, every corruption.
#include "io/colmap_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/io_test_util.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;
using test::ExpectInputError;

void WriteText(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

TEST(ColmapModel, TextRoundTripIsExact) {
  const fs::path dir = test::TempDir();
  const ColmapModel m = test::MakeColmapModel();
  WriteColmapModel(m, dir / "m", ColmapFormat::kText);
  EXPECT_TRUE(IsColmapModelDir(dir / "m"));
  EXPECT_EQ(test::Snapshot(dir / "m").size(), 3u) << "no temporary files left behind";
  test::ExpectModelsEqual(m, ReadColmapModelText(dir / "m"));
  test::ExpectModelsEqual(m, ReadColmapModel(dir / "m"));
}

TEST(ColmapModel, BinaryRoundTripIsExact) {
  const fs::path dir = test::TempDir();
  const ColmapModel m = test::MakeColmapModel();
  WriteColmapModel(m, dir / "m", ColmapFormat::kBinary);
  EXPECT_TRUE(IsColmapModelDir(dir / "m"));
  EXPECT_EQ(test::Snapshot(dir / "m").size(), 3u);
  test::ExpectModelsEqual(m, ReadColmapModelBinary(dir / "m"));
  const ColmapBinaryFiles f = SerializeColmapModelBinary(m);
  test::ExpectModelsEqual(m, ParseColmapModelBinary(f.cameras, f.images, f.points3d, dir));
}

TEST(ColmapModel, KeepsNonContiguousIdsAndUnmatchedPoints) {
  const fs::path dir = test::TempDir();
  WriteColmapModel(test::MakeColmapModel(), dir, ColmapFormat::kText);
  const ColmapModel m = ReadColmapModel(dir);
  std::vector<int> ids;
  for (const auto& [id, im] : m.images) ids.push_back(id);
  EXPECT_EQ(ids, std::vector<int>({3, 8, 20}));
  EXPECT_EQ(m.images.at(8).camera_id, 9);
  EXPECT_EQ(m.cameras.at(9).model, CameraModel::kSimpleRadial);
  EXPECT_EQ(m.images.at(3).points2d[5].point3d_id, -1);
  EXPECT_EQ(m.points3d.count(10), 1u);
}

TEST(ColmapModel, PrefersBinaryWhenBothExist) {
  const fs::path dir = test::TempDir();
  ColmapModel text = test::MakeColmapModel();
  ColmapModel bin = text;
  bin.cameras.at(4).params[0] = 999;
  WriteColmapModel(text, dir, ColmapFormat::kText);
  WriteColmapModel(bin, dir, ColmapFormat::kBinary);
  EXPECT_EQ(ReadColmapModel(dir).cameras.at(4).params[0], 999);
  // As in COLMAP, an incomplete binary set falls back to a complete text set...
  fs::remove(dir / "points3D.bin");
  EXPECT_EQ(ReadColmapModel(dir).cameras.at(4).params[0], 500.125);
  // ...and without one, the missing binary file is named.
  fs::remove(dir / "points3D.txt");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"points3D.bin", "no such file"});
}

TEST(ColmapModel, TextParsesCommentsBlankLinesAndCrLf) {
  const fs::path dir = test::TempDir();
  WriteText(dir / "cameras.txt", "# c\r\n\r\n1 PINHOLE 4 3 2 2 2 1.5\r\n");
  WriteText(dir / "images.txt", "# i\n5 1 0 0 0 0.5 0 0 1 a.png\n\n");
  WriteText(dir / "points3D.txt", "");
  const ColmapModel m = ReadColmapModel(dir);
  ASSERT_EQ(m.cameras.size(), 1u);
  EXPECT_EQ(m.cameras.at(1).params, std::vector<double>({2, 2, 2, 1.5}));
  ASSERT_EQ(m.images.size(), 1u);
  EXPECT_EQ(m.images.at(5).name, "a.png");
  EXPECT_TRUE(m.images.at(5).points2d.empty());
}

TEST(ColmapModel, MissingFolderAndFilesNameTheFile) {
  const fs::path dir = test::TempDir();
  ExpectInputError([&] { ReadColmapModel(dir / "nope"); }, {"nope", "no such model folder"});
  ExpectInputError([&] { ReadColmapModel(dir); }, {"cameras.txt", "no such file"});
  WriteColmapModel(test::MakeColmapModel(), dir, ColmapFormat::kText);
  fs::remove(dir / "images.txt");
  EXPECT_FALSE(IsColmapModelDir(dir));
  ExpectInputError([&] { ReadColmapModelText(dir); }, {"images.txt", "no such file"});
}

// Every truncation of every binary file is refused with the file's name, never a crash.
TEST(ColmapModel, EveryTruncatedBinaryIsAnInputError) {
  const fs::path dir = test::TempDir();
  const ColmapBinaryFiles f = SerializeColmapModelBinary(test::MakeColmapModel());
  for (int which = 0; which < 3; ++which) {
    const std::string& full = which == 0 ? f.cameras : (which == 1 ? f.images : f.points3d);
    const char* name = which == 0 ? "cameras.bin" : (which == 1 ? "images.bin" : "points3D.bin");
    for (size_t len = 0; len < full.size(); ++len) {
      const std::string cut = full.substr(0, len);
      try {
        ParseColmapModelBinary(which == 0 ? cut : f.cameras, which == 1 ? cut : f.images,
                               which == 2 ? cut : f.points3d, dir);
        ADD_FAILURE() << name << " cut at " << len << " was accepted";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
      }
    }
  }
  // And through the files on disk.
  WriteColmapModel(test::MakeColmapModel(), dir, ColmapFormat::kBinary);
  fs::resize_file(dir / "images.bin", fs::file_size(dir / "images.bin") - 5);
  const auto before = test::Snapshot(dir);
  ExpectInputError([&] { ReadColmapModel(dir); }, {(dir / "images.bin").string(), "truncated"});
  EXPECT_EQ(test::Snapshot(dir), before) << "a failed read must not modify its input";
}

TEST(ColmapModel, AbsurdCountsAreRefusedWithoutAllocating) {
  const fs::path dir = test::TempDir();
  ColmapBinaryFiles f = SerializeColmapModelBinary(test::MakeColmapModel());
  const std::uint64_t huge = std::uint64_t{1} << 60;
  std::string cams = f.cameras;
  std::memcpy(cams.data(), &huge, 8);
  ExpectInputError([&] { ParseColmapModelBinary(cams, f.images, f.points3d, dir); },
                   {"cameras.bin", "claims 1152921504606846976 cameras"});
  std::string pts = f.points3d;
  std::memcpy(pts.data(), &huge, 8);
  ExpectInputError([&] { ParseColmapModelBinary(f.cameras, f.images, pts, dir); },
                   {"points3D.bin", "claims"});
  // The 2D point count of the first image sits right after its name.
  std::string ims = f.images;
  const size_t count_at = ims.find(std::string("img_0.jpg") + '\0') + 10;
  std::memcpy(ims.data() + count_at, &huge, 8);
  ExpectInputError([&] { ParseColmapModelBinary(f.cameras, ims, f.points3d, dir); },
                   {"images.bin", "2D points"});
  ExpectInputError([&] { ParseColmapModelBinary(f.cameras + "x", f.images, f.points3d, dir); },
                   {"cameras.bin", "trailing"});
}

TEST(ColmapModel, NanPoseAndNonUnitQuaternionAreRefused) {
  const fs::path dir = test::TempDir();
  ColmapModel m = test::MakeColmapModel();
  m.images.at(8).cam_from_world.translation.y() = std::numeric_limits<double>::quiet_NaN();
  WriteColmapModel(m, dir / "nan_txt", ColmapFormat::kText);
  ExpectInputError([&] { ReadColmapModel(dir / "nan_txt"); },
                   {"images.txt", "image 8 (img_1.jpg) has a non-finite pose"});
  WriteColmapModel(m, dir / "nan_bin", ColmapFormat::kBinary);
  ExpectInputError([&] { ReadColmapModel(dir / "nan_bin"); }, {"images.bin", "non-finite pose"});

  m = test::MakeColmapModel();
  m.images.at(20).cam_from_world.rotation.coeffs() *= 1.1;
  WriteColmapModel(m, dir / "q_txt", ColmapFormat::kText);
  ExpectInputError([&] { ReadColmapModel(dir / "q_txt"); }, {"images.txt", "not a rotation"});
  WriteColmapModel(m, dir / "q_bin", ColmapFormat::kBinary);
  ExpectInputError([&] { ReadColmapModel(dir / "q_bin"); }, {"images.bin", "not a rotation"});
  m.images.at(20).cam_from_world.rotation.coeffs().setZero();
  WriteColmapModel(m, dir / "q0", ColmapFormat::kBinary);
  ExpectInputError([&] { ReadColmapModel(dir / "q0"); }, {"images.bin", "not a rotation"});
}

TEST(ColmapModel, UnknownCameraModelAndBadParametersAreRefused) {
  const fs::path dir = test::TempDir();
  WriteColmapModel(test::MakeColmapModel(), dir, ColmapFormat::kText);
  WriteText(dir / "cameras.txt", "4 FISHEYE_X 640 480 1 2 3\n9 PINHOLE 800 600 1 1 1 1\n");
  ExpectInputError([&] { ReadColmapModel(dir); },
                   {"cameras.txt", "line 1", "unknown camera model 'FISHEYE_X'"});
  WriteText(dir / "cameras.txt", "4 PINHOLE 640 480 1 2 3\n");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"cameras.txt", "needs 4 parameters, got 3"});
  WriteText(dir / "cameras.txt", "4 PINHOLE 640 -480 1 2 3 4\n");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"cameras.txt", "invalid size"});
  WriteText(dir / "cameras.txt", "4 PINHOLE 640 480 500 0 320 240\n");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"cameras.txt", "focal length <= 0"});
  WriteText(dir / "cameras.txt", "4 SIMPLE_RADIAL 640 480 -500 320 240 0\n");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"cameras.txt", "focal length <= 0"});
  WriteText(dir / "cameras.txt", "4 PINHOLE 640 480 1 2 3 x4\n");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"cameras.txt", "'x4' is not a number"});

  ColmapBinaryFiles f = SerializeColmapModelBinary(test::MakeColmapModel());
  const std::int32_t bad_model = 99;
  std::memcpy(f.cameras.data() + 8 + 4, &bad_model, 4);
  ExpectInputError([&] { ParseColmapModelBinary(f.cameras, f.images, f.points3d, dir); },
                   {"cameras.bin", "unknown camera model 99"});
}

TEST(ColmapModel, DanglingIdsAreRefused) {
  const fs::path dir = test::TempDir();
  ColmapModel m = test::MakeColmapModel();
  m.images.at(3).camera_id = 5;
  WriteColmapModel(m, dir / "a", ColmapFormat::kBinary);
  ExpectInputError([&] { ReadColmapModel(dir / "a"); }, {"images.bin", "refers to camera 5"});

  m = test::MakeColmapModel();
  m.points3d.begin()->second.track.push_back({77, 0});
  WriteColmapModel(m, dir / "b", ColmapFormat::kText);
  ExpectInputError([&] { ReadColmapModel(dir / "b"); }, {"points3D.txt", "refers to image 77"});

  m = test::MakeColmapModel();
  m.points3d.begin()->second.track.push_back({8, 6});
  WriteColmapModel(m, dir / "c", ColmapFormat::kText);
  ExpectInputError([&] { ReadColmapModel(dir / "c"); }, {"points3D.txt", "2D point 6 of image 8"});

  m = test::MakeColmapModel();
  m.images.at(20).points2d[5].point3d_id = 12345;
  WriteColmapModel(m, dir / "d", ColmapFormat::kBinary);
  ExpectInputError([&] { ReadColmapModel(dir / "d"); }, {"images.bin", "3D point 12345"});
}

TEST(ColmapModel, MalformedTextLinesAreRefusedWithLineNumbers) {
  const fs::path dir = test::TempDir();
  WriteColmapModel(test::MakeColmapModel(), dir, ColmapFormat::kText);
  const std::string images = ReadFileToString(dir / "images.txt");
  WriteText(dir / "images.txt", images + "99 1 0 0 0 0 0 0 4\n\n");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"images.txt", "line 11", "expected IMAGE_ID"});
  WriteText(dir / "images.txt", images + "3 1 0 0 0 0 0 0 4 again.jpg\n\n");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"images.txt", "image 3 defined twice"});
  WriteText(dir / "images.txt", images + "99 1 0 0 0 0 0 0 4 x.jpg\n1 2\n");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"images.txt", "line 12", "triples"});
  WriteText(dir / "images.txt", images);
  WriteText(dir / "points3D.txt", "1 0 0 0 300 0 0 1\n");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"points3D.txt", "line 1", "0..255"});
  WriteText(dir / "points3D.txt", "1 0 0 0 3 0 0 1 3\n");
  ExpectInputError([&] { ReadColmapModel(dir); }, {"points3D.txt", "expected POINT3D_ID"});
}

}  // namespace
}  // namespace hdribr
