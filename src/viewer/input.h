// Every key and mouse action of the viewer, in one place: read once per frame from GLFW and
// Dear ImGui (a current ImGui frame is needed), applied to the view state and the camera
// controller. Actions that need the rest of the application go through InputActions.
#pragma once

#include <functional>

#include "core/camera.h"
#include "core/scene.h"
#include "viewer/camera_controller.h"
#include "viewer/view_state.h"

struct GLFWwindow;

namespace hdribr::viewer {

// What the input asks of the application (each may be empty).
struct InputActions {
  std::function<void()> screenshot;        // P
  std::function<void()> toggle_recording;  // R
  std::function<void()> play;              // L
};

class InputController {
 public:
  // `camera` is the view's intrinsics (scaled to the window for cursor rays).
  InputController(GLFWwindow* window, const Scene& scene, const Camera& camera,
                  CameraController& controller, ViewState& state, InputActions actions);

  // Handles this frame's keys (skipped while ImGui wants the keyboard), then flying (dt
  // seconds), then the mouse (skipped while ImGui wants it).
  void Process(double dt);
  // Moves to photo `photo` (wrapped around the capture order) with a smooth transition.
  void SnapTo(int photo);

 private:
  void HandleKeys();
  void HandleFly(double dt);
  void HandleMouse();

  GLFWwindow* window_;
  const Scene& scene_;
  const Camera& camera_;
  CameraController& controller_;
  ViewState& state_;
  InputActions actions_;
  bool mouse_left_ = false, mouse_right_ = false;
  double mouse_x_ = 0, mouse_y_ = 0;  // window pixels
};

}  // namespace hdribr::viewer
