// `hdribr inspect WORKSPACE`: summary and validation of a workspace.
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "cli/render_options.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "io/workspace.h"
#include "render/renderer.h"

namespace hdribr::cli {
namespace {

struct InspectOptions {
  std::string workspace;
  bool json = false;
  bool gpu = false;          // --gpu: GPU memory the renderer needs
  int max_photo_size = 0;    // with --gpu
  double gpu_memory_mb = 0;  // with --gpu
};

std::string FormatExposure(const Exposure& e) {
  std::string s;
  char buf[64];
  if (e.time_s) {
    if (*e.time_s < 1.0) {
      std::snprintf(buf, sizeof(buf), "1/%.0f s", 1.0 / *e.time_s);
    } else {
      std::snprintf(buf, sizeof(buf), "%.3g s", *e.time_s);
    }
    s += buf;
  } else {
    s += "time ?";
  }
  std::snprintf(buf, sizeof(buf), " ISO %s f/%s", e.iso ? std::to_string(int(*e.iso)).c_str() : "?",
                e.f_number ? std::to_string(*e.f_number).substr(0, 4).c_str() : "?");
  return s + buf;
}

std::string Attributes(const PointCloud& pc) {
  std::string s;
  auto add = [&](bool has, const char* name) {
    if (!has) return;
    if (!s.empty()) s += ", ";
    s += name;
  };
  add(pc.HasNormals(), "normals");
  add(pc.HasColors(), "colours");
  add(pc.HasRadii(), "radii");
  return s.empty() ? "positions only" : s;
}

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// --gpu: builds the renderer (photos + per-photo depth maps on the GPU) and reports its memory.
nlohmann::json GpuReport(const Scene& scene, int max_photo_size, double gpu_memory_mb) {
  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  render::RendererOptions ro;
  ro.max_photo_size = max_photo_size;
  ro.gpu_memory_mb = gpu_memory_mb;
  const render::Renderer renderer(shaders, scene, ro);
  const render::PhotoResidency r = renderer.residency();
  return {{"gpu_bytes", r.resident_bytes},
          {"resident_bytes", r.resident_bytes},
          {"total_bytes", r.total_bytes},
          {"budget_bytes", r.budget_bytes},
          {"depth_bytes", r.depth_bytes},
          {"cached", r.cached},
          {"full_size_slots", r.slots},
          {"reduced_slots", r.reduced_slots},
          {"fallback_divisor", r.fallback_divisor},
          {"depth_slots", r.depth_slots},
          {"max_photo_size", max_photo_size},
          {"renderer", context.Renderer()}};
}

int Run(const InspectOptions& opt) {
  const WorkspaceLayout layout = DetectWorkspace(opt.workspace);
  const Scene scene = LoadWorkspace(opt.workspace);
  const std::vector<std::string> problems = ValidateScene(scene);
  nlohmann::json gpu;
  if (opt.gpu && problems.empty()) {
    gpu = GpuReport(scene, opt.max_photo_size, opt.gpu_memory_mb);
  }

  if (opt.json) {
    nlohmann::json j;
    j["workspace"] = scene.workspace.string();
    j["layout"] = layout.kind;
    j["cameras"] = nlohmann::json::array();
    for (const auto& [id, c] : scene.cameras) {
      j["cameras"].push_back({{"id", id},
                              {"model", CameraModelName(c.model)},
                              {"width", c.width},
                              {"height", c.height},
                              {"params", c.params}});
    }
    j["series"] = nlohmann::json::array();
    for (const auto& s : scene.series) {
      nlohmann::json names = nlohmann::json::array();
      for (int i : s.photo_indices) names.push_back(scene.photos[i].name);
      j["series"].push_back({{"name", s.name},
                             {"relative_exposure", s.relative_exposure},
                             {"ev", std::log2(s.relative_exposure)},
                             {"photos", names}});
    }
    j["num_photos"] = scene.photos.size();
    j["points"] = {{"count", scene.points.size()},
                   {"normals", scene.points.HasNormals()},
                   {"colors", scene.points.HasColors()},
                   {"radii", scene.points.HasRadii()}};
    if (scene.point_bounds.valid) {
      j["bounds"] = {{"min", Vec(scene.point_bounds.min)}, {"max", Vec(scene.point_bounds.max)}};
    }
    j["centroid"] = Vec(scene.centroid);
    j["scene_scale"] = scene.scene_scale;
    j["problems"] = problems;
    if (!gpu.is_null()) j["gpu"] = gpu;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("workspace    %s (%s layout)\n", scene.workspace.c_str(), layout.kind.c_str());
    std::printf("cameras      %zu\n", scene.cameras.size());
    for (const auto& [id, c] : scene.cameras) {
      std::printf("  camera %-4d %s %dx%d  fx %.1f fy %.1f cx %.1f cy %.1f  (fov %.1f deg)\n", id,
                  CameraModelName(c.model).c_str(), c.width, c.height, c.fx(), c.fy(), c.cx(),
                  c.cy(), c.FovX() * 180.0 / M_PI);
    }
    std::printf("photos       %zu in %zu exposure series\n", scene.photos.size(),
                scene.series.size());
    for (const auto& s : scene.series) {
      const Photo& first = scene.photos[s.photo_indices.front()];
      std::printf("  %-10s %3zu photos  relative exposure %.4g (%+.2f EV)  e.g. %s: %s\n",
                  s.name.c_str(), s.photo_indices.size(), s.relative_exposure,
                  std::log2(s.relative_exposure), first.name.c_str(),
                  FormatExposure(first.exposure).c_str());
    }
    std::printf("points       %zu (%s)\n", scene.points.size(), Attributes(scene.points).c_str());
    if (scene.point_bounds.valid) {
      const auto& b = scene.point_bounds;
      std::printf("bounds       (%.3f, %.3f, %.3f) .. (%.3f, %.3f, %.3f)  diagonal %.3f\n",
                  b.min.x(), b.min.y(), b.min.z(), b.max.x(), b.max.y(), b.max.z(), b.Diagonal());
    }
    std::printf(
        "scene scale  %.4f (median camera-to-centroid distance; unit of relative "
        "thresholds)\n",
        scene.scene_scale);
    if (!gpu.is_null()) {
      std::printf(
          "gpu memory   %.2f MiB resident of %.2f MiB (photo textures + depth maps, the depth maps "
          "%.2f MiB; max "
          "photo size %s; budget %.2f MiB; %s)\n",
          gpu["resident_bytes"].get<size_t>() / 1048576.0,
          gpu["total_bytes"].get<size_t>() / 1048576.0,
          gpu["depth_bytes"].get<size_t>() / 1048576.0,
          opt.max_photo_size > 0 ? std::to_string(opt.max_photo_size).c_str() : "full",
          gpu["budget_bytes"].get<size_t>() / 1048576.0,
          gpu["renderer"].get<std::string>().c_str());
      if (gpu["cached"].get<bool>()) {
        const int depth_slots = gpu["depth_slots"].get<int>();
        const std::string depth =
            depth_slots > 0 ? std::to_string(depth_slots) + " slots" : "all resident";
        std::printf(
            "photo cache  %d full-size slots, %d reduced slots (mip levels 1 or 2 on), coarse "
            "copies at 1/%d size, depth maps %s\n",
            gpu["full_size_slots"].get<int>(), gpu["reduced_slots"].get<int>(),
            gpu["fallback_divisor"].get<int>(), depth.c_str());
      }
    }
    std::printf("problems     %zu\n", problems.size());
  }
  for (const auto& p : problems) std::fprintf(stderr, "problem: %s\n", p.c_str());
  return problems.empty() ? 0 : 1;
}

}  // namespace

CommandRunner SetupInspect(CLI::App& sub);
HDRIBR_COMMAND(inspect, "Summarise and validate a workspace", SetupInspect, 20);

CommandRunner SetupInspect(CLI::App& sub) {
  auto opt = std::make_shared<InspectOptions>();
  sub.add_option("workspace", opt->workspace, "Workspace folder")->required();
  sub.add_flag("--json", opt->json, "Print JSON instead of text");
  sub.add_flag("--gpu", opt->gpu, "Also load the photos on the GPU and report the memory used");
  AddMaxPhotoSizeOption(sub, opt->max_photo_size);
  AddGpuMemoryOption(sub, opt->gpu_memory_mb);
  return [opt] { return RunNamingFlags(RendererFlags(), [&] { return Run(*opt); }); };
}

}  // namespace hdribr::cli
