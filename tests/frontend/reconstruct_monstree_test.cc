// `hdribr reconstruct` of the monstree photos with the real colmap: the shared fixture
// MonstreeWorkspace (tests/monstree_workspace.h), made by the setup test below once per CTest
// run and read by this test and by the eval test of monstree (tests/eval/eval_monstree_test.cc).
#include <gtest/gtest.h>

#include "io/colmap_model.h"
#include "io/ply.h"
#include "monstree_workspace.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;

// The reconstruction itself, with its check that the photo folder is left untouched.
TEST(Fixture, MonstreeWorkspace) {
  HDRIBR_REQUIRE_DATASET(monstree, "monstree");
  test::RemakeSharedFixture(test::kMonstreeFixture, [&](const fs::path& dir) {
    test::MakeMonstreeWorkspace(monstree, dir);
  });
}

TEST(ReconstructCli, MonstreeRegistersMostPhotos) {
  HDRIBR_REQUIRE_DATASET(monstree, "monstree");
  const fs::path ws = test::MonstreeWorkspace(monstree);
  const size_t photos = test::FileTimes(monstree / "images").size();
  const ColmapModel rec = ReadColmapModel(ws / "sparse");
  EXPECT_GE(rec.images.size() * 10, photos * 9) << rec.images.size() << " of " << photos;
  EXPECT_TRUE(fs::exists(ws / "series.json"));
  EXPECT_TRUE(fs::exists(ws / "logs"));
  const PointCloud dense = ReadPly(ws / "points.ply");
  std::cout << "monstree dense points: " << dense.size() << "\n";
  EXPECT_GT(dense.size(), 10000u);
  const auto inspect = test::RunCommand(std::string(HDRIBR_EXE) + " -q inspect " + ws.string());
  EXPECT_EQ(inspect.exit_code, 0) << inspect.output;
}

}  // namespace
}  // namespace hdribr
