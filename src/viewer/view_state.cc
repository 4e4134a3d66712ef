#include "viewer/view_state.h"

#include "io/radiometric_calibration.h"

#include "core/error.h"
#include "render/hdr_photo_set.h"
#include "viewer/viewer_options.h"

namespace hdribr::viewer {
namespace {

struct DisplayModeInfo {
  DisplayMode value;
  const char* name;   // --display
  const char* label;  // panel combo
};
constexpr DisplayModeInfo kDisplayModes[kDisplayModeCount] = {
    {DisplayMode::kFinal, "final", "final"},
    {DisplayMode::kDepth, "depth", "depth"},
    {DisplayMode::kNormals, "normals", "normals"},
    {DisplayMode::kClasses, "classes", "front/back classes"},
    {DisplayMode::kCount, "count", "contributing count"},
    {DisplayMode::kPointColours, "splats", "colour-per-point splats"},
    {DisplayMode::kNearestPhoto, "nearest", "nearest photo"},
};

struct HdrSourceInfo {
  HdrSource value;
  const char* name;   // --hdr
  const char* label;  // panel combo
};
constexpr HdrSourceInfo kHdrSources[] = {
    {HdrSource::kAuto, "auto", nullptr},
    {HdrSource::kLdr, "ldr", "ldr"},
    {HdrSource::kPrecomputed, "precomputed", "precomputed HDR"},
    {HdrSource::kOnTheFly, "onthefly", "on-the-fly HDR"},
    {HdrSource::kDirect, "direct", "direct radiance"},
};

// '\0'-separated labels, as ImGui::Combo takes them.
template <typename Table>
std::string ComboItems(const Table& table) {
  std::string items;
  for (const auto& entry : table) {
    if (entry.label == nullptr) continue;
    items += entry.label;
    items.push_back('\0');
  }
  return items;
}

// (name, value) pairs of a table, in its order.
template <typename Table>
auto NameList(const Table& table) {
  std::vector<std::pair<std::string, decltype(table[0].value)>> names;
  for (const auto& entry : table) names.emplace_back(entry.name, entry.value);
  return names;
}

}  // namespace

const std::vector<std::pair<std::string, DisplayMode>>& DisplayModeNames() {
  static const auto* names = new auto(NameList(kDisplayModes));
  return *names;
}

const std::vector<std::pair<std::string, HdrSource>>& HdrSourceNames() {
  static const auto* names = new auto(NameList(kHdrSources));
  return *names;
}

std::string DisplayModeName(DisplayMode mode) { return kDisplayModes[static_cast<int>(mode)].name; }

std::string HdrSourceName(HdrSource source) { return kHdrSources[static_cast<int>(source)].name; }

const char* DisplayModeCombo() {
  static const std::string items = ComboItems(kDisplayModes);
  return items.c_str();
}

const char* HdrSourceCombo() {
  static const std::string items = ComboItems(kHdrSources);
  return items.c_str();
}

HdrSource ResolveHdrSource(HdrSource source, const std::filesystem::path& workspace) {
  if (source != HdrSource::kAuto) return source;
  const bool has_set =
      std::filesystem::exists(workspace / render::kHdrSetFolder / render::kHdrSetIndex);
  if (has_set) return HdrSource::kPrecomputed;
  return std::filesystem::exists(workspace / kCalibFolder / kCalibResponse) ? HdrSource::kDirect
                                                                            : HdrSource::kLdr;
}

render::HdrMode HdrModeOf(HdrSource source) {
  switch (source) {
    case HdrSource::kPrecomputed:
      return render::HdrMode::kPrecomputed;
    case HdrSource::kOnTheFly:
      return render::HdrMode::kOnTheFly;
    case HdrSource::kDirect:
      return render::HdrMode::kDirect;
    case HdrSource::kAuto:
    case HdrSource::kLdr:
      break;
  }
  HDRIBR_CHECK(false);
  return render::HdrMode::kPrecomputed;
}

ViewState InitialViewState(const ViewerOptions& options, const Scene& scene) {
  ViewState state;
  Settings& s = state.settings;
  s.source = ResolveHdrSource(options.source, options.workspace);
  s.series = options.series;
  if (options.series >= static_cast<int>(scene.series.size())) {
    throw OptionError("series", std::to_string(options.series) + ": the workspace has " +
                                    std::to_string(scene.series.size()) + " series");
  }
  s.depth_mode = options.renderer.depth.mode;
  s.weights = options.renderer.blend.weights;
  s.k_best = options.renderer.blend.k_best;
  s.lambda = options.renderer.blend.lambda;
  s.tolerance = options.renderer.blend.occlusion_tolerance;
  s.background = options.renderer.blend.background;
  s.fill = options.renderer.blend.fill;
  s.sampling = options.renderer.blend.sampling;
  s.outlier_scale = options.renderer.blend.outlier_scale;
  s.refine_depth = options.renderer.blend.refine_depth;
  s.max_candidates = options.renderer.max_candidates;
  state.display = options.display;
  // LDR photos are already display-encoded: no curve, gamma 1 unless asked.
  const bool hdr = s.source != HdrSource::kLdr;
  state.tonemap.enabled = options.tonemap.value_or(hdr);
  state.tonemap.gamma = options.gamma.value_or(hdr ? 2.2f : 1.0f);
  state.tonemap.key = options.key;
  state.tonemap.smoothing = options.frames > 0 ? 0.0f : 0.9f;  // scripted frames: no history
  state.exposure_ev = options.exposure_ev;
  state.camera_curve = options.camera_curve && hdr;
  // Scripted frames are all at full quality unless a budget is asked for.
  state.frame_budget_ms =
      options.frame_budget_ms.value_or(options.frames > 0 ? 0.0 : kDefaultFrameBudgetMs);
  state.frustums = options.show_frustums;
  state.help = options.show_help;
  state.panel = !options.hide_panel;
  return state;
}

}  // namespace hdribr::viewer
