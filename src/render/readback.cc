#include "render/readback.h"

#include "core/error.h"

namespace hdribr::render {

cv::Mat ReadTextureR32F(const gl::Texture& texture) {
  cv::Mat m(texture.height(), texture.width(), CV_32FC1);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(texture.id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(m.total() * 4), m.data);
  return m;
}

cv::Mat ReadTextureLayerR32F(const gl::Texture& texture, int layer) {
  HDRIBR_CHECK(layer >= 0 && layer < texture.layers());
  cv::Mat m(texture.height(), texture.width(), CV_32FC1);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureSubImage(texture.id(), 0, 0, 0, layer, texture.width(), texture.height(), 1, GL_RED,
                       GL_FLOAT, static_cast<GLsizei>(m.total() * 4), m.data);
  return m;
}

DepthImages ReadDepthTarget(const DepthTarget& target) {
  DepthImages out;
  out.depth = ReadTextureR32F(target.depth);
  out.normal.create(target.height(), target.width(), CV_32FC3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(target.normal.id(), 0, GL_RGB, GL_FLOAT,
                    static_cast<GLsizei>(out.normal.total() * 12), out.normal.data);
  out.valid.create(target.height(), target.width(), CV_8UC1);
  glGetTextureImage(target.valid.id(), 0, GL_RED, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(out.valid.total()), out.valid.data);
  return out;
}

}  // namespace hdribr::render
