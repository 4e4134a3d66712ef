#include "viewer/input.h"

// GLFW without its own GL header (epoxy provides GL where it is needed).
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <Eigen/Core>
#include <utility>

namespace hdribr::viewer {
namespace {

constexpr double kRadPerPixel = 0.005;  // orbit; look-around turns at half this

}  // namespace

InputController::InputController(GLFWwindow* window, const Scene& scene, const Camera& camera,
                                 CameraController& controller, ViewState& state,
                                 InputActions actions)
    : window_(window),
      scene_(scene),
      camera_(camera),
      controller_(controller),
      state_(state),
      actions_(std::move(actions)) {}

void InputController::Process(double dt) {
  const bool keyboard = !ImGui::GetIO().WantCaptureKeyboard;
  if (keyboard) HandleKeys();
  if (keyboard) HandleFly(dt);
  HandleMouse();
}

void InputController::SnapTo(int photo) {
  const int n = static_cast<int>(scene_.photos.size());
  state_.current_photo = ((photo % n) + n) % n;
  const Photo& p = scene_.photos[static_cast<size_t>(state_.current_photo)];
  controller_.TransitionTo(p.cam_from_world, 0.6);
  state_.status = "photo " + p.name;
}

void InputController::HandleKeys() {
  // ImGui 1.86 (Debian 12): keys are the backend's (GLFW) key codes. +/- repeat when held.
  const auto pressed = [](int key) { return ImGui::IsKeyPressed(key, false); };
  const auto repeated = [](int key) { return ImGui::IsKeyPressed(key); };
  if (pressed(GLFW_KEY_ESCAPE)) glfwSetWindowShouldClose(window_, GLFW_TRUE);
  if (pressed(GLFW_KEY_H)) state_.help = !state_.help;
  if (pressed(GLFW_KEY_U)) state_.panel = !state_.panel;
  if (pressed(GLFW_KEY_F)) state_.frustums = !state_.frustums;
  if (pressed(GLFW_KEY_T)) {
    state_.tonemap.enabled = !state_.tonemap.enabled;
    state_.tone_changed = true;
  }
  if (repeated(GLFW_KEY_EQUAL) || repeated(GLFW_KEY_KP_ADD)) state_.AddExposure(0.5f);
  if (repeated(GLFW_KEY_MINUS) || repeated(GLFW_KEY_KP_SUBTRACT)) state_.AddExposure(-0.5f);
  if (pressed(GLFW_KEY_N)) SnapTo(scene_.NearestPhoto(controller_.cam_from_world()));
  if (pressed(GLFW_KEY_RIGHT_BRACKET)) SnapTo(state_.current_photo + 1);
  if (pressed(GLFW_KEY_LEFT_BRACKET)) SnapTo(state_.current_photo - 1);
  if (pressed(GLFW_KEY_HOME) || pressed(GLFW_KEY_0)) controller_.Reset();
  for (int d = 0; d < kDisplayModeCount; ++d) {
    if (pressed(GLFW_KEY_1 + d)) state_.SetDisplay(static_cast<DisplayMode>(d));
  }
  if (pressed(GLFW_KEY_P) && actions_.screenshot) actions_.screenshot();
  if (pressed(GLFW_KEY_R) && actions_.toggle_recording) actions_.toggle_recording();
  if (pressed(GLFW_KEY_L) && actions_.play) actions_.play();
}

void InputController::HandleFly(double dt) {
  const auto down = [this](int key) { return glfwGetKey(window_, key) == GLFW_PRESS; };
  Eigen::Vector3d move = Eigen::Vector3d::Zero();
  if (down(GLFW_KEY_W)) move.z() += 1;
  if (down(GLFW_KEY_S)) move.z() -= 1;
  if (down(GLFW_KEY_D)) move.x() += 1;
  if (down(GLFW_KEY_A)) move.x() -= 1;
  if (down(GLFW_KEY_Q)) move.y() += 1;  // y is down
  if (down(GLFW_KEY_E)) move.y() -= 1;
  if (move.squaredNorm() > 0) controller_.Fly(move, dt * (down(GLFW_KEY_LEFT_SHIFT) ? 4 : 1));
}

void InputController::HandleMouse() {
  const ImGuiIO& io = ImGui::GetIO();
  double x = 0, y = 0;
  glfwGetCursorPos(window_, &x, &y);
  const double dx = x - mouse_x_, dy = y - mouse_y_;
  mouse_x_ = x;
  mouse_y_ = y;
  if (io.WantCaptureMouse) return;
  if (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
    if (mouse_left_) controller_.Orbit(dx * kRadPerPixel, -dy * kRadPerPixel);
    mouse_left_ = true;
  } else {
    mouse_left_ = false;
  }
  if (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS) {
    if (mouse_right_) controller_.Look(dx * kRadPerPixel * 0.5, -dy * kRadPerPixel * 0.5);
    mouse_right_ = true;
  } else {
    mouse_right_ = false;
  }
  if (io.MouseWheel != 0 && io.DisplaySize.x > 0) {
    const Camera cam =
        camera_.Scaled(static_cast<int>(io.DisplaySize.x), static_cast<int>(io.DisplaySize.y));
    controller_.ZoomTowards(cam.CamFromPixel({x, y}), io.MouseWheel);
  }
}

}  // namespace hdribr::viewer
