// Shared helpers for the io tests: a small COLMAP model with consistent tracks, model comparison
// and folder snapshots (to prove that failing reads leave inputs untouched).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <initializer_list>
#include <map>
#include <string>

#include "core/error.h"
#include "io/colmap_model.h"

namespace hdribr::test {

// 2 cameras (ids 4 and 9), 3 images (ids 3, 8, 20), 5 points (ids 7..) with tracks whose
// point2D entries refer back to them, plus unmatched 2D points.
ColmapModel MakeColmapModel();
// EXPECTs every field equal; quaternions within rot_tol (COLMAP may renormalise), else exact.
void ExpectModelsEqual(const ColmapModel& a, const ColmapModel& b, double rot_tol = 0.0);
// File name -> contents of every file under dir (recursive).
std::map<std::string, std::string> Snapshot(const std::filesystem::path& dir);

// Runs fn and EXPECTs an InputError of one line whose message contains every needle.
template <typename Fn>
void ExpectInputError(Fn fn, std::initializer_list<std::string> needles) {
  try {
    fn();
    ADD_FAILURE() << "no InputError; expected one containing '" << *needles.begin() << "'";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const auto& n : needles) EXPECT_NE(msg.find(n), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
  }
}

}  // namespace hdribr::test
