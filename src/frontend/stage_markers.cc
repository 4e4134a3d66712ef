#include "frontend/stage_markers.h"

#include <fmt/format.h>

#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "core/hash.h"
#include "frontend/point_attributes.h"

namespace hdribr {
namespace fs = std::filesystem;

namespace {

// The dense methods a setting belongs to.
enum DenseModes : unsigned { kAnyMode = ~0u, kPatchMatchMode = 1u, kSweepMode = 2u };

unsigned ModeBit(const std::string& mode) {
  if (mode == "cpu") return kPatchMatchMode;
  if (mode == "sweep") return kSweepMode;
  return 0;
}

// One setting of a marker: its stage, its name, the dense methods it applies to (dense stage),
// and its value.
struct SettingField {
  const char* stage;
  const char* name;
  unsigned modes;
  std::string (*value)(const StageInputs&);
};

template <typename T>
std::string Text(const T& value) {
  return fmt::format("{}", value);
}
template <auto kMember>
std::string Option(const StageInputs& in) {
  return Text(in.options.*kMember);
}
template <auto kMember>
std::string Dense(const StageInputs& in) {
  return Text(in.options.dense_options.*kMember);
}
template <auto kMember>
std::string PatchMatch(const StageInputs& in) {
  return Text(in.options.dense_options.patch_match.*kMember);
}
template <auto kMember>
std::string Attribute(const StageInputs& in) {
  return Text(in.options.attribute_options.*kMember);
}

// The photo set: names and file sizes, so that added, removed or replaced photos redo it.
std::string PhotoSet(const StageInputs& in) {
  Fnv1a64 photos;
  for (const InputPhoto& p : in.photos) {
    std::error_code ec;
    photos.AddString(p.name).Add(
        static_cast<std::uint64_t>(fs::file_size(in.options.photos / p.name, ec)));
  }
  return fmt::format("{} ({:016x})", in.photos.size(), photos.value());
}

using PM = PatchMatchOptions;
using DO = DenseOptions;
using AO = AttributeOptions;
using RO = ReconstructOptions;

// Every setting, in marker order.
constexpr SettingField kSettings[] = {
    {"features", "photos", kAnyMode, PhotoSet},
    {"features", "camera-model", kAnyMode, Option<&RO::camera_model>},
    {"features", "max-features", kAnyMode, Option<&RO::max_features>},
    {"features", "sift-size", kAnyMode, Option<&RO::sift_max_size>},
    {"matching", "matching", kAnyMode, [](const StageInputs& in) { return in.matching; }},
    {"matching", "vocab-tree", kAnyMode,
     [](const StageInputs& in) { return in.options.vocab_tree.string(); }},
    {"undistortion", "image-size", kAnyMode, Option<&RO::undistort_max_size>},
    {"dense", "dense", kAnyMode, [](const StageInputs& in) { return in.dense_mode; }},
    {"dense", "outlier-neighbors", kAnyMode, Attribute<&AO::outlier_neighbors>},
    {"dense", "outlier-stddev", kAnyMode, Attribute<&AO::outlier_stddev>},
    {"dense", "cleanup-version", kAnyMode,
     [](const StageInputs&) { return Text(kCleanupVersion); }},
    {"dense", "normal-neighbors", kAnyMode, Attribute<&AO::normal_neighbors>},
    {"dense", "radius-neighbors", kAnyMode, Attribute<&AO::radius_neighbors>},
    {"dense", "dense-version", kPatchMatchMode | kSweepMode,
     [](const StageInputs&) { return Text(kDenseVersion); }},
    {"dense", "dense-size", kPatchMatchMode | kSweepMode,
     [](const StageInputs& in) {
       const int size = in.options.dense_options.max_size;
       return size > 0 ? std::to_string(size) : std::string("auto");
     }},
    {"dense", "dense-neighbors", kPatchMatchMode | kSweepMode, Dense<&DO::num_neighbors>},
    {"dense", "fusion-consistency", kPatchMatchMode | kSweepMode, Dense<&DO::consistency>},
    {"dense", "fusion-min-consistent", kPatchMatchMode | kSweepMode, Dense<&DO::min_consistent>},
    {"dense", "fusion-single-ncc", kPatchMatchMode | kSweepMode, Dense<&DO::single_agreement_ncc>},
    {"dense", "fusion-max-normal-error", kPatchMatchMode | kSweepMode,
     Dense<&DO::max_normal_error>},
    {"dense", "dense-depths", kSweepMode, Dense<&DO::num_depths>},
    {"dense", "sweep-window-radius", kSweepMode, Dense<&DO::window_radius>},
    {"dense", "sweep-min-ncc", kSweepMode, Dense<&DO::min_ncc>},
    {"dense", "window-radius", kPatchMatchMode, PatchMatch<&PM::window_radius>},
    {"dense", "window-step", kPatchMatchMode, PatchMatch<&PM::window_step>},
    {"dense", "sigma-color", kPatchMatchMode, PatchMatch<&PM::sigma_color>},
    {"dense", "dense-levels", kPatchMatchMode, PatchMatch<&PM::num_levels>},
    {"dense", "coarse-iterations", kPatchMatchMode, PatchMatch<&PM::coarse_iterations>},
    {"dense", "dense-iterations", kPatchMatchMode, PatchMatch<&PM::iterations>},
    {"dense", "dense-geom-iterations", kPatchMatchMode, PatchMatch<&PM::geom_iterations>},
    {"dense", "geom-weight", kPatchMatchMode, PatchMatch<&PM::geom_weight>},
    {"dense", "geom-max-error", kPatchMatchMode, PatchMatch<&PM::geom_max_error>},
    {"dense", "best-views", kPatchMatchMode, PatchMatch<&PM::best_views>},
    {"dense", "dense-min-ncc", kPatchMatchMode, PatchMatch<&PM::min_ncc>},
    {"dense", "min-texture", kPatchMatchMode, PatchMatch<&PM::min_texture>},
    {"dense", "seed-radius", kPatchMatchMode, PatchMatch<&PM::seed_radius>},
    {"dense", "coarse-fill", kPatchMatchMode, PatchMatch<&PM::coarse_fill>},
};

std::map<std::string, std::string> ParseSettings(const std::string& text) {
  std::map<std::string, std::string> m;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const size_t eq = line.find('=');
    if (eq != std::string::npos) m[line.substr(0, eq)] = line.substr(eq + 1);
  }
  return m;
}

}  // namespace

std::string StageSettings(const StageInputs& inputs, const std::string& stage) {
  const unsigned mode = ModeBit(inputs.dense_mode);
  std::string s;
  for (const SettingField& field : kSettings) {
    if (stage != field.stage || (field.modes != kAnyMode && !(field.modes & mode))) continue;
    s += fmt::format("{}={}\n", field.name, field.value(inputs));
  }
  return s;
}

bool MarkerCurrent(const std::string& marker, const std::string& now) {
  return marker.empty() || marker == now;
}

std::string ChangedSettings(const std::string& before, const std::string& now) {
  const auto a = ParseSettings(before), b = ParseSettings(now);
  std::set<std::string> names;
  for (const auto& [k, v] : a) names.insert(k);
  for (const auto& [k, v] : b) names.insert(k);
  std::string out;
  for (const auto& name : names) {
    const auto ia = a.find(name), ib = b.find(name);
    const std::string va = ia == a.end() ? "(none)" : ia->second;
    const std::string vb = ib == b.end() ? "(none)" : ib->second;
    if (va != vb) out += (out.empty() ? "" : ", ") + name + " " + va + " -> " + vb;
  }
  return out;
}

}  // namespace hdribr
