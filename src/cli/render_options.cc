#include "cli/render_options.h"

#include <climits>
#include <cstdio>
#include <string>

#include "cli/cli_util.h"
#include "core/error.h"
#include "io/depth_map_cache.h"

namespace hdribr::cli {

CLI::Option* AddDepthModeOption(CLI::App& app, render::DepthMode& mode, const std::string& flag) {
  return app.add_option(flag, mode, "Depth pass: plain, marroquim or lechelek (the paper)")
      ->transform(
          NamesTo(NameMap<render::DepthMode>(render::AllDepthModes(), render::DepthModeName)))
      ->default_str(render::DepthModeName(mode));
}

CLI::Option* AddSilhouetteTrimOption(CLI::App& app, int& pixels) {
  return app
      .add_option("--silhouette-trim", pixels,
                  "Lechelek depth: window (pixels each side) of the silhouette trim that gives "
                  "the splats' overhang past a silhouette to the farther surface (0 = off)")
      ->capture_default_str()
      ->check(CLI::Range(0, 8));
}

CLI::Option* AddPointRasterOption(CLI::App& app, render::PointRaster& raster) {
  return app
      .add_option("--raster", raster,
                  "How points are rasterised: compute (shaders with atomics) or pipeline "
                  "(GL_POINTS sprites)")
      ->transform(
          NamesTo(NameMap<render::PointRaster>(render::kAllPointRasters, render::PointRasterName)))
      ->default_str(render::PointRasterName(raster));
}

void AddBlendOptions(CLI::App& app, render::BlendOptions& blend) {
  app.add_option("--weights", blend.weights,
                 "Blending weights: ulr (Unstructured Lumigraph, K best) or paper (eq. 5, all)")
      ->transform(NamesTo(
          NameMap<render::BlendWeights>(render::kAllBlendWeights, render::BlendWeightsName)))
      ->default_str(render::BlendWeightsName(blend.weights));
  // A subcommand that binds its own --k-best (bench render's list) keeps it.
  if (app.get_option_no_throw("--k-best") == nullptr) {
    app.add_option("--k-best", blend.k_best,
                   "K best photos per pixel (0: " + std::to_string(render::kDefaultUnstructuredK) +
                       " for ulr, all for paper; at most " + std::to_string(render::kMaxKBest) +
                       ")")
        ->capture_default_str();
  }
  app.add_option("--lambda", blend.lambda, "Grazing-angle threshold on N . V_k, in [0, 1)")
      ->capture_default_str();
  app.add_option("--tolerance", blend.occlusion_tolerance,
                 "Occlusion test: relative depth tolerance, in (0, 1)")
      ->capture_default_str();
  AddBackgroundOption(app, blend.background);
  app.add_flag("--fill,!--no-fill", blend.fill,
               "Pixels that no photo shows (past every photo's frame) take the pull-push "
               "interpolation of those around them, marked as filled (--no-fill: left empty)")
      ->default_str(blend.fill ? "true" : "false");
  app.add_option("--visibility", blend.visibility,
                 "Occlusion test: hard (visible when one of the 2x2 depth texels agrees) or soft "
                 "(weighted by the share that agree)")
      ->transform(NamesTo(std::map<std::string, render::Visibility>{
          {"hard", render::Visibility::kHard}, {"soft", render::Visibility::kSoft}}))
      ->default_str(blend.visibility == render::Visibility::kSoft ? "soft" : "hard");
  app.add_option("--filter", blend.filter,
                 "Filtered blending (Eisemann et al. 2007): relative depth uncertainty over "
                 "which each photo is low-passed along its line of disparity (0 = off)")
      ->capture_default_str();
  app.add_option("--sampling", blend.sampling,
                 "Photo sampling: linear (trilinear) or cubic (Catmull-Rom at full resolution)")
      ->transform(NamesTo(
          NameMap<render::PhotoSampling>(render::kAllPhotoSamplings, render::PhotoSamplingName)))
      ->default_str(render::PhotoSamplingName(blend.sampling));
  app.add_option("--outlier-scale", blend.outlier_scale,
                 "Photometric outlier rejection: colour distance (1 = white) from the weighted "
                 "mean at which a ranked photo's weight halves (0 = off)")
      ->capture_default_str();
  AddRefineDepthOption(app, blend.refine_depth);
}

CLI::Option* AddRefineDepthOption(CLI::App& app, float& refine_depth) {
  return app
      .add_option("--refine-depth", refine_depth,
                  "Photo-consistent depth: relative half-range of view depths, about the depth "
                  "pass's, among which each pixel takes the one where its photos agree best "
                  "(0 = off)")
      ->capture_default_str();
}

CLI::Option* AddBackgroundOption(CLI::App& app, render::Background& background) {
  return app
      .add_option("--background", background,
                  "Where no point is: plane (the scene's dominant plane where it holds points, "
                  "else the sphere), sphere (around the points and the cameras), infinity (the "
                  "photos' pixels in the ray's direction) or none (left empty)")
      ->transform(
          NamesTo(NameMap<render::Background>(render::kAllBackgrounds, render::BackgroundName)))
      ->default_str(render::BackgroundName(background));
}

CLI::Option* AddMaxPhotoSizeOption(CLI::App& app, int& max_photo_size) {
  return app
      .add_option("--max-photo-size", max_photo_size,
                  "Longest side of photos on the GPU (0 = full size)")
      ->capture_default_str()
      ->check(kAtLeastZero);
}

CLI::Option* AddNoDepthCacheOption(CLI::App& app, bool& off) {
  return app.add_flag("--no-depth-cache", off,
                      "Compute the photos' depth maps instead of reusing them from (and storing "
                      "them in) " +
                          DepthMapCacheDir("WORKSPACE").string());
}

CLI::Option* AddCandidatesOption(CLI::App& app, int& max_candidates) {
  return app
      .add_option("--candidates", max_candidates,
                  "Most candidate photos per frame: the blend uses only the active photos that "
                  "can matter for the view, at most N (0 = every active photo)")
      ->capture_default_str()
      ->check(kAtLeastZero);
}

CLI::Option* AddGpuMemoryOption(CLI::App& app, double& mb) {
  char default_mb[32];
  std::snprintf(default_mb, sizeof(default_mb), "%.0f", render::kDefaultGpuMemoryMb);
  return app
      .add_option("--gpu-memory", mb,
                  "GPU memory budget of the photos and their depth maps, MiB: beyond it the "
                  "photos are cached (coarse copies of all, the view's candidates at full "
                  "size); 0 = three quarters of the free video memory the driver reports, else " +
                      std::string(default_mb))
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
}

void AddRendererOptions(CLI::App& app, render::RendererOptions& options, bool& no_depth_cache) {
  AddDepthModeOption(app, options.depth.mode);
  AddSilhouetteTrimOption(app, options.depth.silhouette_trim);
  AddBlendOptions(app, options.blend);
  AddMaxPhotoSizeOption(app, options.max_photo_size);
  AddCandidatesOption(app, options.max_candidates);
  AddGpuMemoryOption(app, options.gpu_memory_mb);
  AddNoDepthCacheOption(app, no_depth_cache);
}

std::filesystem::path WorkspaceDepthCache(const std::filesystem::path& workspace, bool off) {
  return off ? std::filesystem::path() : DepthMapCacheDir(workspace);
}

const FlagNames& RendererFlags() {
  static const FlagNames flags = {{"gpu_memory_mb", "--gpu-memory"},
                                  {"max_candidates", "--candidates"}};
  return flags;
}

void CheckBlendOptions(const render::BlendOptions& blend) {
  static const FlagNames kFlags = {{"k_best", "--k-best"},
                                   {"lambda", "--lambda"},
                                   {"occlusion_tolerance", "--tolerance"},
                                   {"filter", "--filter"},
                                   {"outlier_scale", "--outlier-scale"},
                                   {"refine_depth", "--refine-depth"}};
  RunNamingFlags(kFlags, [&] {
    render::ValidateBlendOptions(blend);
    return 0;
  });
}

}  // namespace hdribr::cli
