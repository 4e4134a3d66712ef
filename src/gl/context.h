// OpenGL 4.5 core contexts: headless through EGL (no display server) and a GLFW window.
#pragma once

#include <memory>
#include <string>

struct GLFWwindow;

namespace hdribr::gl {

// A current OpenGL 4.5 core context. Sets glClipControl(GL_UPPER_LEFT, GL_NEGATIVE_ONE_TO_ONE)
// (see core/projection.h) and, in debug builds, a GL_KHR_debug callback.
class Context {
 public:
  virtual ~Context() = default;
  // GL_RENDERER and GL_VERSION, for logs and benchmark reports.
  std::string Renderer() const;
  std::string Version() const;
  // Makes this context current on the calling thread.
  virtual void MakeCurrent() = 0;
};

// Headless context through EGL: the surfaceless platform (EGL_PLATFORM_SURFACELESS_MESA, which
// Mesa and NVIDIA's EGL both offer), falling back to the EGL device platform and then the
// default display. Throws std::runtime_error with the reason when no 4.5 core context can be
// made.
class HeadlessContext final : public Context {
 public:
  HeadlessContext();
  ~HeadlessContext() override;
  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;
  void MakeCurrent() override;
  // Which EGL platform was used: "surfaceless", "device" or "default".
  const std::string& platform() const { return platform_; }

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string platform_;
};

// A GLFW window with a 4.5 core context (for the viewer). Throws std::runtime_error on failure.
class WindowContext final : public Context {
 public:
  WindowContext(int width, int height, const std::string& title, bool visible = true);
  ~WindowContext() override;
  WindowContext(const WindowContext&) = delete;
  WindowContext& operator=(const WindowContext&) = delete;
  void MakeCurrent() override;
  GLFWwindow* window() const { return window_; }
  bool ShouldClose() const;
  void SwapBuffers();

 private:
  GLFWwindow* window_ = nullptr;
};

// Sets the state every hdribr context shares (clip control, debug output). Called by the
// contexts above after creation.
void InitContextState();

}  // namespace hdribr::gl
