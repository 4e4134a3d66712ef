#include "viewer/panel.h"

#include <imgui.h>

#include <string>

#include "viewer/false_colour_pass.h"

namespace hdribr::viewer {
namespace {

// Every key of the viewer, for the help overlay and docs/usage/view.md.
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
    {"F", "input camera frustums (3D, hidden by the scene; candidates green) on / off"},
    {"P", "screenshot (PNG tone-mapped + EXR linear)"},
    {"R", "start / stop recording a camera path"},
    {"L", "play the recorded (or --play) path"},
    {"U", "control panel on / off"},
    {"H", "this help"},
    {"Esc", "quit"},
};

// One line under the display combo saying how to read the current display mode.
void DrawLegend(const ViewState& state, const PanelInfo& info) {
  switch (state.display) {
    case DisplayMode::kDepth:
      ImGui::TextUnformatted("depth: near red ... far blue (turbo over the visible range)");
      break;
    case DisplayMode::kNormals:
      ImGui::TextUnformatted("normals: RGB = camera-space (x, y, z) / 2 + 1/2");
      break;
    case DisplayMode::kCount:
      ImGui::Text("count: 0 blue ... %zu photos red", info.scene->photos.size());
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
      ImGui::TextUnformatted(info.point_colours_known
                                 ? "splats: one colour per point (the cloud's), no blending"
                                 : "splats: the cloud has no colours (grey)");
      break;
    default:
      break;
  }
}

void DrawToneMapping(ViewState& state, const FrameStats& stats, bool camera_curve) {
  bool changed = false;
  changed |= ImGui::SliderFloat("exposure (EV)", &state.exposure_ev, -8, 8, "%.2f");
  changed |= ImGui::SliderFloat("key", &state.tonemap.key, 0.01f, 1.0f, "%.3f");
  changed |= ImGui::SliderFloat("gamma", &state.tonemap.gamma, 1.0f, 3.0f, "%.2f");
  changed |= ImGui::Checkbox("tone mapping (Reinhard)", &state.tonemap.enabled);
  if (camera_curve) {
    changed |= ImGui::Checkbox("camera's response (EV 0 = median photo)", &state.camera_curve);
  }
  if (ImGui::Checkbox("auto L_a", &state.auto_la)) {
    state.fixed_la = stats.last_la;
    changed = true;
  }
  if (!state.auto_la) {
    changed |= ImGui::SliderFloat("fixed L_a", &state.fixed_la, 1e-4f, 100.0f, "%.4g",
                                  ImGuiSliderFlags_Logarithmic);
  }
  if (changed) state.tone_changed = true;
}

// Combo over an enum whose values are 0, 1, ... in item order, plus `offset`.
template <typename Enum>
void EnumCombo(const char* label, Enum& value, const char* items, int offset = 0) {
  int i = static_cast<int>(value) - offset;
  if (ImGui::Combo(label, &i, items)) value = static_cast<Enum>(i + offset);
}

void DrawSettings(ViewState& state, const Scene& scene) {
  Settings& s = state.settings;
  // The source combo lists the resolved sources: HdrSource::kLdr first.
  EnumCombo("source", s.source, HdrSourceCombo(), static_cast<int>(HdrSource::kLdr));
  if (s.source == HdrSource::kLdr) {
    int i = s.series + 1;
    std::string items = "all series";
    items.push_back('\0');
    for (const ExposureSeries& es : scene.series) {
      items += es.name;
      items.push_back('\0');
    }
    if (ImGui::Combo("series", &i, items.c_str())) s.series = i - 1;
  }
  EnumCombo("depth", s.depth_mode, "plain\0marroquim\0lechelek\0");
  EnumCombo("weights", s.weights, "paper (eq. 5)\0unstructured lumigraph\0");
  ImGui::SliderInt(s.weights == render::BlendWeights::kPaper ? "K best (0 = all)" : "K (0 = 4)",
                   &s.k_best, 0, 16);
  ImGui::SliderInt("candidates (0 = all)", &s.max_candidates, 0, 64);
  ImGui::SliderFloat("lambda", &s.lambda, 0.0f, 0.5f, "%.4f");
  ImGui::SliderFloat("occlusion tol.", &s.tolerance, 0.001f, 0.1f, "%.3f",
                     ImGuiSliderFlags_Logarithmic);
  EnumCombo("background", s.background, "none\0infinity\0sphere\0plane\0");
  ImGui::Checkbox("fill what no photo shows", &s.fill);
  EnumCombo("sampling", s.sampling, "linear\0cubic\0");
  ImGui::SliderFloat("outlier scale (0 = off)", &s.outlier_scale, 0.0f, 0.5f, "%.3f");
  ImGui::SliderFloat("refine depth (0 = off)", &s.refine_depth, 0.0f, render::kMaxRefineDepth,
                     "%.4f");
  int mode = static_cast<int>(state.display);
  if (ImGui::Combo("display", &mode, DisplayModeCombo())) {
    state.SetDisplay(static_cast<DisplayMode>(mode));
  }
}

void DrawPanel(ViewState& state, const PanelInfo& info) {
  const FrameStats& stats = *info.stats;
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.75f);
  ImGui::Begin("hdribr", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::Text("%.1f fps   render %.1f ms (depth %.1f + blend %.1f + fill %.1f GPU)", info.fps,
              stats.render_wall_ms, stats.render_gpu.depth_ms, stats.render_gpu.blend_ms,
              stats.render_gpu.fill_ms);
  ImGui::Text("tone map %.2f ms (GPU %.2f)   L_a %.4g", stats.tonemap_wall_ms, stats.tonemap_gpu_ms,
              stats.last_la);
  ImGui::Text("candidates %d of %d photos (chosen in %.2f ms)", stats.candidates, stats.active,
              stats.candidates_ms);
  if (stats.scale < 1) {
    ImGui::Text("moving: %.0f%% of the size, full quality once still", 100 * stats.scale);
  } else {
    ImGui::TextUnformatted("full quality");
  }
  const render::PhotoResidency& gpu = stats.residency;
  if (gpu.cached) {
    ImGui::Text(
        "GPU memory %.0f of %.0f MiB (budget %.0f): %d of %d photos at full size, %d "
        "from a coarser level%s",
        gpu.resident_bytes / 1048576.0, gpu.total_bytes / 1048576.0, gpu.budget_bytes / 1048576.0,
        gpu.full_size, gpu.photos, gpu.reduced, gpu.pending > 0 ? ", loading" : "");
  } else {
    ImGui::Text("GPU memory %.0f MiB, every photo resident", gpu.resident_bytes / 1048576.0);
  }
  float budget = static_cast<float>(state.frame_budget_ms);
  if (ImGui::SliderFloat("frame budget (ms, 0 = off)", &budget, 0, 1000, "%.0f")) {
    state.frame_budget_ms = budget;
  }
  DrawToneMapping(state, stats, info.camera_curve);
  ImGui::Separator();
  DrawSettings(state, *info.scene);
  DrawLegend(state, info);
  ImGui::Checkbox("camera frustums", &state.frustums);
  ImGui::Text("%s", info.recording ? "RECORDING (R to stop)" : state.status.c_str());
  ImGui::End();
}

}  // namespace

void DrawUi(ViewState& state, const PanelInfo& info) {
  if (state.panel) DrawPanel(state, info);
  if (state.help) {
    ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x * 0.5f, 40), ImGuiCond_Always,
                            ImVec2(0.5f, 0));
    ImGui::Begin("keys (H)", &state.help, ImGuiWindowFlags_AlwaysAutoResize);
    for (const auto& k : kHelp) ImGui::Text("%-16s %s", k[0], k[1]);
    ImGui::End();
  }
}

}  // namespace hdribr::viewer
