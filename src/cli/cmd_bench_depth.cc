// `hdribr bench depth`: speed of the splat depth pass per mode, size and cloud size: GPU time
// of each step (timer queries) and wall time per frame, on generated clouds.
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli/bench_cloud.h"
#include "cli/cli_util.h"
#include "cli/command.h"
#include "core/error.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "render/depth_pass.h"

namespace hdribr::cli {
namespace {

struct BenchDepthOptions {
  std::string sizes = "512x512,1920x1080";
  std::string points = "100000,1000000,4000000";
  std::string modes = "plain,marroquim,lechelek";
  std::string rasters = "compute,pipeline";
  int frames = 3;
  double detail = 1.0;  // DepthPass::Process's detail (a reduced preview below 1)
  std::string json;
};

int Run(const BenchDepthOptions& opt) {
  if (opt.frames < 1) throw UsageError("--frames must be >= 1");
  if (!(opt.detail > 0 && opt.detail <= 1)) throw UsageError("--detail must be in (0, 1]");
  std::vector<std::pair<int, int>> sizes;
  for (const auto& s : SplitList(opt.sizes)) {
    const cv::Size size = ParseSize(s, "--sizes");
    sizes.emplace_back(size.width, size.height);
  }
  std::vector<size_t> counts;
  for (const auto& s : SplitList(opt.points)) {
    try {
      const long long v = std::stoll(s);
      if (v <= 0) throw std::invalid_argument("");
      counts.push_back(static_cast<size_t>(v));
    } catch (const std::exception&) {
      throw UsageError("--points: bad count '" + s + "'");
    }
  }
  std::vector<render::DepthMode> modes;
  for (const auto& s : SplitList(opt.modes)) modes.push_back(render::ParseDepthMode(s));
  std::vector<render::PointRaster> rasters;
  for (const auto& s : SplitList(opt.rasters)) rasters.push_back(render::ParsePointRaster(s));

  gl::HeadlessContext context;
  spdlog::info("OpenGL {} on {} (EGL {} platform)", context.Version(), context.Renderer(),
               context.platform());
  const gl::ShaderLibrary shaders;
  render::DepthPass pass(shaders);
  nlohmann::json results = nlohmann::json::array();
  const Rigid3d cam_from_world = LookAt(Eigen::Vector3d(0.0, -2.0, -4.5),
                                        Eigen::Vector3d(0.0, -0.5, 0.5), Eigen::Vector3d(0, -1, 0));
  for (size_t n : counts) {
    pass.SetPoints(MakeBenchCloud(n, DepthBenchScene()));
    for (const auto& [w, h] : sizes) {
      const double f = 0.5 * w / std::tan(M_PI / 6.0);
      const Camera cam = Camera::Pinhole(1, w, h, f, f, 0.5 * w, 0.5 * h);
      render::DepthTarget target = render::DepthTarget::Create(w, h);
      for (render::PointRaster raster : rasters)
        for (render::DepthMode mode : modes) {
          pass.options().mode = mode;
          pass.options().raster = raster;
          // Warm-up (allocation, shader compilation of the driver), then wall time per frame
          // without queries, then per-step GPU times with queries.
          pass.options().profile = false;
          pass.Process(cam, cam_from_world, target, opt.detail);
          glFinish();
          const auto t0 = std::chrono::steady_clock::now();
          for (int i = 0; i < opt.frames; ++i)
            pass.Process(cam, cam_from_world, target, opt.detail);
          glFinish();
          const double wall_ms =
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                  .count() /
              opt.frames;
          pass.options().profile = true;
          render::DepthStepTimes sum;
          for (int i = 0; i < opt.frames; ++i) {
            pass.Process(cam, cam_from_world, target, opt.detail);
            const auto& t = pass.last_times();
            for (int k = 0; k < render::DepthStepTimes::kSteps; ++k) {
              sum.gpu_ms[k] += t.gpu_ms[k] / opt.frames;
              sum.wall_ms[k] += t.wall_ms[k] / opt.frames;
            }
          }
          pass.options().profile = false;
          nlohmann::json gpu, step_wall;
          for (int k = 0; k < render::DepthStepTimes::kSteps; ++k) {
            gpu[render::DepthStepTimes::kNames[k]] = sum.gpu_ms[k];
            step_wall[render::DepthStepTimes::kNames[k]] = sum.wall_ms[k];
          }
          gpu["total"] = sum.gpu_total_ms();
          step_wall["total"] = sum.wall_total_ms();
          const size_t drawn = pass.last_point_count();
          const auto per_s = [&](double ms) { return static_cast<double>(drawn) / (ms * 1e-3); };
          nlohmann::json r = {
              {"mode", render::DepthModeName(mode)},
              {"raster", render::PointRasterName(raster)},
              {"width", w},
              {"height", h},
              {"points", n},
              {"detail", opt.detail},
              {"points_drawn", drawn},
              {"frames", opt.frames},
              {"wall_ms", wall_ms},
              {"gpu_ms", gpu},
              {"step_wall_ms", step_wall},
              {"points_per_s", per_s(wall_ms)},
          };
          if (sum.gpu_ms[0] > 0) r["splat_points_per_s_gpu"] = per_s(sum.gpu_ms[0]);
          if (sum.wall_ms[0] > 0) r["splat_points_per_s_wall"] = per_s(sum.wall_ms[0]);
          results.push_back(r);
          spdlog::info("{} ({} raster) {}x{} {} points ({} drawn): {:.1f} ms/frame",
                       render::DepthModeName(mode), render::PointRasterName(raster), w, h, n, drawn,
                       wall_ms);
        }
    }
  }
  // lechelek / marroquim wall-time ratio per raster, size and cloud.
  nlohmann::json ratios = nlohmann::json::array();
  for (const auto& a : results) {
    if (a["mode"] != "lechelek") continue;
    for (const auto& b : results) {
      if (b["mode"] == "marroquim" && b["raster"] == a["raster"] && b["width"] == a["width"] &&
          b["height"] == a["height"] && b["points"] == a["points"]) {
        ratios.push_back({{"raster", a["raster"]},
                          {"width", a["width"]},
                          {"height", a["height"]},
                          {"points", a["points"]},
                          {"wall_ratio", a["wall_ms"].get<double>() / b["wall_ms"].get<double>()},
                          {"gpu_ratio", a["gpu_ms"]["total"].get<double>() /
                                            b["gpu_ms"]["total"].get<double>()}});
      }
    }
  }
  nlohmann::json doc = {{"benchmark", "depth"},
                        {"renderer", context.Renderer()},
                        {"gl_version", context.Version()},
                        {"egl_platform", context.platform()},
                        {"results", results},
                        {"lechelek_over_marroquim", ratios}};

  FILE* table = TableStream(opt.json);
  std::fprintf(table, "depth pass on %s\n", context.Renderer().c_str());
  std::fprintf(table,
               "steps: wall ms with a glFinish after each step; gpu ms: timestamp queries\n");
  std::fprintf(table, "%-9s %-8s %9s %8s | %8s %8s %8s %8s %8s | %9s %8s %10s\n", "mode", "raster",
               "size", "points", "splat", "project", "pullpush", "resolve", "gpu ms", "wall ms",
               "fps", "Mpoints/s");
  for (const auto& r : results) {
    const std::string size =
        std::to_string(r["width"].get<int>()) + "x" + std::to_string(r["height"].get<int>());
    const auto& g = r["step_wall_ms"];
    std::fprintf(table, "%-9s %-8s %9s %8zu | %8.1f %8.1f %8.1f %8.1f %8.1f | %9.1f %8.2f %10.2f\n",
                 r["mode"].get<std::string>().c_str(), r["raster"].get<std::string>().c_str(),
                 size.c_str(), r["points"].get<size_t>(), g["splat"].get<double>(),
                 g["project"].get<double>(), g["pullpush"].get<double>(),
                 g["resolve"].get<double>(), g["total"].get<double>(), r["wall_ms"].get<double>(),
                 1000.0 / r["wall_ms"].get<double>(), r["points_per_s"].get<double>() * 1e-6);
  }
  for (const auto& r : ratios) {
    std::fprintf(table, "lechelek/marroquim (%s raster) %dx%d %zu points: wall %.2fx, gpu %.2fx\n",
                 r["raster"].get<std::string>().c_str(), r["width"].get<int>(),
                 r["height"].get<int>(), r["points"].get<size_t>(), r["wall_ratio"].get<double>(),
                 r["gpu_ratio"].get<double>());
  }
  EmitJson(opt.json, doc);
  return 0;
}

CommandRunner SetupBenchDepth(CLI::App& sub) {
  auto opt = std::make_shared<BenchDepthOptions>();
  sub.add_option("--sizes", opt->sizes, "Comma-separated WxH")->capture_default_str();
  sub.add_option("--points", opt->points, "Comma-separated point counts")->capture_default_str();
  sub.add_option("--modes", opt->modes, "Comma-separated modes")->capture_default_str();
  sub.add_option("--rasters", opt->rasters, "Comma-separated point rasters (compute, pipeline)")
      ->capture_default_str();
  sub.add_option("--frames", opt->frames, "Timed frames per configuration")->capture_default_str();
  sub.add_option("--detail", opt->detail,
                 "The target's size per axis relative to the full-size picture it previews, (0, "
                 "1]: below 1 a coarser level of the cloud is drawn")
      ->capture_default_str();
  sub.add_option("--json", opt->json, "Write the JSON here instead of stdout")
      ->check(OutputFolderCheck());
  return [opt] { return Run(*opt); };
}

}  // namespace

HDRIBR_BENCH(depth, "Depth pass speed per mode, size and cloud (GPU step times, wall time)",
             SetupBenchDepth);

}  // namespace hdribr::cli
