// libFuzzer target: the binary COLMAP reader must answer any bytes with a model or InputError.
// Input layout: two little-endian uint16 lengths (cameras.bin, images.bin), then the three files'
// bytes back to back (points3D.bin takes the rest).
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "io/colmap_model.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 4) return 0;
  const std::string all(reinterpret_cast<const char*>(data) + 4, size - 4);
  const std::size_t a = std::min<std::size_t>(data[0] | (data[1] << 8), all.size());
  const std::size_t b = std::min<std::size_t>(data[2] | (data[3] << 8), all.size() - a);
  try {
    const hdribr::ColmapModel m = hdribr::ParseColmapModelBinary(all.substr(0, a), all.substr(a, b),
                                                                 all.substr(a + b), "fuzz");
    // A model that parsed must be self-consistent.
    for (const auto& [id, image] : m.images) {
      if (!m.cameras.count(image.camera_id)) __builtin_trap();
    }
  } catch (const hdribr::InputError&) {
  }
  return 0;
}
