// PLY point clouds through PCL: binary or ASCII, with optional normals, colours and radius.
#pragma once

#include <filesystem>

#include "core/point_cloud.h"

namespace hdribr {

// Reads x,y,z and, when present, nx,ny,nz / red,green,blue / radius (also "scale"). Throws
// InputError naming the file for a missing, empty (no vertices), truncated or corrupt file.
PointCloud ReadPly(const std::filesystem::path& path);
// Parses PLY bytes; `name` only labels errors (used by the fuzzer).
PointCloud ParsePly(const std::string& bytes, const std::filesystem::path& name);
// Writes the attributes the cloud has, atomically.
void WritePly(const std::filesystem::path& path, const PointCloud& cloud, bool binary = true);

}  // namespace hdribr
