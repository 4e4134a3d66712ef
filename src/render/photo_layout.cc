#include "render/photo_layout.h"

namespace hdribr::render {

size_t PhotoLayout::LayerBytes() const {
  const size_t texel = is_float ? 8 : 4;
  size_t bytes = 0;
  for (int l = 0; l < levels; ++l) {
    bytes += static_cast<size_t>(std::max(1, width >> l)) *
             static_cast<size_t>(std::max(1, height >> l)) * texel;
  }
  return bytes;
}

}  // namespace hdribr::render
