// The renderer's command-line options, bound in one place for every subcommand that renders:
// flag names, defaults (the option structs' own), help and checks.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <map>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "cli/cli_util.h"
#include "render/blend_options.h"
#include "render/depth_pass.h"
#include "render/renderer.h"

namespace hdribr::cli {

// --depth-mode NAME (or `flag`) into `mode` (names from render::DepthModeName).
CLI::Option* AddDepthModeOption(CLI::App& app, render::DepthMode& mode,
                                const std::string& flag = "--depth-mode");
// --silhouette-trim PX into `pixels` (render::DepthPassOptions::silhouette_trim, 0 = off).
CLI::Option* AddSilhouetteTrimOption(CLI::App& app, int& pixels);
// --raster NAME into `raster` (names from render::PointRasterName).
CLI::Option* AddPointRasterOption(CLI::App& app, render::PointRaster& raster);
// --weights, --k-best, --lambda, --tolerance, --background, --fill/--no-fill, --visibility,
// --filter, --sampling, --outlier-scale, --refine-depth into `blend` (--k-best only where `app`
// has none yet); CheckBlendOptions validates them.
void AddBlendOptions(CLI::App& app, render::BlendOptions& blend);
// --refine-depth into `refine_depth` (render::BlendOptions::refine_depth, 0 = off).
CLI::Option* AddRefineDepthOption(CLI::App& app, float& refine_depth);
// --background NAME into `background` (names from render::BackgroundName).
CLI::Option* AddBackgroundOption(CLI::App& app, render::Background& background);
// --max-photo-size PX into `max_photo_size` (0 = full size).
CLI::Option* AddMaxPhotoSizeOption(CLI::App& app, int& max_photo_size);
// --no-depth-cache into `off`: compute the photos' depth maps without the workspace's cache.
CLI::Option* AddNoDepthCacheOption(CLI::App& app, bool& off);
// --candidates N into `max_candidates` (0 = every active photo).
CLI::Option* AddCandidatesOption(CLI::App& app, int& max_candidates);
// --gpu-memory MB into `mb` (0 = from the device; render/photo_cache.h).
CLI::Option* AddGpuMemoryOption(CLI::App& app, double& mb);
// The five above on `options` (depth mode, blend options, photo size, candidates, GPU memory)
// and
// --no-depth-cache into `no_depth_cache` (for WorkspaceDepthCache once the workspace is known).
void AddRendererOptions(CLI::App& app, render::RendererOptions& options, bool& no_depth_cache);
// The renderer's depth_cache_dir for `workspace`: its cache folder (DepthMapCacheDir), or
// none when `off` (--no-depth-cache).
std::filesystem::path WorkspaceDepthCache(const std::filesystem::path& workspace, bool off);

// Field -> flag of the renderer options that the renderer itself checks (its OptionError), for
// RunNamingFlags around a command that builds a renderer.
const FlagNames& RendererFlags();

// Throws UsageError naming the flag of the first blend option that no blend can use
// (render::BlendOptionProblems); call before any work.
void CheckBlendOptions(const render::BlendOptions& blend);

// Name -> value for a CLI11 CheckedTransformer, from a name function over every value.
template <typename Enum, typename Values, typename NameOf>
std::map<std::string, Enum> NameMap(const Values& values, NameOf name_of) {
  std::map<std::string, Enum> map;
  for (Enum v : values) map.emplace(name_of(v), v);
  return map;
}

// Name -> value from a table of (name, value) pairs.
template <typename Enum>
std::map<std::string, Enum> EnumMap(const std::vector<std::pair<std::string, Enum>>& names) {
  return {names.begin(), names.end()};
}

// A CLI11 transformer from the names of `map` to their values (for an option bound to an
// enum); its help lists the names, its error says which ones exist.
template <typename Enum>
CLI::Validator NamesTo(const std::map<std::string, Enum>& map) {
  std::string names;
  for (const auto& entry : map) names += (names.empty() ? "" : ", ") + entry.first;
  return CLI::Validator(
      [map, names](std::string& value) -> std::string {
        const auto it = map.find(value);
        if (it == map.end()) return "must be one of " + names + ", got '" + value + "'";
        value = std::to_string(static_cast<std::underlying_type_t<Enum>>(it->second));
        return {};
      },
      "{" + names + "}");
}

}  // namespace hdribr::cli
