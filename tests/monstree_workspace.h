// The monstree workspace that the reconstruct and eval tests read: `hdribr reconstruct` of
// ../shared/datasets/monstree/images at reduced sizes, made once per CTest run by the setup
// of the shared fixture MonstreeWorkspace (test_util.h; TEST(Fixture, MonstreeWorkspace) in
// tests/frontend/reconstruct_monstree_test.cc), which also checks that the photo folder is left
// untouched. Header-only: the including test defines HDRIBR_EXE (hdribr_test).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>

#include "test_util.h"

namespace hdribr::test {

inline constexpr char kMonstreeFixture[] = "MonstreeWorkspace";

// The files of a folder and their modification times.
inline std::map<std::string, std::filesystem::file_time_type> FileTimes(
    const std::filesystem::path& folder) {
  std::map<std::string, std::filesystem::file_time_type> times;
  for (const auto& e : std::filesystem::directory_iterator(folder)) {
    times[e.path().string()] = e.last_write_time();
  }
  return times;
}

// Reconstructs the photos of the dataset folder `monstree` into dir/ws (the command's output in
// dir/reconstruct.log), and checks that the photo folder is untouched: the same files with the
// same modification times.
inline void MakeMonstreeWorkspace(const std::filesystem::path& monstree,
                                  const std::filesystem::path& dir) {
  const std::filesystem::path photos = monstree / "images";
  const auto before = FileTimes(photos);
  const auto r = RunCommand(std::string(HDRIBR_EXE) + " reconstruct " + photos.string() + " " +
                            (dir / "ws").string() + " --image-size 800 --dense-size 300 2>&1");
  std::ofstream(dir / "reconstruct.log") << r.output;
  std::cout << r.output.substr(r.output.size() > 3000 ? r.output.size() - 3000 : 0) << "\n";
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(before, FileTimes(photos)) << "reconstruct changed the photo folder";
}

// The workspace (made first when absent); `monstree` is the dataset's folder.
inline std::filesystem::path MonstreeWorkspace(const std::filesystem::path& monstree) {
  const auto make = [&](const std::filesystem::path& dir) { MakeMonstreeWorkspace(monstree, dir); };
  return SharedFixture(kMonstreeFixture, make) / "ws";
}

}  // namespace hdribr::test
