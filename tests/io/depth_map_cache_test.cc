// The depth-map cache files (io/depth_map_cache.h): exact round trip, every kind of bad file
// refused with a message naming it, atomic writes and the pruning of old keys.
#include "io/depth_map_cache.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"
#include "test_util.h"

namespace hdribr {
namespace {
namespace fs = std::filesystem;

constexpr std::uint64_t kKey = 0x0123456789abcdefULL;

// Two layers of different sizes with awkward values (signed zero, subnormal, huge, NaN).
std::vector<cv::Mat> SampleLayers() {
  cv::Mat a(3, 5, CV_32FC1), b(4, 2, CV_32FC1);
  for (int i = 0; i < static_cast<int>(a.total()); ++i) a.at<float>(i) = 0.25f * i + 1e-3f;
  for (int i = 0; i < static_cast<int>(b.total()); ++i) b.at<float>(i) = 7.0f - 1.5f * i;
  a.at<float>(0, 0) = -0.0f;
  a.at<float>(1, 1) = std::numeric_limits<float>::denorm_min();
  a.at<float>(2, 4) = std::numeric_limits<float>::max();
  b.at<float>(3, 1) = std::numeric_limits<float>::quiet_NaN();
  return {a, b};
}

std::vector<cv::Size> SizesOf(const std::vector<cv::Mat>& layers) {
  std::vector<cv::Size> sizes;
  for (const cv::Mat& m : layers) sizes.push_back(m.size());
  return sizes;
}

bool SameBits(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && a.isContinuous() && b.isContinuous() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

std::string ReadAll(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void WriteAll(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

// The message of the InputError that reading `file` throws, or "" when it reads.
std::string ReadProblem(const fs::path& file, std::uint64_t key,
                        const std::vector<cv::Size>& sizes) {
  try {
    ReadDepthMapCache(file, key, sizes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(DepthMapCacheTest, FolderAndFileNames) {
  EXPECT_EQ(DepthMapCacheDir("/ws"), fs::path("/ws/cache/depth_maps"));
  EXPECT_EQ(DepthMapCacheFile("/c", kKey), fs::path("/c/0123456789abcdef.bin"));
  EXPECT_EQ(DepthMapCacheFile("/c", 1), fs::path("/c/0000000000000001.bin"));
}

TEST(DepthMapCacheTest, RoundTripIsBitExact) {
  const fs::path dir = test::TempDir() / "new" / "folder";  // created by the write
  const fs::path file = DepthMapCacheFile(dir, kKey);
  const std::vector<cv::Mat> layers = SampleLayers();
  WriteDepthMapCache(file, kKey, layers);
  // Header, size table, floats, checksum: nothing else.
  EXPECT_EQ(fs::file_size(file), 24u + 2 * 8 + (15 + 8) * 4 + 8);
  const std::vector<cv::Mat> back = ReadDepthMapCache(file, kKey, SizesOf(layers));
  ASSERT_EQ(back.size(), 2u);
  for (size_t i = 0; i < 2; ++i) EXPECT_TRUE(SameBits(back[i], layers[i])) << "layer " << i;
  // A region of a larger image (not continuous) is written as its pixels.
  cv::Mat big(6, 8, CV_32FC1, cv::Scalar(3.0f));
  const cv::Mat roi = big(cv::Rect(1, 2, 5, 3));
  layers[0].copyTo(roi);
  WriteDepthMapCache(file, kKey, {roi, layers[1]});
  EXPECT_TRUE(SameBits(ReadDepthMapCache(file, kKey, SizesOf(layers))[0], layers[0]));
  // No temporary file is left beside it.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(DepthMapCacheTest, BadFilesAreRefusedNamingTheProblem) {
  const fs::path dir = test::TempDir();
  const fs::path file = dir / "a.bin";
  const std::vector<cv::Mat> layers = SampleLayers();
  const std::vector<cv::Size> sizes = SizesOf(layers);
  WriteDepthMapCache(file, kKey, layers);
  const std::string good = ReadAll(file);
  ASSERT_EQ(ReadProblem(file, kKey, sizes), "");

  EXPECT_NE(ReadProblem(dir / "none.bin", kKey, sizes).find("no such file"), std::string::npos);
  EXPECT_NE(ReadProblem(file, kKey + 1, sizes).find("holds key 0123456789abcdef"),
            std::string::npos);
  EXPECT_NE(ReadProblem(file, kKey, {sizes[0]}).find("2 depth maps, expected 1"),
            std::string::npos);
  EXPECT_NE(ReadProblem(file, kKey, {sizes[0], cv::Size(2, 5)}).find("depth map 1 is 2x4"),
            std::string::npos);
  // Cut anywhere: in the magic, the header, the size table, the floats, the checksum.
  for (size_t cut : {size_t{0}, size_t{5}, size_t{20}, size_t{30}, size_t{60}, good.size() - 1}) {
    WriteAll(file, good.substr(0, cut));
    const std::string problem = ReadProblem(file, kKey, sizes);
    EXPECT_TRUE(problem.find("truncated") != std::string::npos ||
                problem.find("not a depth map cache file") != std::string::npos)
        << "cut at " << cut << ": " << problem;
    EXPECT_NE(problem.find(file.string()), std::string::npos) << problem;
  }
  WriteAll(file, good + "x");
  EXPECT_NE(ReadProblem(file, kKey, sizes).find("too long"), std::string::npos);
  std::string bad = good;
  bad[1] = 'X';
  WriteAll(file, bad);
  EXPECT_NE(ReadProblem(file, kKey, sizes).find("not a depth map cache file"), std::string::npos);
  bad = good;
  bad[8] = 2;  // version
  WriteAll(file, bad);
  EXPECT_NE(ReadProblem(file, kKey, sizes).find("format version 2, expected 1"), std::string::npos);
  bad = good;
  bad[60] = static_cast<char>(bad[60] ^ 0x10);  // one bit of a float
  WriteAll(file, bad);
  EXPECT_NE(ReadProblem(file, kKey, sizes).find("checksum mismatch"), std::string::npos);
  bad = good;
  bad.back() = static_cast<char>(bad.back() ^ 1);  // the checksum itself
  WriteAll(file, bad);
  EXPECT_NE(ReadProblem(file, kKey, sizes).find("checksum mismatch"), std::string::npos);
}

TEST(DepthMapCacheTest, UnwritableFolderThrowsAndLeavesNothing) {
  const fs::path dir = test::TempDir();
  WriteAll(dir / "blocker", "a file where the cache folder would be");
  const fs::path file = DepthMapCacheFile(dir / "blocker" / "depth_maps", kKey);
  EXPECT_THROW(WriteDepthMapCache(file, kKey, SampleLayers()), InputError);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(DepthMapCacheTest, PruneKeepsTheMostRecentlyUsed) {
  const fs::path dir = test::TempDir();
  const auto now = fs::file_time_type::clock::now();
  const std::vector<cv::Mat> layers = SampleLayers();
  // Keys 1..5, key k used k minutes ago: 1, 2 and 3 are the most recent.
  for (std::uint64_t k = 1; k <= 5; ++k) {
    WriteDepthMapCache(DepthMapCacheFile(dir, k), k, layers);
    fs::last_write_time(DepthMapCacheFile(dir, k), now - std::chrono::minutes(k));
  }
  // Reading key 5 marks it used: it stays, key 3 goes.
  ASSERT_TRUE(TouchDepthMapCache(DepthMapCacheFile(dir, 5)));
  // Leftovers of interrupted writes: an old one goes, a fresh one (a write under way) stays.
  const fs::path old_tmp = dir / ".0000000000000009.tmp123_0.bin";
  const fs::path new_tmp = dir / ".0000000000000008.tmp124_0.bin";
  WriteAll(old_tmp, "partial");
  WriteAll(new_tmp, "partial");
  fs::last_write_time(old_tmp, now - std::chrono::hours(2));
  // Other files are never touched, whatever their age.
  WriteAll(dir / "notes.txt", "mine");
  WriteAll(dir / "0123.bin", "not a key");
  fs::last_write_time(dir / "notes.txt", now - std::chrono::hours(48));

  EXPECT_EQ(PruneDepthMapCache(dir, 3), 3);
  for (std::uint64_t k : {1, 2, 5}) EXPECT_TRUE(fs::exists(DepthMapCacheFile(dir, k))) << k;
  for (std::uint64_t k : {3, 4}) EXPECT_FALSE(fs::exists(DepthMapCacheFile(dir, k))) << k;
  EXPECT_FALSE(fs::exists(old_tmp));
  EXPECT_TRUE(fs::exists(new_tmp));
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
  EXPECT_TRUE(fs::exists(dir / "0123.bin"));
  EXPECT_EQ(PruneDepthMapCache(dir, 3), 0);
  EXPECT_EQ(PruneDepthMapCache(dir / "absent"), 0);  // never throws
}

}  // namespace
}  // namespace hdribr
