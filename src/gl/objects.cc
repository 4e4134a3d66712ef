#include "gl/objects.h"

#include <stdexcept>
#include <vector>

namespace hdribr::gl {

Buffer::Buffer(size_t bytes, const void* data, GLbitfield flags) {
  glCreateBuffers(1, &id_);
  // Zero-sized storage is an error in GL: keep one byte for empty buffers.
  glNamedBufferStorage(id_, static_cast<GLsizeiptr>(bytes == 0 ? 1 : bytes),
                       bytes == 0 ? nullptr : data, flags);
  size_ = bytes;
}

Texture Texture::Create2D(GLenum internal_format, int width, int height, int levels) {
  Texture t;
  glCreateTextures(GL_TEXTURE_2D, 1, &t.id_);
  glTextureStorage2D(t.id_, levels, internal_format, width, height);
  glTextureParameteri(t.id_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.id_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(t.id_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  t.target_ = GL_TEXTURE_2D;
  t.format_ = internal_format;
  t.width_ = width;
  t.height_ = height;
  t.layers_ = 1;
  return t;
}

Texture Texture::Create2DArray(GLenum internal_format, int width, int height, int layers) {
  Texture t;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t.id_);
  glTextureStorage3D(t.id_, 1, internal_format, width, height, layers);
  glTextureParameteri(t.id_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.id_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(t.id_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  t.target_ = GL_TEXTURE_2D_ARRAY;
  t.format_ = internal_format;
  t.width_ = width;
  t.height_ = height;
  t.layers_ = layers;
  return t;
}

Texture Texture::LayerView(const Texture& array, int layer) {
  Texture t;
  glGenTextures(1, &t.id_);  // views need a name never bound (not glCreateTextures)
  glTextureView(t.id_, GL_TEXTURE_2D, array.id(), array.format(), 0, 1, static_cast<GLuint>(layer),
                1);
  glTextureParameteri(t.id_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.id_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  t.target_ = GL_TEXTURE_2D;
  t.format_ = array.format();
  t.width_ = array.width();
  t.height_ = array.height();
  t.layers_ = 1;
  return t;
}

Framebuffer Framebuffer::Create() {
  Framebuffer f;
  glCreateFramebuffers(1, &f.id_);
  return f;
}

void Framebuffer::AttachColor(int index, const Texture& texture, int level) {
  glNamedFramebufferTexture(id_, GL_COLOR_ATTACHMENT0 + index, texture.id(), level);
}

void Framebuffer::AttachColorLayer(int index, const Texture& texture, int layer) {
  glNamedFramebufferTextureLayer(id_, GL_COLOR_ATTACHMENT0 + index, texture.id(), 0, layer);
}

void Framebuffer::AttachDepth(const Texture& texture) {
  glNamedFramebufferTexture(id_, GL_DEPTH_ATTACHMENT, texture.id(), 0);
}

void Framebuffer::SetDrawBuffers(int count) {
  std::vector<GLenum> bufs;
  for (int i = 0; i < count; ++i) bufs.push_back(GL_COLOR_ATTACHMENT0 + i);
  glNamedFramebufferDrawBuffers(id_, count, bufs.data());
}

void Framebuffer::CheckComplete() const {
  const GLenum status = glCheckNamedFramebufferStatus(id_, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error("framebuffer incomplete, status 0x" + std::to_string(status));
  }
}

void Framebuffer::Bind(int width, int height) const {
  glBindFramebuffer(GL_FRAMEBUFFER, id_);
  glViewport(0, 0, width, height);
}

VertexArray VertexArray::Create() {
  VertexArray v;
  glCreateVertexArrays(1, &v.id_);
  return v;
}

TimerQuery TimerQuery::Create() {
  TimerQuery q;
  glCreateQueries(GL_TIME_ELAPSED, 1, &q.id_);
  return q;
}

double TimerQuery::ElapsedMs() const {
  GLuint64 ns = 0;
  glGetQueryObjectui64v(id_, GL_QUERY_RESULT, &ns);
  return static_cast<double>(ns) * 1e-6;
}

TimestampQuery TimestampQuery::Create() {
  TimestampQuery q;
  glCreateQueries(GL_TIMESTAMP, 1, &q.id_);
  return q;
}

GLuint64 TimestampQuery::ResultNs() const {
  GLuint64 ns = 0;
  glGetQueryObjectui64v(id_, GL_QUERY_RESULT, &ns);
  return ns;
}

bool TimestampQuery::Available() const {
  GLuint available = GL_FALSE;
  glGetQueryObjectuiv(id_, GL_QUERY_RESULT_AVAILABLE, &available);
  return available == GL_TRUE;
}

}  // namespace hdribr::gl
