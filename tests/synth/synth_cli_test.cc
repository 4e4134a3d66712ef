// `hdribr synth` end to end: a capture that `hdribr inspect` accepts, the preview, errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "io/image.h"
#include "support/exe.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;
using test::Exe;

TEST(SynthCli, MakesACaptureThatInspectAccepts) {
  const fs::path tmp = test::TempDir();
  const fs::path out = tmp / "cap";
  const auto r = test::RunCommand(Exe() + " synth " + out.string() +
                                  " --scene thin --series 2 --views 3 --size 160x120 --novel 1"
                                  " --preview " +
                                  (tmp / "preview.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("6 photos"), std::string::npos) << r.output;
  const cv::Mat preview = ReadImage(tmp / "preview.png");
  EXPECT_EQ(preview.cols, 3 * 160);  // two exposures + depth
  EXPECT_EQ(preview.rows, 120);

  const auto js = test::RunCommand(Exe() + " -q inspect --json " + (out / "workspace").string());
  ASSERT_EQ(js.exit_code, 0) << js.output;
  const auto j = nlohmann::json::parse(js.output);
  EXPECT_EQ(j["layout"], "hdribr");
  EXPECT_EQ(j["num_photos"], 6);
  EXPECT_EQ(j["series"].size(), 2u);
  EXPECT_TRUE(j["points"]["radii"].get<bool>());
  EXPECT_TRUE(j["problems"].empty());
}

TEST(SynthCli, BadInputGivesOneLineAndNoOutput) {
  const fs::path tmp = test::TempDir();
  auto r = test::RunCommand(Exe() + " synth " + (tmp / "a").string() + " --scene nope");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("unknown synthetic scene 'nope'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(tmp / "a"));
  r = test::RunCommand(Exe() + " synth " + (tmp / "a").string() + " --size 64by48");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--size"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(tmp / "a"));
}

}  // namespace
}  // namespace hdribr
