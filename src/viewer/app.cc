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
#include <cmath>
#include <cstdio>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "core/error.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "io/camera_spec.h"
#include "io/image.h"
#include "io/workspace.h"
#include "render/hdr_photo_set.h"
#include "render/hdr_render.h"
#include "render/point_color_pass.h"
#include "render/render_output.h"
#include "render/renderer.h"
#include "render/tonemap_pass.h"
#include "viewer/camera_controller.h"
#include "viewer/false_colour_pass.h"
#include "viewer/frustum_pass.h"
#include "viewer/recorder.h"

namespace hdribr::viewer {
namespace {

using Clock = std::chrono::steady_clock;

double NowS() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }

// Keys 1 ... 7 in this order.
enum class DisplayMode { kFinal, kDepth, kNormals, kClasses, kCount, kPointColours, kNearestPhoto };
constexpr int kDisplayModes = 7;
// --display names, in DisplayMode order.
constexpr const char* kDisplayNames[kDisplayModes] = {"final", "depth",  "normals", "classes",
                                                      "count", "splats", "nearest"};
constexpr const char* kDisplayCombo =
    "final\0depth\0normals\0front/back classes\0contributing count\0colour-per-point "
    "splats\0nearest photo\0";
constexpr const char* kSourceNames[] = {"ldr", "precomputed", "onthefly", "direct"};

// Every key of the viewer, for the help overlay and docs/usage.md.
constexpr const char* kHelp[][2] = {
    {"left drag", "orbit around the scene centre"},
    {"right drag", "look around (fly mode)"},
    {"W A S D / Q E", "fly forward, left, back, right / down, up (Shift: x4)"},
    {"scroll", "zoom towards the cursor"},
    {"N", "snap to the nearest photo"},
    {"[ / ]", "previous / next photo in capture order"},
    {"Home or 0", "reset the view"},
    {"+ / -", "exposure +- 1/2 EV (tone-map pass only)"},
    {"T", "tone mapping on / off"},
    {"1 ... 7", "display: final, depth, normals, classes, count, splats, nearest photo"},
    {"F", "input camera frustums (3D, hidden by the scene) on / off"},
    {"P", "screenshot (PNG tone-mapped + EXR linear)"},
    {"R", "start / stop recording a camera path"},
    {"L", "play the recorded (or --play) path"},
    {"U", "control panel on / off"},
    {"H", "this help"},
    {"Esc", "quit"},
};

struct Settings {
  int source = 0;  // index into kSourceNames
  int series = -1;
  int depth_mode = 2;  // plain, marroquim, lechelek
  int weights = 1;     // paper, ulr (render::BlendWeights order)
  int k_best = 0;
  float lambda = 1e-4f;
  float tolerance = 0.01f;
  bool operator==(const Settings&) const = default;
};

class ViewerApp {
 public:
  ViewerApp(const ViewerOptions& opt, gl::WindowContext& window)
      : opt_(opt), window_(window), scene_(LoadWorkspace(opt.workspace)) {
    if (scene_.photos.empty()) throw InputError(opt.workspace, "the workspace has no photos");
    const std::string source =
        opt.hdr == "auto"
            ? (std::filesystem::exists(opt.workspace / "hdr/hdr_set.json") ? "precomputed" : "ldr")
            : opt.hdr;
    for (int i = 0; i < 4; ++i) {
      if (source == kSourceNames[i]) settings_.source = i;
    }
    if (source != kSourceNames[settings_.source]) {
      throw UsageError("--hdr must be auto, ldr, precomputed, onthefly or direct, got '" + opt.hdr +
                       "'");
    }
    settings_.series = opt.series;
    if (opt.series >= static_cast<int>(scene_.series.size())) {
      throw UsageError("--series " + std::to_string(opt.series) + ": the workspace has " +
                       std::to_string(scene_.series.size()) + " series");
    }
    settings_.depth_mode = static_cast<int>(render::ParseDepthMode(opt.depth_mode));
    const auto* mode = std::find(std::begin(kDisplayNames), std::end(kDisplayNames), opt.display);
    if (mode == std::end(kDisplayNames)) {
      throw UsageError(
          "--display must be final, depth, normals, classes, count, splats or "
          "nearest, got '" +
          opt.display + "'");
    }
    display_mode_ = static_cast<DisplayMode>(mode - std::begin(kDisplayNames));
    settings_.weights = static_cast<int>(render::ParseBlendWeights(opt.weights));
    settings_.k_best = opt.k_best;
    settings_.lambda = opt.lambda;
    settings_.tolerance = opt.tolerance;
    const bool hdr = settings_.source != 0;
    tonemap_.enabled = opt.tonemap.value_or(hdr);
    tonemap_.gamma = opt.gamma.value_or(hdr ? 2.2f : 1.0f);
    tonemap_.key = opt.key;
    exposure_ev_ = opt.exposure_ev;
    tonemap_.smoothing = opt.frames > 0 ? 0.0f : 0.9f;  // scripted frames: no history

    controller_ =
        std::make_unique<CameraController>(scene_.centroid, scene_.scene_scale, SceneUp(scene_));
    const View start = opt.camera.empty() ? ParseCameraSpec(scene_.photos[0].name, scene_)
                                          : ParseCameraSpec(opt.camera, scene_);
    camera_ = start.camera;
    controller_->SetPose(start.cam_from_world);
    controller_->SetHome(start.cam_from_world);
    if (!opt.play.empty()) player_ = std::make_unique<Player>(ReadCameraPath(opt.play));
  }

  int Run();

 private:
  void Load();
  void RenderIfNeeded(int width, int height);
  void RenderSplats(const Camera& cam, const Rigid3d& pose);
  void Blit(int fb_width, int fb_height);
  void HandleInput(double dt);
  void DrawUi();
  void DrawPanel();
  void DrawLegend();
  void Screenshot(const std::filesystem::path& png);
  void SnapTo(int photo);
  void Benchmark();
  Camera ViewCamera(int width, int height) const { return camera_.Scaled(width, height); }
  render::Renderer& BaseRenderer() { return hdr_ ? hdr_->renderer() : *ldr_; }

  const ViewerOptions& opt_;
  gl::WindowContext& window_;
  Scene scene_;
  gl::ShaderLibrary shaders_;
  Camera camera_;
  std::unique_ptr<CameraController> controller_;
  std::unique_ptr<render::Renderer> ldr_;
  std::unique_ptr<render::HdrRenderer> hdr_;
  std::unique_ptr<render::LoadedHdrPhotoSet> set_;
  std::unique_ptr<render::TonemapPass> tonemap_pass_;
  std::unique_ptr<FalseColourPass> false_colour_;
  std::unique_ptr<FrustumPass> frustum_pass_;
  std::unique_ptr<render::PointColorPass> point_pass_;
  bool point_colours_known_ = true;  // false: the cloud has no colours (grey splats)
  render::RenderTarget target_;
  gl::Texture display_;  // what the screenshot saves: the picture without overlays
  gl::Framebuffer display_fb_;
  gl::Texture composite_;  // display_ + the frustums, when they are shown
  gl::Framebuffer composite_fb_;
  gl::Texture splats_;  // RGBA32F colour-per-point splats (a = covered), tone-mapped like final
  Settings settings_, loaded_settings_;
  bool loaded_ = false;
  bool options_dirty_ = false;  // display mode changed: blend mode to update
  render::TonemapOptions tonemap_;
  float exposure_ev_ = 0;
  bool auto_la_ = true;
  float fixed_la_ = 1;  // target units
  float last_la_ = 1;
  DisplayMode display_mode_ = DisplayMode::kFinal;
  bool frustums_ = opt_.show_frustums, help_ = opt_.show_help, panel_ = !opt_.hide_panel;
  // Dirty flags: the radiance target (camera / blend) and the display (tone mapping).
  bool render_dirty_ = true, display_dirty_ = true;
  Rigid3d rendered_pose_;
  // Timings of the last re-render and the last tone-map (ms).
  double render_wall_ms_ = 0, tonemap_wall_ms_ = 0;
  render::RenderTimes render_gpu_;
  double tonemap_gpu_ms_ = 0;
  double fps_ = 0;
  int current_photo_ = 0;
  Recorder recorder_;
  CameraPath last_path_;
  std::unique_ptr<Player> player_;
  double play_start_s_ = -1;
  std::string status_;
  bool mouse_left_ = false, mouse_right_ = false;
  double mouse_x_ = 0, mouse_y_ = 0;
};

void ViewerApp::Load() {
  if (loaded_ && settings_ == loaded_settings_ && !options_dirty_) return;
  const bool reload = !loaded_ || settings_.source != loaded_settings_.source;
  options_dirty_ = false;
  if (reload) {
    hdr_.reset();
    ldr_.reset();
    render::RendererOptions ro;
    ro.max_photo_size = opt_.max_photo_size;
    const auto t0 = Clock::now();
    std::printf("loading %zu photos, computing their depth maps (%s)...\n", scene_.photos.size(),
                kSourceNames[settings_.source]);
    std::fflush(stdout);
    if (settings_.source == 0) {
      ldr_ = std::make_unique<render::Renderer>(shaders_, scene_, ro);
    } else {
      if (!set_) {
        set_ = std::make_unique<render::LoadedHdrPhotoSet>(
            render::LoadHdrPhotoSet(scene_, opt_.workspace / render::kHdrSetFolder));
      }
      const render::HdrMode mode = render::ParseHdrMode(kSourceNames[settings_.source]);
      hdr_ = std::make_unique<render::HdrRenderer>(shaders_, scene_, mode, set_->response, ro,
                                                   set_.get());
    }
    std::printf("loaded in %.1f s, GPU memory %.1f MiB\n",
                std::chrono::duration<double>(Clock::now() - t0).count(),
                BaseRenderer().gpu_bytes() / 1048576.0);
  }
  render::Renderer& r = BaseRenderer();
  r.blend_options().weights = static_cast<render::BlendWeights>(settings_.weights);
  r.blend_options().k_best = settings_.k_best;
  r.blend_options().lambda = settings_.lambda;
  r.blend_options().occlusion_tolerance = settings_.tolerance;
  r.blend_options().mode = display_mode_ == DisplayMode::kNearestPhoto
                               ? render::BlendMode::kNearestPhoto
                               : render::BlendMode::kBlend;
  r.depth_pass().options().mode = static_cast<render::DepthMode>(settings_.depth_mode);
  if (ldr_) {
    if (settings_.series >= 0) {
      ldr_->SetActivePhotos(scene_.series[static_cast<size_t>(settings_.series)].photo_indices);
    } else {
      ldr_->SetAllPhotosActive();
    }
  }
  loaded_settings_ = settings_;
  loaded_ = true;
  render_dirty_ = true;
  tonemap_pass_->ResetHistory();
}

void ViewerApp::RenderIfNeeded(int width, int height) {
  if (width <= 0 || height <= 0) return;  // minimised
  if (target_.width() != width || target_.height() != height) {
    target_ = render::RenderTarget::Create(width, height);
    display_ = gl::Texture::Create2D(GL_RGBA8, width, height);
    display_fb_ = gl::Framebuffer::Create();
    display_fb_.AttachColor(0, display_);
    composite_ = gl::Texture::Create2D(GL_RGBA8, width, height);
    composite_fb_ = gl::Framebuffer::Create();
    composite_fb_.AttachColor(0, composite_);
    splats_ = gl::Texture::Create2D(GL_RGBA32F, width, height);
    render_dirty_ = true;
  }
  const Rigid3d pose = controller_->cam_from_world();
  if (!pose.rotation.isApprox(rendered_pose_.rotation, 1e-12) ||
      !pose.translation.isApprox(rendered_pose_.translation, 1e-12)) {
    render_dirty_ = true;
  }
  if (render_dirty_) {
    const auto t0 = Clock::now();
    const Camera cam = ViewCamera(width, height);
    if (hdr_) {
      hdr_->Render(cam, pose, target_);
    } else {
      ldr_->Render(cam, pose, target_);
    }
    if (display_mode_ == DisplayMode::kPointColours) RenderSplats(cam, pose);
    glFinish();
    render_wall_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    render_gpu_ = BaseRenderer().last_times();
    rendered_pose_ = pose;
    render_dirty_ = false;
    display_dirty_ = true;
  }
  if (display_dirty_) {
    const auto t0 = Clock::now();
    const int photos = static_cast<int>(scene_.photos.size());
    switch (display_mode_) {
      case DisplayMode::kFinal:
      case DisplayMode::kNearestPhoto: {
        render::TonemapOptions o = tonemap_;
        o.exposure = std::exp2(exposure_ev_);
        if (!auto_la_) o.fixed_log_average = fixed_la_;
        last_la_ = tonemap_pass_->Apply(target_.color, o, display_);
        tonemap_gpu_ms_ = tonemap_pass_->last_ms();
        break;
      }
      case DisplayMode::kPointColours: {
        // The cloud's colours are display values (sRGB 8-bit): exposure only, no curve.
        render::TonemapOptions o;
        o.enabled = false;
        o.exposure = std::exp2(exposure_ev_);
        o.gamma = 1.0f;
        tonemap_pass_->Apply(splats_, o, display_);
        tonemap_gpu_ms_ = tonemap_pass_->last_ms();
        break;
      }
      case DisplayMode::kDepth:
        false_colour_->Apply(FalseColourMap::kDepth, target_, photos, display_);
        tonemap_gpu_ms_ = 0;
        break;
      case DisplayMode::kNormals:
        false_colour_->Apply(FalseColourMap::kNormals, target_, photos, display_);
        tonemap_gpu_ms_ = 0;
        break;
      case DisplayMode::kCount:
        false_colour_->Apply(FalseColourMap::kCount, target_, photos, display_);
        tonemap_gpu_ms_ = 0;
        break;
      case DisplayMode::kClasses:
        if (target_.depth.classes.empty()) {  // a depth pass without classes: nothing to show
          glClearTexImage(display_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        } else {
          false_colour_->Apply(FalseColourMap::kClasses, target_, photos, display_,
                               &target_.depth.classes);
        }
        tonemap_gpu_ms_ = 0;
        break;
    }
    glFinish();
    tonemap_wall_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    display_dirty_ = false;
  }
}

// Colour-per-point splats (the paper's Fig. 8 baseline) into splats_, for the tone-map pass.
void ViewerApp::RenderSplats(const Camera& cam, const Rigid3d& pose) {
  const render::PointColorImages im =
      point_pass_->Render(cam, pose, splats_.width(), splats_.height());
  cv::Mat rgba;
  cv::cvtColor(im.color, rgba, cv::COLOR_BGR2RGBA);
  rgba.setTo(cv::Scalar(0, 0, 0, 0), im.valid == 0);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(splats_.id(), 0, 0, 0, rgba.cols, rgba.rows, GL_RGBA, GL_FLOAT, rgba.ptr());
}

void ViewerApp::Blit(int fb_width, int fb_height) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fb_width, fb_height);
  glClearColor(0.08f, 0.08f, 0.08f, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  if (display_.empty()) return;
  GLuint source = display_fb_.id();
  if (frustums_ && frustum_pass_) {
    // Frustums over a copy, so that display_ (the screenshot) stays the bare picture.
    glCopyImageSubData(display_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, composite_.id(), GL_TEXTURE_2D, 0,
                       0, 0, 0, display_.width(), display_.height(), 1);
    frustum_pass_->Draw(ViewCamera(display_.width(), display_.height()), rendered_pose_,
                        target_.depth.depth, composite_fb_, current_photo_);
    source = composite_fb_.id();
  }
  // The display texture's row 0 is the image's top row; the window's row 0 is its bottom.
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fb_width, fb_height);
  glBlitNamedFramebuffer(source, 0, 0, 0, display_.width(), display_.height(), 0, fb_height,
                         fb_width, 0, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

void ViewerApp::SnapTo(int photo) {
  const int n = static_cast<int>(scene_.photos.size());
  current_photo_ = ((photo % n) + n) % n;
  controller_->TransitionTo(scene_.photos[static_cast<size_t>(current_photo_)].cam_from_world, 0.6);
  status_ = "photo " + scene_.photos[static_cast<size_t>(current_photo_)].name;
}

void ViewerApp::Screenshot(const std::filesystem::path& out) {
  const bool exr = out.extension() == ".exr";
  std::filesystem::path png = exr ? std::filesystem::path(out).replace_extension(".png") : out;
  std::filesystem::path exr_path = std::filesystem::path(out).replace_extension(".exr");
  cv::Mat rgba(display_.height(), display_.width(), CV_8UC4);
  glGetTextureImage(display_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                    static_cast<GLsizei>(rgba.total() * rgba.elemSize()), rgba.ptr());
  cv::Mat bgra;
  cv::cvtColor(rgba, bgra, cv::COLOR_RGBA2BGRA);
  WriteImage(png, bgra);
  const render::RenderImages im = render::Renderer::Read(target_);
  cv::Mat linear = im.color;
  if (hdr_ && hdr_->target_scale() != 1.0) linear = im.color / hdr_->target_scale();
  render::WriteRgbaExr(exr_path, linear, im.valid);
  std::printf("screenshot: %s (tone-mapped), %s (linear)\n", png.c_str(), exr_path.c_str());
  status_ = "saved " + png.string();
}

void ViewerApp::HandleInput(double dt) {
  GLFWwindow* w = window_.window();
  const ImGuiIO& io = ImGui::GetIO();
  if (!io.WantCaptureKeyboard) {
    Eigen::Vector3d move = Eigen::Vector3d::Zero();
    if (glfwGetKey(w, GLFW_KEY_W) == GLFW_PRESS) move.z() += 1;
    if (glfwGetKey(w, GLFW_KEY_S) == GLFW_PRESS) move.z() -= 1;
    if (glfwGetKey(w, GLFW_KEY_D) == GLFW_PRESS) move.x() += 1;
    if (glfwGetKey(w, GLFW_KEY_A) == GLFW_PRESS) move.x() -= 1;
    if (glfwGetKey(w, GLFW_KEY_Q) == GLFW_PRESS) move.y() += 1;  // y is down
    if (glfwGetKey(w, GLFW_KEY_E) == GLFW_PRESS) move.y() -= 1;
    if (move.squaredNorm() > 0) {
      const bool fast = glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS;
      controller_->Fly(move, dt * (fast ? 4 : 1));
    }
  }
  double x = 0, y = 0;
  glfwGetCursorPos(w, &x, &y);
  const double dx = x - mouse_x_, dy = y - mouse_y_;
  mouse_x_ = x;
  mouse_y_ = y;
  if (io.WantCaptureMouse) return;
  const double rad_per_px = 0.005;
  if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
    if (mouse_left_) controller_->Orbit(dx * rad_per_px, -dy * rad_per_px);
    mouse_left_ = true;
  } else {
    mouse_left_ = false;
  }
  if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS) {
    if (mouse_right_) controller_->Look(dx * rad_per_px * 0.5, -dy * rad_per_px * 0.5);
    mouse_right_ = true;
  } else {
    mouse_right_ = false;
  }
  if (io.MouseWheel != 0 && io.DisplaySize.x > 0) {
    const Camera cam =
        ViewCamera(static_cast<int>(io.DisplaySize.x), static_cast<int>(io.DisplaySize.y));
    controller_->ZoomTowards(cam.CamFromPixel({x, y}), io.MouseWheel);
  }
}

void ViewerApp::DrawUi() {
  if (panel_) DrawPanel();
  if (help_) {
    ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x * 0.5f, 40), ImGuiCond_Always,
                            ImVec2(0.5f, 0));
    ImGui::Begin("keys (H)", &help_, ImGuiWindowFlags_AlwaysAutoResize);
    for (const auto& k : kHelp) ImGui::Text("%-16s %s", k[0], k[1]);
    ImGui::End();
  }
}

void ViewerApp::DrawPanel() {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.75f);
  ImGui::Begin("hdribr", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::Text("%.1f fps   render %.1f ms (depth %.1f + blend %.1f GPU)", fps_, render_wall_ms_,
              render_gpu_.depth_ms, render_gpu_.blend_ms);
  ImGui::Text("tone map %.2f ms (GPU %.2f)   L_a %.4g", tonemap_wall_ms_, tonemap_gpu_ms_,
              last_la_);
  bool tone_changed = false;
  tone_changed |= ImGui::SliderFloat("exposure (EV)", &exposure_ev_, -8, 8, "%.2f");
  tone_changed |= ImGui::SliderFloat("key", &tonemap_.key, 0.01f, 1.0f, "%.3f");
  tone_changed |= ImGui::SliderFloat("gamma", &tonemap_.gamma, 1.0f, 3.0f, "%.2f");
  tone_changed |= ImGui::Checkbox("tone mapping (Reinhard)", &tonemap_.enabled);
  if (ImGui::Checkbox("auto L_a", &auto_la_)) {
    fixed_la_ = last_la_;
    tone_changed = true;
  }
  if (!auto_la_) {
    tone_changed |= ImGui::SliderFloat("fixed L_a", &fixed_la_, 1e-4f, 100.0f, "%.4g",
                                       ImGuiSliderFlags_Logarithmic);
  }
  if (tone_changed) display_dirty_ = true;

  ImGui::Separator();
  const char* sources = "ldr\0precomputed HDR\0on-the-fly HDR\0direct radiance\0";
  ImGui::Combo("source", &settings_.source, sources);
  if (settings_.source == 0) {
    int s = settings_.series + 1;
    std::string items = "all series";
    items.push_back('\0');
    for (const ExposureSeries& es : scene_.series) {
      items += es.name;
      items.push_back('\0');
    }
    if (ImGui::Combo("series", &s, items.c_str())) settings_.series = s - 1;
  }
  ImGui::Combo("depth", &settings_.depth_mode, "plain\0marroquim\0lechelek\0");
  ImGui::Combo("weights", &settings_.weights, "paper (eq. 5)\0unstructured lumigraph\0");
  ImGui::SliderInt(settings_.weights == 0 ? "K best (0 = all)" : "K (0 = 4)", &settings_.k_best, 0,
                   16);
  ImGui::SliderFloat("lambda", &settings_.lambda, 0.0f, 0.5f, "%.4f");
  ImGui::SliderFloat("occlusion tol.", &settings_.tolerance, 0.001f, 0.1f, "%.3f",
                     ImGuiSliderFlags_Logarithmic);
  int mode = static_cast<int>(display_mode_);
  if (ImGui::Combo("display", &mode, kDisplayCombo)) {
    display_mode_ = static_cast<DisplayMode>(mode);
    options_dirty_ = true;  // the blend mode may change
  }
  DrawLegend();
  ImGui::Checkbox("camera frustums", &frustums_);
  ImGui::Text("%s", recorder_.recording() ? "RECORDING (R to stop)" : status_.c_str());
  ImGui::End();
}

// One line under the display combo saying how to read the current display mode.
void ViewerApp::DrawLegend() {
  switch (display_mode_) {
    case DisplayMode::kDepth:
      ImGui::TextUnformatted("depth: near red ... far blue (turbo over the visible range)");
      break;
    case DisplayMode::kNormals:
      ImGui::TextUnformatted("normals: RGB = camera-space (x, y, z) / 2 + 1/2");
      break;
    case DisplayMode::kCount:
      ImGui::Text("count: 0 blue ... %zu photos red", scene_.photos.size());
      break;
    case DisplayMode::kClasses: {
      const auto colour = [](const float* c) { return ImVec4(c[0], c[1], c[2], 1.0f); };
      ImGui::TextColored(colour(kFrontColour), "front");
      ImGui::SameLine();
      ImGui::TextColored(colour(kFilledColour), "background-filled");
      ImGui::SameLine();
      ImGui::TextUnformatted("black: no depth");
      break;
    }
    case DisplayMode::kPointColours:
      ImGui::TextUnformatted(point_colours_known_
                                 ? "splats: one colour per point (the cloud's), no blending"
                                 : "splats: the cloud has no colours (grey)");
      break;
    default:
      break;
  }
}

void ViewerApp::Benchmark() {
  const int n = 10;
  const int w = target_.width(), h = target_.height();
  double move_ms = 0, expo_ms = 0, move_gpu = 0, expo_gpu = 0;
  for (int i = 0; i < n; ++i) {
    controller_->Orbit(0.01, 0);
    const auto t0 = Clock::now();
    RenderIfNeeded(w, h);
    move_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    move_gpu += render_gpu_.depth_ms + render_gpu_.blend_ms + tonemap_gpu_ms_;
  }
  for (int i = 0; i < n; ++i) {
    exposure_ev_ += 0.1f;
    display_dirty_ = true;
    const auto t0 = Clock::now();
    RenderIfNeeded(w, h);
    expo_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    expo_gpu += tonemap_gpu_ms_;
  }
  std::printf(
      "viewer benchmark %dx%d, %zu photos, %s: camera move %.2f ms/frame (GPU %.2f ms), "
      "exposure change %.2f ms/frame (GPU %.2f ms)\n",
      w, h, BaseRenderer().scene().photos.size(), kSourceNames[settings_.source], move_ms / n,
      move_gpu / n, expo_ms / n, expo_gpu / n);
}

int ViewerApp::Run() {
  GLFWwindow* w = window_.window();
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui_ImplGlfw_InitForOpenGL(w, true);
  ImGui_ImplOpenGL3_Init("#version 450");
  struct ImGuiGuard {
    ~ImGuiGuard() {
      ImGui_ImplOpenGL3_Shutdown();
      ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext();
    }
  } guard;

  // A first frame saying what is happening, since loading blocks for a while.
  for (int i = 0; i < 2; ++i) {
    glfwPollEvents();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGui::Begin("loading", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("Loading %zu photos and computing their depth maps...", scene_.photos.size());
    ImGui::End();
    ImGui::Render();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(w, &fw, &fh);
    Blit(fw, fh);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    window_.SwapBuffers();
  }
  tonemap_pass_ = std::make_unique<render::TonemapPass>(shaders_);
  false_colour_ = std::make_unique<FalseColourPass>(shaders_);
  frustum_pass_ = std::make_unique<FrustumPass>(shaders_);
  frustum_pass_->SetLines(MakeFrustumLines(scene_, 0.15 * scene_.scene_scale));
  point_pass_ = std::make_unique<render::PointColorPass>(shaders_);
  {
    // The cloud's sRGB colours (BGR, 0..1); grey when it has none.
    const PointCloud& cloud = scene_.points;
    point_colours_known_ = cloud.HasColors();
    std::vector<Eigen::Vector3f> bgr(cloud.size(), Eigen::Vector3f::Constant(0.5f));
    for (size_t i = 0; point_colours_known_ && i < cloud.size(); ++i) {
      const auto& c = cloud.colors[i];
      bgr[i] = Eigen::Vector3f(c[2], c[1], c[0]) / 255.0f;
    }
    point_pass_->SetPoints(cloud, bgr);
  }

  int frame = 0;
  double last = NowS(), fps_clock = last;
  int fps_frames = 0;
  if (player_) play_start_s_ = last;
  while (!window_.ShouldClose()) {
    glfwPollEvents();
    const double now = NowS();
    const double dt = std::min(0.1, now - last);
    last = now;
    if (++fps_frames >= 10) {
      fps_ = fps_frames / std::max(1e-6, now - fps_clock);
      fps_clock = now;
      fps_frames = 0;
    }
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(w, &fw, &fh);
    if (fw == 0 || fh == 0) {  // minimised: nothing to draw
      glfwWaitEventsTimeout(0.1);
      continue;
    }
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const ImGuiIO& io = ImGui::GetIO();
    if (!io.WantCaptureKeyboard) {
      // ImGui 1.86 (Debian 12): keys are the backend's (GLFW) key codes.
      auto pressed = [](int key) { return ImGui::IsKeyPressed(key, false); };
      if (pressed(GLFW_KEY_ESCAPE)) glfwSetWindowShouldClose(w, GLFW_TRUE);
      if (pressed(GLFW_KEY_H)) help_ = !help_;
      if (pressed(GLFW_KEY_U)) panel_ = !panel_;
      if (pressed(GLFW_KEY_F)) frustums_ = !frustums_;
      if (pressed(GLFW_KEY_T)) {
        tonemap_.enabled = !tonemap_.enabled;
        display_dirty_ = true;
      }
      if (ImGui::IsKeyPressed(GLFW_KEY_EQUAL) || ImGui::IsKeyPressed(GLFW_KEY_KP_ADD)) {
        exposure_ev_ += 0.5f;
        display_dirty_ = true;
      }
      if (ImGui::IsKeyPressed(GLFW_KEY_MINUS) || ImGui::IsKeyPressed(GLFW_KEY_KP_SUBTRACT)) {
        exposure_ev_ -= 0.5f;
        display_dirty_ = true;
      }
      if (pressed(GLFW_KEY_N)) SnapTo(NearestPhoto(scene_, controller_->cam_from_world()));
      if (pressed(GLFW_KEY_RIGHT_BRACKET)) SnapTo(current_photo_ + 1);
      if (pressed(GLFW_KEY_LEFT_BRACKET)) SnapTo(current_photo_ - 1);
      if (pressed(GLFW_KEY_HOME) || pressed(GLFW_KEY_0)) controller_->Reset();
      for (int d = 0; d < kDisplayModes; ++d) {
        if (pressed(GLFW_KEY_1 + d)) {
          display_mode_ = static_cast<DisplayMode>(d);
          options_dirty_ = true;
        }
      }
      if (pressed(GLFW_KEY_P)) {
        char name[64];
        std::snprintf(name, sizeof(name), "hdribr_screenshot_%03d.png", frame % 1000);
        Screenshot(name);
      }
      if (pressed(GLFW_KEY_R)) {
        if (recorder_.recording()) {
          View v{"frame", camera_, controller_->cam_from_world()};
          last_path_ = recorder_.Stop(std::make_pair(now, v));
          const std::filesystem::path out =
              opt_.record.empty() ? std::filesystem::path("hdribr_path.json") : opt_.record;
          WriteCameraPath(out, last_path_);
          status_ = "path saved to " + out.string();
          std::printf("%s (%zu keyframes)\n", status_.c_str(), last_path_.keyframes.size());
        } else {
          recorder_.Start(30);
        }
      }
      if (pressed(GLFW_KEY_L)) {
        if (!last_path_.keyframes.empty()) player_ = std::make_unique<Player>(last_path_);
        if (player_) play_start_s_ = now;
      }
    }
    HandleInput(dt);
    controller_->Update(dt);
    if (player_ && play_start_s_ >= 0) {
      const double t = opt_.frames > 0 ? frame / player_->path().fps : now - play_start_s_;
      if (auto v = player_->At(t)) {
        controller_->SetPose(v->cam_from_world);
      } else {
        play_start_s_ = -1;
      }
    }
    if (recorder_.recording())
      recorder_.Add(now, {"frame", camera_, controller_->cam_from_world()});
    DrawUi();
    Load();
    RenderIfNeeded(fw, fh);
    Blit(fw, fh);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ++frame;
    if (opt_.frames > 0 && frame >= opt_.frames && !opt_.window_screenshot.empty()) {
      cv::Mat rgb(fh, fw, CV_8UC3);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadBuffer(GL_BACK);
      glReadPixels(0, 0, fw, fh, GL_RGB, GL_UNSIGNED_BYTE, rgb.ptr());
      cv::Mat bgr;
      cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
      cv::flip(bgr, bgr, 0);  // GL rows start at the bottom
      WriteImage(opt_.window_screenshot, bgr);
      std::printf("window screenshot: %s\n", opt_.window_screenshot.c_str());
    }
    window_.SwapBuffers();
    if (opt_.frames > 0 && frame >= opt_.frames) break;
  }
  if (opt_.benchmark) Benchmark();
  if (!opt_.screenshot.empty() && !display_.empty()) Screenshot(opt_.screenshot);
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
  // The window size: the initial camera's (at most 1280 wide) unless given.
  int width = options.width, height = options.height;
  if (width <= 0 || height <= 0) {
    const Scene scene = LoadWorkspace(options.workspace);
    if (scene.photos.empty()) throw InputError(options.workspace, "the workspace has no photos");
    const View v = options.camera.empty() ? ParseCameraSpec(scene.photos[0].name, scene)
                                          : ParseCameraSpec(options.camera, scene);
    width = v.camera.width;
    height = v.camera.height;
    if (width > 1280) {
      height = height * 1280 / width;
      width = 1280;
    }
  }
  gl::WindowContext window(width, height, "hdribr view " + options.workspace.string(),
                           !options.hidden);
  glfwSwapInterval(options.frames > 0 ? 0 : 1);
  ViewerApp app(options, window);
  return app.Run();
}

}  // namespace hdribr::viewer
