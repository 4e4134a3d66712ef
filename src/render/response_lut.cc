#include "render/response_lut.h"

#include <vector>

#include "core/error.h"

namespace hdribr::render {

gl::Texture MakeResponseLut(const ResponseCurve& response) {
  if (!response.IsValid()) throw UsageError("the response curve is not valid");
  std::vector<float> lut(256 * 3);
  for (int z = 0; z < 256; ++z) {
    for (int c = 0; c < 3; ++c) {  // BGR curve -> RGB texel
      lut[static_cast<size_t>(z * 3 + c)] = static_cast<float>(
          response.log_inverse[static_cast<size_t>(2 - c)][static_cast<size_t>(z)]);
    }
  }
  gl::Texture texture = gl::Texture::Create2D(GL_RGB32F, 256, 1);
  glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(texture.id(), 0, 0, 0, 256, 1, GL_RGB, GL_FLOAT, lut.data());
  return texture;
}

}  // namespace hdribr::render
