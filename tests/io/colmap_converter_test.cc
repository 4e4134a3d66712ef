// A model written by hdribr, converted by the real `colmap model_converter` (TEXT -> BIN -> TEXT)
// and read back identically; and our BINARY files read by colmap.
#include <gtest/gtest.h>

#include "io/colmap_model.h"
#include "io/io_test_util.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;

bool HaveColmap() { return test::RunCommand("command -v colmap").exit_code == 0; }

void Convert(const fs::path& in, const fs::path& out, const char* type) {
  fs::create_directories(out);
  const auto r = test::RunCommand("colmap model_converter --input_path " + in.string() +
                                  " --output_path " + out.string() + " --output_type " + type);
  ASSERT_EQ(r.exit_code, 0) << r.output;
}

TEST(ColmapConverter, TextToBinaryAndBackReadsIdentically) {
  if (!HaveColmap()) GTEST_SKIP() << "colmap is not installed";
  const fs::path dir = test::TempDir();
  const ColmapModel model = test::MakeColmapModel();
  WriteColmapModel(model, dir / "ours_txt", ColmapFormat::kText);
  Convert(dir / "ours_txt", dir / "colmap_bin", "BIN");
  ASSERT_TRUE(fs::exists(dir / "colmap_bin" / "images.bin"));
  // COLMAP may renormalise quaternions; everything else is bit-exact.
  test::ExpectModelsEqual(model, ReadColmapModelBinary(dir / "colmap_bin"), 1e-15);
  Convert(dir / "colmap_bin", dir / "colmap_txt", "TXT");
  test::ExpectModelsEqual(model, ReadColmapModelText(dir / "colmap_txt"), 1e-15);
}

TEST(ColmapConverter, ColmapReadsOurBinary) {
  if (!HaveColmap()) GTEST_SKIP() << "colmap is not installed";
  const fs::path dir = test::TempDir();
  const ColmapModel model = test::MakeColmapModel();
  WriteColmapModel(model, dir / "ours_bin", ColmapFormat::kBinary);
  Convert(dir / "ours_bin", dir / "colmap_txt", "TXT");
  test::ExpectModelsEqual(model, ReadColmapModelText(dir / "colmap_txt"), 1e-15);
}

}  // namespace
}  // namespace hdribr
