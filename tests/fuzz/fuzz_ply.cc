// libFuzzer target: the PLY reader (our header check, then PCL) must answer any bytes with a
// point cloud or InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "io/ply.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const hdribr::PointCloud cloud = hdribr::ParsePly(bytes, "fuzz.ply");
    if (cloud.empty() || !cloud.IsConsistent()) __builtin_trap();
  } catch (const hdribr::InputError&) {
  }
  return 0;
}
