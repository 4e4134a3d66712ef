// The monstree photos: 19 of 23 carry EXIF Orientation 6 (rotate 90 CW). COLMAP ignores the tag,
// so ReadImage must return the stored landscape pixels, not the displayed portrait ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "io/atomic_file.h"
#include "io/exif.h"
#include "io/image.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;

TEST(Monstree, RotatedPhotosAreReadAsStoredLikeColmap) {
  HDRIBR_REQUIRE_DATASET(dataset, "monstree");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dataset / "images")) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_EQ(files.size(), 23u);
  int rotated = 0;
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    const ExifInfo exif = ReadExif(f);
    ASSERT_TRUE(exif.orientation.has_value());
    ASSERT_TRUE(exif.exposure.time_s && exif.exposure.iso && exif.exposure.f_number);
    EXPECT_GT(*exif.exposure.time_s, 0.0);
    EXPECT_LT(*exif.exposure.time_s, 1.0);
    EXPECT_GE(*exif.exposure.iso, 10.0);  // phone camera: ISO 20..40 here
    EXPECT_LE(*exif.exposure.iso, 102400.0);
    EXPECT_GT(*exif.exposure.f_number, 1.0);
    EXPECT_FALSE(exif.make.empty());
    if (f.filename() == "IMG_1025.JPG") {
      std::printf("IMG_1025.JPG: %s %s, 1/%.1f s, ISO %.0f, f/%.2f, %.2f mm, orientation %d\n",
                  exif.make.c_str(), exif.model.c_str(), 1.0 / *exif.exposure.time_s,
                  *exif.exposure.iso, *exif.exposure.f_number, exif.exposure.focal_mm.value_or(0),
                  *exif.orientation);
      // Known values of this iPhone 7 photo (f/1.8, 3.99 mm lens).
      EXPECT_EQ(exif.make, "Apple");
      EXPECT_EQ(exif.model, "iPhone 7");
      EXPECT_DOUBLE_EQ(*exif.exposure.time_s, 1.0 / 60);
      EXPECT_DOUBLE_EQ(*exif.exposure.iso, 20);
      EXPECT_DOUBLE_EQ(*exif.exposure.f_number, 1.8);
    }
    const cv::Mat ours = ReadImage(f);
    ASSERT_EQ(ours.type(), CV_8UC3);
    EXPECT_EQ(ReadImageSize(f), ours.size());
    if (*exif.orientation != 6) {
      EXPECT_EQ(*exif.orientation, 1);
      continue;
    }
    ++rotated;
    // Stored pixels: landscape 1600x1200; a viewer applying the tag shows 1200x1600.
    EXPECT_EQ(ours.size(), cv::Size(1600, 1200));
    const std::string bytes = ReadFileToString(f);
    const cv::Mat buf(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data()));
    const cv::Mat raw = cv::imdecode(buf, cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION);
    const cv::Mat displayed = cv::imdecode(buf, cv::IMREAD_COLOR);
    EXPECT_EQ(displayed.size(), cv::Size(1200, 1600));
    EXPECT_EQ(cv::norm(ours, raw, cv::NORM_INF), 0.0) << "identical to the un-rotated decode";
  }
  EXPECT_EQ(rotated, 19);
}

}  // namespace
}  // namespace hdribr
