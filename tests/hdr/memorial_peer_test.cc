// hdribr's Debevec calibration + merge against OpenCV's (photo module) on Debevec's Memorial
// Church stack.
#include <gtest/gtest.h>

#include <cmath>

#include "hdr/debevec.h"
#include "hdr/opencv_reference.h"
#include "hdr/synthetic_stack.h"
#include "io/image.h"
#include "test_util.h"

namespace hdribr {
namespace {

ExposureStack LoadMemorial(const std::filesystem::path& dir) {
  ExposureStack stack;
  stack.times = ReadShutterTimes(dir / "shutter_times.txt").times;
  for (int i = 61; i <= 76; ++i) {
    stack.images.push_back(ReadImage(dir / ("memorial00" + std::to_string(i) + ".png")));
  }
  return stack;
}

TEST(MemorialPeer, RadianceMatchesOpenCv) {
  HDRIBR_REQUIRE_DATASET(dir, "memorial");
  const ExposureStack stack = LoadMemorial(dir);
  ASSERT_EQ(stack.images.size(), 16u);
  ASSERT_EQ(stack.times.size(), 16u);
  EXPECT_DOUBLE_EQ(stack.times.front(), 32.0);

  const ResponseCurve ours_curve = CalibrateDebevec(stack);
  const cv::Mat ours = MergeDebevec(stack, ours_curve);
  const cv::Mat cv_response = OpenCvCalibrateDebevec(stack.images, stack.times);
  const cv::Mat theirs = OpenCvMergeDebevec(stack.images, stack.times, cv_response);
  ASSERT_EQ(ours.size(), theirs.size());
  EXPECT_TRUE(cv::checkRange(ours, true, nullptr, 0.0, 1e38));

  const double err = test::MedianAbsLogRatio(ours, theirs);
  // The same merge with OpenCV's curve isolates the calibration's share of the difference.
  const cv::Mat ours_with_cv_curve = MergeDebevec(stack, [&] {
    ResponseCurve c = ResponseFromOpenCv(cv_response);
    for (auto& g : c.log_inverse) {
      for (size_t z = 1; z < g.size(); ++z) g[z] = std::max(g[z], g[z - 1]);
    }
    return c;
  }());
  const double err_merge_only = test::MedianAbsLogRatio(ours_with_cv_curve, theirs);
  std::printf("memorial: median |log ratio| vs OpenCV %.4f (with OpenCV's curve: %.4f)\n", err,
              err_merge_only);
  RecordProperty("median_abs_log_ratio", std::to_string(err));
  // docs/decisions/0005 and 0008: 0.043 with the defaults, 0.023 with OpenCV's curve (the
  // remainder is the curve); the plain method gives 0.070, a single trim round 0.048.
  EXPECT_LE(err, 0.045);
  EXPECT_LE(err_merge_only, 0.025);
  EXPECT_LT(err_merge_only, err);
}

}  // namespace
}  // namespace hdribr
