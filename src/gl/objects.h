// Move-only RAII wrappers for OpenGL objects (GL 4.5 direct state access): copy deleted,
// noexcept move, an empty state (id() == 0), id().
#pragma once

#include <epoxy/gl.h>

#include <cstddef>
#include <string>
#include <utility>

namespace hdribr::gl {

// Base of every wrapper: owns one GL name, released by Traits::Delete.
template <typename Traits>
class Object {
 public:
  Object() = default;
  ~Object() { Reset(); }
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;
  Object(Object&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  Object& operator=(Object&& other) noexcept {
    if (this != &other) {
      Reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  GLuint id() const { return id_; }
  bool empty() const { return id_ == 0; }
  explicit operator bool() const { return id_ != 0; }
  // Deletes the GL object; the wrapper becomes empty.
  void Reset() {
    if (id_ != 0) Traits::Delete(id_);
    id_ = 0;
  }

 protected:
  explicit Object(GLuint id) : id_(id) {}
  GLuint id_ = 0;
};

struct BufferTraits {
  static void Delete(GLuint id) { glDeleteBuffers(1, &id); }
};
struct TextureTraits {
  static void Delete(GLuint id) { glDeleteTextures(1, &id); }
};
struct FramebufferTraits {
  static void Delete(GLuint id) { glDeleteFramebuffers(1, &id); }
};
struct VertexArrayTraits {
  static void Delete(GLuint id) { glDeleteVertexArrays(1, &id); }
};
struct ShaderTraits {
  static void Delete(GLuint id) { glDeleteShader(id); }
};
struct ProgramTraits {
  static void Delete(GLuint id) { glDeleteProgram(id); }
};
struct QueryTraits {
  static void Delete(GLuint id) { glDeleteQueries(1, &id); }
};

// Immutable-storage buffer (glNamedBufferStorage).
class Buffer : public Object<BufferTraits> {
 public:
  Buffer() = default;
  // `data` may be null; flags as for glNamedBufferStorage (GL_DYNAMIC_STORAGE_BIT, ...).
  Buffer(size_t bytes, const void* data, GLbitfield flags = 0);
  size_t size() const { return size_; }

 private:
  size_t size_ = 0;
};

// 2D texture or 2D texture array with immutable storage (glTextureStorage2D/3D).
class Texture : public Object<TextureTraits> {
 public:
  Texture() = default;
  // A 2D texture (levels >= 1) with nearest filtering and clamp-to-edge.
  static Texture Create2D(GLenum internal_format, int width, int height, int levels = 1);
  // A 2D array texture with `layers` layers.
  static Texture Create2DArray(GLenum internal_format, int width, int height, int layers);
  // A 2D view (glTextureView) of level 0 of one layer of a 2D array texture: shares its
  // storage; usable as an image, a sampler or a framebuffer attachment.
  static Texture LayerView(const Texture& array, int layer);
  GLenum target() const { return target_; }
  GLenum format() const { return format_; }
  int width() const { return width_; }
  int height() const { return height_; }
  int layers() const { return layers_; }

 private:
  GLenum target_ = 0;
  GLenum format_ = 0;
  int width_ = 0, height_ = 0, layers_ = 0;
};

// Framebuffer object; throws std::runtime_error from CheckComplete() when incomplete.
class Framebuffer : public Object<FramebufferTraits> {
 public:
  static Framebuffer Create();
  // Attaches level 0 of `texture` (2D) to GL_COLOR_ATTACHMENT0 + index.
  void AttachColor(int index, const Texture& texture, int level = 0);
  // Attaches one layer of a 2D array texture.
  void AttachColorLayer(int index, const Texture& texture, int layer);
  void AttachDepth(const Texture& texture);
  // glNamedFramebufferDrawBuffers with attachments 0..count-1.
  void SetDrawBuffers(int count);
  void CheckComplete() const;
  // Binds for drawing and sets the viewport to width x height.
  void Bind(int width, int height) const;
};

class VertexArray : public Object<VertexArrayTraits> {
 public:
  static VertexArray Create();
};

// One shader stage; compile errors are reported by the shader library (shader_library.h).
class Shader : public Object<ShaderTraits> {
 public:
  Shader() = default;
  explicit Shader(GLenum stage) : Object(glCreateShader(stage)) {}
};

class Program : public Object<ProgramTraits> {
 public:
  Program() = default;
  static Program Create() {
    Program p;
    p.id_ = glCreateProgram();
    return p;
  }
  // Uniform location by name (-1 when absent or optimised away).
  GLint Uniform(const char* name) const { return glGetUniformLocation(id_, name); }
  void Use() const { glUseProgram(id_); }
};

// GL_TIME_ELAPSED query: Begin(), End(), then ElapsedMs() (waits for the result).
class TimerQuery : public Object<QueryTraits> {
 public:
  static TimerQuery Create();
  void Begin() const { glBeginQuery(GL_TIME_ELAPSED, id_); }
  void End() const { glEndQuery(GL_TIME_ELAPSED); }
  double ElapsedMs() const;
};

// GL_TIMESTAMP query: Stamp() records the GPU time when the commands before it are done;
// ResultNs() waits for it, Available() tells without waiting whether it is there.
class TimestampQuery : public Object<QueryTraits> {
 public:
  static TimestampQuery Create();
  void Stamp() const { glQueryCounter(id_, GL_TIMESTAMP); }
  GLuint64 ResultNs() const;
  bool Available() const;
};

}  // namespace hdribr::gl
