#include "gl/debug.h"

#include <epoxy/gl.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <cstdlib>
#include <cstring>

namespace hdribr::gl {
namespace {

std::atomic<int> g_error_count{0};

void GLAPIENTRY OnDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity,
                               GLsizei length, const GLchar* message, const void* user) {
  if (type == GL_DEBUG_TYPE_ERROR) {
    ++g_error_count;
    spdlog::error("GL: {}", message);
  } else if (severity == GL_DEBUG_SEVERITY_HIGH || severity == GL_DEBUG_SEVERITY_MEDIUM) {
    spdlog::warn("GL: {}", message);
  } else {
    spdlog::debug("GL: {}", message);
  }
}

}  // namespace

void InstallDebugCallback() {
  bool enable = false;
#ifndef NDEBUG
  enable = true;
#endif
  if (const char* env = std::getenv("HDRIBR_GL_DEBUG")) enable = std::strcmp(env, "0") != 0;
  if (!enable || !epoxy_has_gl_extension("GL_KHR_debug")) return;
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(&OnDebugMessage, nullptr);
}

int DebugErrorCount() { return g_error_count.load(); }

std::string DrainGlErrors() {
  std::string out;
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    const char* name = "GL error";
    switch (e) {
      case GL_INVALID_ENUM:
        name = "GL_INVALID_ENUM";
        break;
      case GL_INVALID_VALUE:
        name = "GL_INVALID_VALUE";
        break;
      case GL_INVALID_OPERATION:
        name = "GL_INVALID_OPERATION";
        break;
      case GL_INVALID_FRAMEBUFFER_OPERATION:
        name = "GL_INVALID_FRAMEBUFFER_OPERATION";
        break;
      case GL_OUT_OF_MEMORY:
        name = "GL_OUT_OF_MEMORY";
        break;
      default:
        break;
    }
    if (!out.empty()) out += " ";
    out += name;
  }
  return out;
}

}  // namespace hdribr::gl
