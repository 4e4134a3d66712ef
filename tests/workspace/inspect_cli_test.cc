// `hdribr inspect` end to end: text and JSON output, exit codes, one-line errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/io_test_util.h"
#include "support/exe.h"
#include "test_util.h"
#include "workspace/workspace_fixture.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;
using test::Exe;

TEST(InspectCli, PrintsSummaryAndJson) {
  const fs::path dir = test::TempDir();
  test::MakeWorkspace(dir);
  const auto text = test::RunCommand(Exe() + " inspect " + dir.string());
  EXPECT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("4 in 2 exposure series"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("200 (normals, radii)"), std::string::npos) << text.output;

  const auto js = test::RunCommand(Exe() + " -q inspect --json " + dir.string());
  ASSERT_EQ(js.exit_code, 0) << js.output;
  const auto j = nlohmann::json::parse(js.output);
  EXPECT_EQ(j["num_photos"], 4);
  EXPECT_EQ(j["series"].size(), 2u);
  EXPECT_EQ(j["points"]["count"], 200);
  EXPECT_GT(j["scene_scale"].get<double>(), 0.0);
  EXPECT_TRUE(j["problems"].empty());
}

TEST(InspectCli, ProblemsGiveNonZeroExitAndOneLineEach) {
  const fs::path dir = test::TempDir();
  test::MakeWorkspace(dir);
  fs::remove(dir / "images" / "p3.jpg");
  const auto r = test::RunCommand(Exe() + " inspect " + dir.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(
      r.output.find("problem: " + (dir / "images" / "p3.jpg").string() + ": photo file is missing"),
      std::string::npos)
      << r.output;
}

TEST(InspectCli, BadInputIsOneClearLine) {
  const fs::path dir = test::TempDir();
  const auto r = test::RunCommand(Exe() + " inspect " + (dir / "missing").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, "error: " + (dir / "missing").string() + ": no such workspace folder\n");

  test::MakeWorkspace(dir / "ws");
  std::ofstream(dir / "ws" / "sparse" / "images.txt", std::ios::trunc)
      << "1 nan 0 0 0 0 0 0 3 p0.jpg\n\n";
  const auto nan = test::RunCommand(Exe() + " inspect " + (dir / "ws").string());
  EXPECT_EQ(nan.exit_code, 2) << nan.output;
  EXPECT_NE(nan.output.find("images.txt"), std::string::npos) << nan.output;
  EXPECT_EQ(std::count(nan.output.begin(), nan.output.end(), '\n'), 1) << nan.output;
}

TEST(InspectCli, CommandLineErrorsAreOneLine) {
  // Parse errors of the command line (CLI11) follow the same one-line rule.
  for (const std::string args : {" inspect", " inspect a b", " inspect --no-such-option x", "",
                                 " inspect x --gpu --max-photo-size -1"}) {
    const auto r = test::RunCommand(Exe() + args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(r.output.rfind("error: ", 0), 0u) << args << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
  }
}

// Bad workspaces: exit 2 and exactly one line naming the file; inspect never writes anything.
TEST(InspectCli, CorruptFilesGiveOneLineAndLeaveTheWorkspaceUntouched) {
  const fs::path dir = test::TempDir();
  auto run_bad = [&](const fs::path& ws, const fs::path& file, const std::string& needle) {
    const auto before = test::Snapshot(ws);
    const auto r = test::RunCommand(Exe() + " inspect " + ws.string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(r.output.rfind("error: " + file.string() + ": ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(needle), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_EQ(test::Snapshot(ws), before) << "inspect modified " << ws;
  };
  test::MakeWorkspace(dir / "ply");
  {
    std::ofstream(dir / "ply" / "points.ply", std::ios::trunc)
        << "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
           "property float z\nend_header\n";
  }
  run_bad(dir / "ply", dir / "ply" / "points.ply", "no vertices");

  test::MakeWorkspace(dir / "cams");
  {
    std::ofstream(dir / "cams" / "sparse" / "cameras.txt", std::ios::trunc) << "3 WEIRD 64 48 1\n";
  }
  run_bad(dir / "cams", dir / "cams" / "sparse" / "cameras.txt", "unknown camera model 'WEIRD'");

  test::MakeWorkspace(dir / "dangling");
  {
    std::ofstream(dir / "dangling" / "sparse" / "points3D.txt", std::ios::trunc)
        << "1 0 0 0 1 2 3 0.5 99 0\n";
  }
  run_bad(dir / "dangling", dir / "dangling" / "sparse" / "points3D.txt", "refers to image 99");
}

TEST(InspectCli, CorruptPhotoIsAProblemAndGoodRunsWriteNothing) {
  const fs::path dir = test::TempDir();
  test::MakeWorkspace(dir);
  const auto good_before = test::Snapshot(dir);
  EXPECT_EQ(test::RunCommand(Exe() + " -q inspect --json " + dir.string()).exit_code, 0);
  EXPECT_EQ(test::Snapshot(dir), good_before);

  const fs::path photo = dir / "images" / "p2.jpg";
  fs::resize_file(photo, fs::file_size(photo) - 100);
  const auto before = test::Snapshot(dir);
  const auto r = test::RunCommand(Exe() + " inspect " + dir.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("problem: " + photo.string() + ": corrupt JPEG"), std::string::npos)
      << r.output;
  EXPECT_EQ(test::Snapshot(dir), before);
}

}  // namespace
}  // namespace hdribr
