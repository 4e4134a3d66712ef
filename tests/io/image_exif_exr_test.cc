// Photos (OpenCV), EXIF (exiv2) and OpenEXR: round trips and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/exif.h"
#include "io/exr.h"
#include "io/image.h"
#include "io/io_test_util.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;
using test::ExpectInputError;

cv::Mat Pattern(int w, int h) {
  cv::Mat m(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      m.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uchar>(x * 4), static_cast<uchar>(y * 3),
                                        static_cast<uchar>((x + y) % 256));
    }
  }
  return m;
}

// ---------------------------------------------------------------- images

TEST(Image, PngRoundTripIsExactAndJpegClose) {
  const fs::path dir = test::TempDir();
  const cv::Mat img = Pattern(64, 40);
  WriteImage(dir / "a.png", img);
  const cv::Mat png = ReadImage(dir / "a.png");
  ASSERT_EQ(png.type(), CV_8UC3);
  EXPECT_EQ(cv::norm(png, img, cv::NORM_INF), 0.0);
  EXPECT_EQ(ReadImageSize(dir / "a.png"), cv::Size(64, 40));

  WriteImage(dir / "a.jpg", img, 98);
  const cv::Mat jpg = ReadImage(dir / "a.jpg");
  ASSERT_EQ(jpg.size(), img.size());
  EXPECT_LT(cv::norm(jpg, img, cv::NORM_L1) / img.total() / 3, 3.0);
  EXPECT_EQ(ReadImageSize(dir / "a.jpg"), cv::Size(64, 40));
  EXPECT_EQ(test::Snapshot(dir).size(), 2u) << "no temporary files left behind";
  // A format without a header exiv2 reads: the size comes from decoding.
  WriteImage(dir / "a.ppm", img);
  EXPECT_EQ(ReadImageSize(dir / "a.ppm"), cv::Size(64, 40));
}

TEST(Image, GrayPngIsReadAsBgr) {
  const fs::path dir = test::TempDir();
  cv::Mat gray(5, 7, CV_8UC1, cv::Scalar(77));
  WriteImage(dir / "g.png", gray);
  const cv::Mat img = ReadImage(dir / "g.png");
  ASSERT_EQ(img.type(), CV_8UC3);
  EXPECT_EQ(img.at<cv::Vec3b>(2, 3), cv::Vec3b(77, 77, 77));
}

TEST(Image, OrientationTagIsIgnoredLikeColmap) {
  const fs::path dir = test::TempDir();
  const cv::Mat img = Pattern(60, 20);
  WriteImage(dir / "r.jpg", img);
  ExifInfo exif;
  exif.orientation = 6;  // rotate 90 CW on display
  WriteExif(dir / "r.jpg", exif);
  ASSERT_EQ(ReadExif(dir / "r.jpg").orientation, 6);
  // OpenCV's default imread applies the tag; we must not.
  EXPECT_EQ(cv::imread((dir / "r.jpg").string()).size(), cv::Size(20, 60));
  EXPECT_EQ(ReadImage(dir / "r.jpg").size(), cv::Size(60, 20));
  EXPECT_EQ(ReadImageSize(dir / "r.jpg"), cv::Size(60, 20));
}

TEST(Image, CorruptAndMissingFilesAreInputErrors) {
  const fs::path dir = test::TempDir();
  ExpectInputError([&] { ReadImage(dir / "none.jpg"); }, {"none.jpg", "no such file"});
  ExpectInputError([&] { ReadImageSize(dir / "none.jpg"); }, {"none.jpg", "no such file"});
  WriteImage(dir / "t.jpg", Pattern(64, 64));
  fs::resize_file(dir / "t.jpg", fs::file_size(dir / "t.jpg") / 2);
  const auto before = test::Snapshot(dir);
  ExpectInputError([&] { ReadImage(dir / "t.jpg"); }, {"t.jpg", "corrupt JPEG"});
  ExpectInputError([&] { ReadImageSize(dir / "t.jpg"); }, {"t.jpg", "corrupt JPEG"});
  EXPECT_EQ(test::Snapshot(dir), before);
  std::ofstream(dir / "g.jpg") << "this is not a jpeg";
  ExpectInputError([&] { ReadImage(dir / "g.jpg"); }, {"g.jpg", "cannot decode"});
  ExpectInputError([&] { ReadImageSize(dir / "g.jpg"); }, {"g.jpg", "cannot decode"});
  std::ofstream(dir / "e.png");
  ExpectInputError([&] { ReadImage(dir / "e.png"); }, {"e.png", "empty file"});
}

TEST(Image, FailedWriteLeavesNothing) {
  const fs::path dir = test::TempDir();
  EXPECT_THROW(WriteImage(dir / "nodir" / "a.png", Pattern(4, 4)), InputError);
  EXPECT_ANY_THROW(WriteImage(dir / "a.unknownext", Pattern(4, 4)));
  EXPECT_TRUE(test::Snapshot(dir).empty());
}

// ---------------------------------------------------------------- EXIF

TEST(Exif, RoundTripOfEveryField) {
  const fs::path dir = test::TempDir();
  WriteImage(dir / "a.jpg", Pattern(16, 16));
  ExifInfo in;
  in.exposure.time_s = 1.0 / 125;
  in.exposure.iso = 400;
  in.exposure.f_number = 2.8;
  in.exposure.focal_mm = 35;
  in.orientation = 1;
  in.make = "hdribr";
  in.model = "synthetic camera";
  WriteExif(dir / "a.jpg", in);
  const ExifInfo out = ReadExif(dir / "a.jpg");
  ASSERT_TRUE(out.exposure.Complete());
  EXPECT_DOUBLE_EQ(*out.exposure.time_s, 1.0 / 125);
  EXPECT_DOUBLE_EQ(*out.exposure.iso, 400);
  EXPECT_DOUBLE_EQ(*out.exposure.f_number, 2.8);
  EXPECT_DOUBLE_EQ(*out.exposure.focal_mm, 35);
  EXPECT_EQ(out.orientation, 1);
  EXPECT_EQ(out.make, "hdribr");
  EXPECT_EQ(out.model, "synthetic camera");
  // Long exposures too, and the pixels survive.
  in.exposure.time_s = 2.5;
  WriteExif(dir / "a.jpg", in);
  EXPECT_DOUBLE_EQ(*ReadExif(dir / "a.jpg").exposure.time_s, 2.5);
  EXPECT_EQ(ReadImage(dir / "a.jpg").size(), cv::Size(16, 16));
}

TEST(Exif, MissingExifGivesEmptyFieldsAndBadFilesErrors) {
  const fs::path dir = test::TempDir();
  WriteImage(dir / "plain.jpg", Pattern(8, 8));
  const ExifInfo e = ReadExif(dir / "plain.jpg");
  EXPECT_FALSE(e.exposure.time_s);
  EXPECT_FALSE(e.exposure.iso);
  EXPECT_FALSE(e.exposure.f_number);
  EXPECT_FALSE(e.exposure.focal_mm);
  EXPECT_FALSE(e.orientation);
  EXPECT_TRUE(e.make.empty());
  EXPECT_DOUBLE_EQ(e.exposure.Relative(), 1.0);
  ExifInfo partial;
  partial.exposure.iso = 200;
  WriteExif(dir / "plain.jpg", partial);
  const ExifInfo p = ReadExif(dir / "plain.jpg");
  EXPECT_EQ(p.exposure.iso, 200);
  EXPECT_FALSE(p.exposure.time_s);
  EXPECT_FALSE(p.exposure.Complete());

  ExpectInputError([&] { ReadExif(dir / "none.jpg"); }, {"none.jpg", "no such file"});
  std::ofstream(dir / "junk.jpg") << "junk junk junk";
  ExpectInputError([&] { ReadExif(dir / "junk.jpg"); }, {"junk.jpg", "cannot read EXIF"});
  ExpectInputError([&] { WriteExif(dir / "junk.jpg", partial); }, {"junk.jpg"});
}

// ---------------------------------------------------------------- EXR

cv::Mat HdrPattern(int w, int h, int channels) {
  cv::Mat m(h, w, channels == 3 ? CV_32FC3 : CV_32FC1);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < channels; ++c) {
        m.ptr<float>(y)[x * channels + c] =
            std::exp2(static_cast<float>(x - w / 2) / 3.0f) * (1.0f + c) + 0.001f * y;
      }
    }
  }
  return m;
}

TEST(Exr, RgbAndSingleChannelRoundTripsInHalfAndFloat) {
  const fs::path dir = test::TempDir();
  for (int channels : {3, 1}) {
    const cv::Mat img = HdrPattern(37, 23, channels);
    WriteExr(dir / "f.exr", img, ExrPixel::kFloat, "Z");
    const cv::Mat f = ReadExr(dir / "f.exr");
    ASSERT_EQ(f.type(), img.type());
    EXPECT_EQ(cv::norm(f, img, cv::NORM_INF), 0.0);

    WriteExr(dir / "h.exr", img, ExrPixel::kHalf);
    const cv::Mat h = ReadExr(dir / "h.exr");
    ASSERT_EQ(h.type(), img.type());
    cv::Mat rel;
    cv::absdiff(h, img, rel);
    rel = rel / img;
    double max_rel = 0;
    cv::minMaxLoc(rel.reshape(1), nullptr, &max_rel);
    EXPECT_LT(max_rel, 1.0 / 1024) << "half keeps 11 significant bits";
    EXPECT_LT(fs::file_size(dir / "h.exr"), fs::file_size(dir / "f.exr"));
  }
  // BGR in memory is R,G,B in the file: blue stays blue.
  cv::Mat blue(2, 2, CV_32FC3, cv::Scalar(5, 0, 0));
  WriteExr(dir / "b.exr", blue);
  EXPECT_EQ(ReadExr(dir / "b.exr").at<cv::Vec3f>(1, 1), cv::Vec3f(5, 0, 0));
  EXPECT_EQ(test::Snapshot(dir).size(), 3u) << "no temporary files left behind";
}

TEST(Exr, BadFilesAreInputErrors) {
  const fs::path dir = test::TempDir();
  ExpectInputError([&] { ReadExr(dir / "none.exr"); }, {"none.exr", "no such file"});
  std::ofstream(dir / "junk.exr") << "not an exr";
  ExpectInputError([&] { ReadExr(dir / "junk.exr"); }, {"junk.exr", "cannot read EXR"});
  WriteExr(dir / "t.exr", HdrPattern(64, 64, 3), ExrPixel::kFloat);
  fs::resize_file(dir / "t.exr", fs::file_size(dir / "t.exr") / 2);
  ExpectInputError([&] { ReadExr(dir / "t.exr"); }, {"t.exr", "cannot read EXR"});
  EXPECT_THROW(WriteExr(dir / "u8.exr", cv::Mat(2, 2, CV_8UC3)), UsageError);
  EXPECT_THROW(WriteExr(dir / "nodir" / "x.exr", HdrPattern(4, 4, 1)), InputError);
  EXPECT_EQ(test::Snapshot(dir).size(), 2u);
}

}  // namespace
}  // namespace hdribr
