#include "viewer/app.h"

// epoxy first: it must precede any GL header (GLFW's, ImGui's backends).
#include <epoxy/gl.h>
// Then GLFW without its own GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "core/error.h"
#include "gl/context.h"
#include "io/camera_spec.h"
#include "io/workspace.h"
#include "viewer/benchmark.h"
#include "viewer/camera_controller.h"
#include "viewer/frame_renderer.h"
#include "viewer/input.h"
#include "viewer/panel.h"
#include "viewer/path_control.h"
#include "viewer/view_state.h"

namespace hdribr::viewer {
namespace {

double NowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Dear ImGui with its GLFW and OpenGL 3 backends for the life of this object.
class ImGuiScope {
 public:
  explicit ImGuiScope(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 450");
  }
  ~ImGuiScope() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  ImGuiScope(const ImGuiScope&) = delete;
  ImGuiScope& operator=(const ImGuiScope&) = delete;

  static void NewFrame() {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
  }
  static void Draw() {
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  }
};

class ViewerApp {
 public:
  ViewerApp(const ViewerOptions& opt, gl::WindowContext& window, double start_s)
      : opt_(opt),
        start_s_(start_s),
        window_(window),
        scene_(LoadScene(opt.workspace)),
        state_(InitialViewState(opt, scene_)),
        start_(opt.camera.empty() ? ParseCameraSpec(scene_.photos[0].name, scene_)
                                  : ParseCameraSpec(opt.camera, scene_)),
        camera_(start_.camera),
        controller_(scene_.centroid, scene_.scene_scale, SceneUp(scene_)),
        paths_(camera_, opt.record, opt.play),
        input_(window.window(), scene_, camera_, controller_, state_, Actions()) {
    controller_.SetPose(start_.cam_from_world);
    controller_.SetHome(start_.cam_from_world);
  }

  int Run();

 private:
  static Scene LoadScene(const std::filesystem::path& workspace) {
    Scene scene = LoadWorkspace(workspace);
    if (scene.photos.empty()) throw InputError(workspace, "the workspace has no photos");
    return scene;
  }
  InputActions Actions();
  void DrawLoadingFrames();
  void SoakFrame(int frame);

  const ViewerOptions& opt_;
  double start_s_;  // when RunViewer was called (NowS)
  gl::WindowContext& window_;
  Scene scene_;
  ViewState state_;
  View start_;     // the initial view
  Camera camera_;  // the view's intrinsics (the start view's camera)
  CameraController controller_;
  PathControl paths_;
  InputController input_;
  std::unique_ptr<FrameRenderer> renderer_;
  int frame_ = 0;
  bool screenshot_pending_ = false;  // P pressed: saved once the picture is at full quality
  double now_s_ = 0;                 // this frame's time
  double fps_ = 0;
  ResourceSample soak_start_;
};

InputActions ViewerApp::Actions() {
  InputActions a;
  a.screenshot = [this] {
    screenshot_pending_ = true;
    state_.status = "screenshot: at the next full-quality frame";
  };
  a.toggle_recording = [this] {
    const std::string status = paths_.ToggleRecording(now_s_, controller_.cam_from_world());
    if (!status.empty()) state_.status = status;
  };
  a.play = [this] { paths_.Play(now_s_); };
  return a;
}

// A first frame saying what is happening, since loading blocks for a while.
void ViewerApp::DrawLoadingFrames() {
  for (int i = 0; i < 2; ++i) {
    glfwPollEvents();
    ImGuiScope::NewFrame();
    ImGui::Begin("loading", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("Loading %zu photos and computing their depth maps...", scene_.photos.size());
    ImGui::End();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window_.window(), &fw, &fh);
    ClearWindow(fw, fh);
    ImGuiScope::Draw();
    window_.SwapBuffers();
  }
}

// After frame `frame` (1-based) of a soak run: samples resources after the warm-up and at the
// end, then prints them.
void ViewerApp::SoakFrame(int frame) {
  const int warm_up = std::max(1, std::min(500, opt_.soak_frames / 2));
  if (frame == warm_up) soak_start_ = SampleResources();
  if (frame < opt_.soak_frames) return;
  const ResourceSample end = SampleResources();
  std::printf(
      "soak: frames %d (warm-up %d), rss_kb start %ld end %ld, gl_objects start %d end %d\n", frame,
      warm_up, soak_start_.rss_kb, end.rss_kb, soak_start_.gl_objects, end.gl_objects);
}

int ViewerApp::Run() {
  GLFWwindow* w = window_.window();
  const ImGuiScope imgui(w);
  DrawLoadingFrames();
  renderer_ = std::make_unique<FrameRenderer>(scene_, camera_, opt_.workspace, opt_.renderer);
  double last = NowS(), fps_clock = last;
  int fps_frames = 0;
  paths_.Start(last);
  while (!window_.ShouldClose()) {
    glfwPollEvents();
    now_s_ = NowS();
    const double dt = std::min(0.1, now_s_ - last);
    last = now_s_;
    if (++fps_frames >= 10) {
      fps_ = fps_frames / std::max(1e-6, now_s_ - fps_clock);
      fps_clock = now_s_;
      fps_frames = 0;
    }
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(w, &fw, &fh);
    if (fw == 0 || fh == 0) {  // minimised: nothing to draw
      glfwWaitEventsTimeout(0.1);
      continue;
    }
    ImGuiScope::NewFrame();
    input_.Process(dt);
    if (opt_.soak_frames > 0) SoakStep(frame_, controller_, state_);
    controller_.Update(dt);
    paths_.Advance(now_s_, opt_.frames > 0 ? frame_ : -1, controller_);
    paths_.Record(now_s_, controller_.cam_from_world());
    DrawUi(state_, {&scene_, &renderer_->stats(), fps_, renderer_->point_colours_known(),
                    paths_.recording(), renderer_->has_camera_curve()});
    renderer_->Load(state_);
    renderer_->Render(state_, controller_.cam_from_world(), fw, fh);
    if (screenshot_pending_ && renderer_->settled()) {
      char name[64];
      std::snprintf(name, sizeof(name), "hdribr_screenshot_%03d.png", frame_ % 1000);
      state_.status = "saved " + renderer_->Screenshot(name).string();
      screenshot_pending_ = false;
    }
    renderer_->Blit(fw, fh, state_.frustums, state_.current_photo);
    ImGuiScope::Draw();
    ++frame_;
    const bool last_frame = opt_.frames > 0 && frame_ >= opt_.frames;
    if (last_frame && !opt_.window_screenshot.empty()) {
      SaveWindow(opt_.window_screenshot, fw, fh);
    }
    window_.SwapBuffers();
    if (frame_ == 1) {
      std::printf("first picture %.1f s after start (%.0f%% of the window's size)\n",
                  NowS() - start_s_, 100 * renderer_->stats().scale);
      std::fflush(stdout);
    }
    if (opt_.soak_frames > 0) SoakFrame(frame_);
    if (last_frame) break;
  }
  if (opt_.benchmark) {
    RunBenchmark(*renderer_, controller_, state_, state_.settings.source,
                 opt_.frame_budget_ms.value_or(kDefaultFrameBudgetMs));
  }
  if (!opt_.screenshot.empty() && renderer_->has_display()) {
    // The last picture at full quality, whatever the frame budget and the photos' loads.
    while (!renderer_->settled()) {
      renderer_->Render(state_, controller_.cam_from_world(), renderer_->width(),
                        renderer_->height());
    }
    renderer_->Screenshot(opt_.screenshot);
  }
  return 0;
}

}  // namespace

bool CanOpenWindow() {
  const char* x = std::getenv("DISPLAY");
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  if ((x == nullptr || *x == 0) && (wl == nullptr || *wl == 0)) return false;
  try {
    gl::WindowContext probe(64, 64, "hdribr probe", false);
    return true;
  } catch (const std::exception& e) {
    spdlog::info("no window: {}", e.what());
    return false;
  }
}

int RunViewer(const ViewerOptions& options) {
  const double start_s = NowS();
  ViewerOptions opt = options;
  if (opt.soak_frames > 0) opt.frames = opt.soak_frames;
  // The window size: the initial camera's (at most 1280 wide) unless given.
  int width = opt.width, height = opt.height;
  if (width <= 0 || height <= 0) {
    const Scene scene = LoadWorkspace(opt.workspace);
    if (scene.photos.empty()) throw InputError(opt.workspace, "the workspace has no photos");
    const View v = opt.camera.empty() ? ParseCameraSpec(scene.photos[0].name, scene)
                                      : ParseCameraSpec(opt.camera, scene);
    width = v.camera.width;
    height = v.camera.height;
    if (width > 1280) {
      height = height * 1280 / width;
      width = 1280;
    }
  }
  gl::WindowContext window(width, height, "hdribr view " + opt.workspace.string(), !opt.hidden);
  glfwSwapInterval(opt.frames > 0 ? 0 : 1);
  ViewerApp app(opt, window, start_s);
  return app.Run();
}

}  // namespace hdribr::viewer
