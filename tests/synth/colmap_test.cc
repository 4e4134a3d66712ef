// The synthetic capture's ground-truth models (TEXT, in COLMAP's conventions) read by the real
// colmap: `colmap model_converter` turns them into BINARY, which our binary reader reads back
// equal to what our text reader reads. That COLMAP's structure from motion registers every photo
// of a capture at its true pose is checked through `hdribr reconstruct`
// (ReconstructCli.SyntheticCaptureMatchesGroundTruth), not by running COLMAP again here.
#include <gtest/gtest.h>

#include <string>

#include "io/colmap_model.h"
#include "io/io_test_util.h"
#include "support/test_capture.h"
#include "synth/capture.h"
#include "test_util.h"

namespace hdribr::synth {
namespace {
namespace fs = std::filesystem;

TEST(SynthColmap, ColmapReadsTheGroundTruthModels) {
  if (test::RunCommand("colmap help").exit_code != 0) GTEST_SKIP() << "colmap is not installed";
  const fs::path tmp = test::TempDir();
  test::WriteTestCapture(tmp / "capture", {2, 3, 96, 72, 2, 3});
  for (const std::string model : {"gt", "gt/novel"}) {
    const fs::path text = tmp / "capture" / model;
    const fs::path binary = tmp / "binary" / model;
    fs::create_directories(binary);
    const auto r = test::RunCommand(
        "QT_QPA_PLATFORM=offscreen colmap model_converter --input_path " + text.string() +
        " --output_path " + binary.string() + " --output_type BIN");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const ColmapModel ours = ReadColmapModelText(text);
    EXPECT_EQ(ours.images.size(), model == "gt" ? 6u : 2u);
    // COLMAP may renormalise quaternions; everything else is bit-exact.
    test::ExpectModelsEqual(ours, ReadColmapModelBinary(binary), 1e-15);
  }
}

}  // namespace
}  // namespace hdribr::synth
