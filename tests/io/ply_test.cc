// PLY through PCL: round trips of every attribute combination, foreign files, corruption.
#include "io/ply.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/io_test_util.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;
using test::ExpectInputError;

PointCloud MakeCloud(int n, bool normals, bool colors, bool radii) {
  PointCloud c;
  for (int i = 0; i < n; ++i) {
    const float t = static_cast<float>(i) / static_cast<float>(n);
    c.positions.emplace_back(std::cos(7 * t) * 1.5f, t - 0.3f / 7.0f, 1e-3f * i);
    if (normals) c.normals.push_back(Eigen::Vector3f(std::cos(7 * t), 0.25f, 1.0f).normalized());
    if (colors) {
      c.colors.push_back({static_cast<std::uint8_t>(i % 256),
                          static_cast<std::uint8_t>(255 - i % 256),
                          static_cast<std::uint8_t>(i * 7 % 256)});
    }
    if (radii) c.radii.push_back(0.01f + 1e-4f * i);
  }
  return c;
}

void ExpectCloudsEqual(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.HasNormals(), b.HasNormals());
  EXPECT_EQ(a.HasColors(), b.HasColors());
  EXPECT_EQ(a.HasRadii(), b.HasRadii());
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.positions[i], b.positions[i]) << i;
    if (a.HasNormals() && b.HasNormals()) {
      ASSERT_EQ(a.normals[i], b.normals[i]) << i;
    }
    if (a.HasColors() && b.HasColors()) {
      ASSERT_EQ(a.colors[i], b.colors[i]) << i;
    }
    if (a.HasRadii() && b.HasRadii()) {
      ASSERT_EQ(a.radii[i], b.radii[i]) << i;
    }
  }
}

TEST(Ply, RoundTripsEveryAttributeCombinationBinaryAndAscii) {
  const fs::path dir = test::TempDir();
  for (int mask = 0; mask < 8; ++mask) {
    for (bool binary : {true, false}) {
      SCOPED_TRACE("mask " + std::to_string(mask) + (binary ? " binary" : " ascii"));
      const PointCloud c = MakeCloud(300, mask & 1, mask & 2, mask & 4);
      const fs::path p = dir / ("c" + std::to_string(mask) + (binary ? "b" : "a") + ".ply");
      WritePly(p, c, binary);
      ExpectCloudsEqual(c, ReadPly(p));  // %.9g makes ASCII floats exact too
      ExpectCloudsEqual(c, ParsePly(ReadFileToString(p), p));
    }
  }
  EXPECT_EQ(test::Snapshot(dir).size(), 16u) << "no temporary files left behind";
}

TEST(Ply, ReadsForeignFilesWithScaleExtraPropertiesAndFaces) {
  const fs::path dir = test::TempDir();
  std::ofstream(dir / "a.ply") << "ply\nformat ascii 1.0\ncomment foreign\n"
                                  "element vertex 3\nproperty double x\nproperty double y\n"
                                  "property double z\nproperty float intensity\n"
                                  "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                  "property float scale\n"
                                  "element face 1\nproperty list uchar int vertex_indices\n"
                                  "end_header\n"
                                  "0 0 0 5 255 0 0 0.5\n1 0 0 5 0 255 0 0.25\n0 1 0 5 0 0 255 2\n"
                                  "3 0 1 2\n";
  const PointCloud c = ReadPly(dir / "a.ply");
  ASSERT_EQ(c.size(), 3u);
  EXPECT_FALSE(c.HasNormals());
  ASSERT_TRUE(c.HasColors());
  ASSERT_TRUE(c.HasRadii());
  EXPECT_EQ(c.positions[2], Eigen::Vector3f(0, 1, 0));
  EXPECT_EQ(c.colors[1], (std::array<std::uint8_t, 3>{0, 255, 0}));
  EXPECT_EQ(c.radii[0], 0.5f);
  EXPECT_EQ(c.radii[2], 2.0f);
}

TEST(Ply, ReadsBigEndianBinary) {
  const fs::path dir = test::TempDir();
  std::string s =
      "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  for (float v : {1.0f, 2.0f, 3.0f, -4.0f, 0.5f, 6.0f}) {
    std::uint32_t u;
    std::memcpy(&u, &v, 4);
    for (int k = 3; k >= 0; --k) s.push_back(static_cast<char>((u >> (8 * k)) & 0xFF));
  }
  std::ofstream(dir / "be.ply", std::ios::binary) << s;
  const PointCloud c = ReadPly(dir / "be.ply");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.positions[1], Eigen::Vector3f(-4.0f, 0.5f, 6.0f));
}

TEST(Ply, BadFilesAreInputErrorsNamingTheFile) {
  const fs::path dir = test::TempDir();
  const fs::path p = dir / "x.ply";
  ExpectInputError([&] { ReadPly(p); }, {p.string(), "no such file"});

  std::ofstream(p) << "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
                      "property float y\nproperty float z\nend_header\n";
  ExpectInputError([&] { ReadPly(p); }, {p.string(), "no vertices"});

  WritePly(p, MakeCloud(100, true, true, true), true);
  fs::resize_file(p, fs::file_size(p) - 3);
  const auto before = test::Snapshot(dir);
  ExpectInputError([&] { ReadPly(p); }, {p.string(), "truncated"});
  EXPECT_EQ(test::Snapshot(dir), before) << "a failed read must not modify its input";

  WritePly(p, MakeCloud(100, false, false, false), false);
  fs::resize_file(p, fs::file_size(p) - 400);
  ExpectInputError([&] { ReadPly(p); }, {p.string()});

  std::ofstream(p, std::ios::trunc) << "ply\nformat binary_little_endian 1.0\n"
                                       "element vertex 4000000000\nproperty float x\n"
                                       "property float y\nproperty float z\nend_header\n1234";
  ExpectInputError([&] { ReadPly(p); }, {p.string(), "absurd element count"});
  std::ofstream(p, std::ios::trunc) << "ply\nformat binary_little_endian 1.0\n"
                                       "element vertex 400000000\nproperty float x\n"
                                       "property float y\nproperty float z\nend_header\n1234";
  ExpectInputError([&] { ReadPly(p); }, {p.string(), "truncated", "400000000"});

  std::ofstream(p, std::ios::trunc) << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                                       "property float y\nproperty float z\nend_header\n"
                                       "1 2 3\n4 5 banana\n";
  ExpectInputError([&] { ReadPly(p); }, {p.string()});
  std::ofstream(p, std::ios::trunc) << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                                       "property float y\nproperty float z\nend_header\n"
                                       "1 2 3\n4 nan 6\n";
  ExpectInputError([&] { ReadPly(p); }, {p.string(), "vertex 1", "non-finite"});
  std::ofstream(p, std::ios::trunc) << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                                       "property float y\nend_header\n1 2\n3 4\n";
  ExpectInputError([&] { ReadPly(p); }, {p.string(), "no 'z' property"});
  std::ofstream(p, std::ios::trunc) << "not a ply at all";
  ExpectInputError([&] { ReadPly(p); }, {p.string(), "not a PLY"});
  std::ofstream(p, std::ios::trunc) << "ply\nformat ascii 1.0\nelement vertex 1\n";
  ExpectInputError([&] { ReadPly(p); }, {p.string(), "end_header"});
  std::ofstream(p, std::ios::trunc) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty quux x\n"
                                       "end_header\n1\n";
  ExpectInputError([&] { ReadPly(p); }, {p.string(), "bad property"});
  ExpectInputError([&] { ParsePly("", "mem.ply"); }, {"mem.ply", "not a PLY"});
}

TEST(Ply, FailedWriteLeavesNothing) {
  const fs::path dir = test::TempDir();
  EXPECT_THROW(WritePly(dir / "no_such_dir" / "x.ply", MakeCloud(5, false, false, false)),
               InputError);
  PointCloud bad = MakeCloud(5, true, false, false);
  bad.normals.pop_back();
  EXPECT_THROW(WritePly(dir / "bad.ply", bad), UsageError);
  EXPECT_TRUE(test::Snapshot(dir).empty());
}

}  // namespace
}  // namespace hdribr
