#include "gl/context.h"

// epoxy/gl.h must come before any other GL header.
#include <epoxy/gl.h>
// (keep order)
#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "gl/debug.h"

namespace hdribr::gl {
namespace {

std::string EglErrorString() {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "EGL error 0x%04x", eglGetError());
  return buf;
}

bool HasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::string s = std::string(" ") + list + " ";
  return s.find(std::string(" ") + name + " ") != std::string::npos;
}

// Initialises `display`; returns false (leaving nothing open) when it fails.
bool TryInitialize(EGLDisplay display) {
  if (display == EGL_NO_DISPLAY) return false;
  EGLint major = 0, minor = 0;
  return eglInitialize(display, &major, &minor) == EGL_TRUE;
}

}  // namespace

std::string Context::Renderer() const {
  const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return s ? s : "";
}

std::string Context::Version() const {
  const auto* s = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return s ? s : "";
}

void InitContextState() {
  if (epoxy_gl_version() < 45) {
    throw std::runtime_error("OpenGL 4.5 is required, got " +
                             std::to_string(epoxy_gl_version() / 10) + "." +
                             std::to_string(epoxy_gl_version() % 10));
  }
  glClipControl(GL_UPPER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  InstallDebugCallback();
}

HeadlessContext::HeadlessContext() {
  const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  EGLDisplay display = EGL_NO_DISPLAY;
  if (get_platform_display && HasExtension(client_ext, "EGL_MESA_platform_surfaceless")) {
    display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (TryInitialize(display)) platform_ = "surfaceless";
  }
  if (platform_.empty() && get_platform_display &&
      HasExtension(client_ext, "EGL_EXT_platform_device")) {
    auto query_devices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (query_devices) {
      EGLint n = 0;
      query_devices(0, nullptr, &n);
      std::vector<EGLDeviceEXT> devices(static_cast<size_t>(std::max(n, 0)));
      if (n > 0 && query_devices(n, devices.data(), &n)) {
        for (EGLint i = 0; i < n && platform_.empty(); ++i) {
          display = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
          if (TryInitialize(display)) platform_ = "device";
        }
      }
    }
  }
  if (platform_.empty()) {
    display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (!TryInitialize(display)) {
      throw std::runtime_error("no EGL display (surfaceless, device or default): " +
                               EglErrorString());
    }
    platform_ = "default";
  }
  display_ = display;
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
    eglTerminate(display);
    throw std::runtime_error("EGL cannot bind the desktop OpenGL API: " + EglErrorString());
  }
  const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                   EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint num_configs = 0;
  const bool have_config =
      eglChooseConfig(display, config_attribs, &config, 1, &num_configs) && num_configs > 0;
  const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                    4,
                                    EGL_CONTEXT_MINOR_VERSION,
                                    5,
                                    EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                    EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
#ifndef NDEBUG
                                    EGL_CONTEXT_OPENGL_DEBUG,
                                    EGL_TRUE,
#endif
                                    EGL_NONE};
  // Surfaceless contexts need no config (EGL_KHR_no_config_context).
  EGLContext ctx = eglCreateContext(display, have_config ? config : EGL_NO_CONFIG_KHR,
                                    EGL_NO_CONTEXT, context_attribs);
  if (ctx == EGL_NO_CONTEXT) {
    const std::string err = EglErrorString();
    eglTerminate(display);
    throw std::runtime_error("cannot create an OpenGL 4.5 core context through EGL (" + platform_ +
                             "): " + err);
  }
  context_ = ctx;
  MakeCurrent();
  InitContextState();
}

HeadlessContext::~HeadlessContext() {
  if (display_ != nullptr) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != nullptr) eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
}

void HeadlessContext::MakeCurrent() {
  if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE) {
    throw std::runtime_error("eglMakeCurrent failed: " + EglErrorString());
  }
}

WindowContext::WindowContext(int width, int height, const std::string& title, bool visible) {
  if (!glfwInit()) throw std::runtime_error("glfwInit failed (no display?)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
#ifndef NDEBUG
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (window_ == nullptr) {
    glfwTerminate();
    throw std::runtime_error("cannot create a GLFW window with an OpenGL 4.5 core context");
  }
  MakeCurrent();
  InitContextState();
}

WindowContext::~WindowContext() {
  if (window_ != nullptr) glfwDestroyWindow(window_);
  glfwTerminate();
}

void WindowContext::MakeCurrent() { glfwMakeContextCurrent(window_); }
bool WindowContext::ShouldClose() const { return glfwWindowShouldClose(window_); }
void WindowContext::SwapBuffers() { glfwSwapBuffers(window_); }

}  // namespace hdribr::gl
