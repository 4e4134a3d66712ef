// Shared helpers for the io tests: a small COLMAP model with consistent tracks, model comparison
// and folder snapshots (to prove that failing reads leave inputs untouched).
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "io/colmap_model.h"

namespace hdribr::test {

// 2 cameras (ids 4 and 9), 3 images (ids 3, 8, 20), 5 points (ids 7..) with tracks whose
// point2D entries refer back to them, plus unmatched 2D points.
ColmapModel MakeColmapModel();
// EXPECTs every field equal; quaternions within rot_tol (COLMAP may renormalise), else exact.
void ExpectModelsEqual(const ColmapModel& a, const ColmapModel& b, double rot_tol = 0.0);
// File name -> contents of every file under dir (recursive).
std::map<std::string, std::string> Snapshot(const std::filesystem::path& dir);

}  // namespace hdribr::test
