// `hdribr bench render`: frame time of the renderer split into depth pass and blend pass, per
// output size, photo count, K best, candidate cap and GPU memory budget, on a generated scene
// (points + synthetic photos).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cli/bench_cloud.h"
#include "cli/cli_util.h"
#include "cli/command.h"
#include "cli/render_options.h"
#include "core/error.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "render/renderer.h"

namespace hdribr::cli {
namespace {

struct BenchRenderOptions {
  std::string sizes = "512x512,1920x1080";
  std::string photos = "20,60,200";
  std::string k_best = "0,1,4";
  // Caps on the candidate photos per frame: 0 (every photo) and the renderer's default.
  std::string candidates = "0," + std::to_string(render::kDefaultMaxCandidates);
  long long points = 1000000;
  std::string photo_size = "640x480";
  int frames = 2;
  // GPU memory budgets, MiB (0 = the device's: every photo resident on a large GPU).
  std::string gpu_memory = "0";
  int silhouette_trim = render::DepthPassOptions{}.silhouette_trim;
  render::BlendOptions blend;  // every blend option but K (the list above)
  std::string json;
};

// CPU seconds of every thread of the process (llvmpipe's rasteriser threads included): on a
// shared machine a frame's CPU time varies far less than its wall time.
double ProcessCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::vector<double> ParseBudgets(const std::string& s) {
  std::vector<double> out;
  for (const auto& item : SplitList(s)) {
    try {
      size_t used = 0;
      const double v = std::stod(item, &used);
      if (used != item.size() || !(v >= 0)) throw std::invalid_argument("");
      out.push_back(v);
    } catch (const std::exception&) {
      throw UsageError("--gpu-memory: bad value '" + item + "'");
    }
  }
  if (out.empty()) throw UsageError("--gpu-memory: empty list");
  return out;
}

std::vector<int> ParseInts(const std::string& s, const char* what, int min) {
  std::vector<int> out;
  for (const auto& item : SplitList(s)) {
    try {
      size_t used = 0;
      const int v = std::stoi(item, &used);
      if (used != item.size() || v < min) throw std::invalid_argument("");
      out.push_back(v);
    } catch (const std::exception&) {
      throw UsageError(std::string(what) + ": bad value '" + item + "'");
    }
  }
  if (out.empty()) throw UsageError(std::string(what) + ": empty list");
  return out;
}

// A scene of `count` photos on a ring around the dome, looking at it, with generated pixels.
Scene MakeScene(int count, int pw, int ph, const PointCloud& cloud, std::vector<cv::Mat>& images) {
  Scene scene;
  const double f = 0.5 * pw / std::tan(M_PI / 6.0);
  scene.cameras[1] = Camera::Pinhole(1, pw, ph, f, f, 0.5 * pw, 0.5 * ph);
  images.clear();
  for (int i = 0; i < count; ++i) {
    const double a = 2 * M_PI * i / count;
    const double height = -1.5 - 0.5 * (i % 3);
    Photo photo;
    photo.id = i + 1;
    photo.name = "bench_" + std::to_string(i) + ".png";
    photo.image_path = photo.name;
    photo.camera_id = 1;
    photo.cam_from_world =
        LookAt({4.0 * std::cos(a), height, 4.0 * std::sin(a)}, {0, -0.3, 0}, {0, -1, 0});
    scene.photos.push_back(photo);
    cv::Mat img(ph, pw, CV_8UC3);
    cv::RNG rng(static_cast<uint64_t>(i) + 1);  // the same pixels for every budget
    rng.fill(img, cv::RNG::UNIFORM, cv::Scalar::all(0), cv::Scalar::all(255));
    cv::GaussianBlur(img, img, cv::Size(0, 0), 2.0);
    images.push_back(img);
  }
  scene.points = cloud;
  scene.UpdateDerived();
  return scene;
}

int Run(const BenchRenderOptions& opt) {
  if (opt.frames < 1) throw UsageError("--frames must be >= 1");
  if (opt.points <= 0) throw UsageError("--points must be positive");
  const render::BlendOptions& blend = opt.blend;
  CheckBlendOptions(blend);
  std::vector<std::pair<int, int>> sizes;
  for (const auto& s : SplitList(opt.sizes)) {
    const cv::Size size = ParseSize(s, "--sizes");
    sizes.emplace_back(size.width, size.height);
  }
  const std::vector<int> photo_counts = ParseInts(opt.photos, "--photos", 1);
  const std::vector<int> ks = ParseInts(opt.k_best, "--k-best", 0);
  const std::vector<int> caps = ParseInts(opt.candidates, "--candidates", 0);
  const std::vector<double> budgets = ParseBudgets(opt.gpu_memory);
  const cv::Size photo_size = ParseSize(opt.photo_size, "--photo-size");
  const int pw = photo_size.width, ph = photo_size.height;

  gl::HeadlessContext context;
  const gl::ShaderLibrary shaders;
  const PointCloud cloud = MakeBenchCloud(static_cast<size_t>(opt.points), DomeBenchScene());
  const Rigid3d cam_from_world = LookAt({2.5, -2.2, -3.0}, {0, -0.3, 0}, {0, -1, 0});
  nlohmann::json results = nlohmann::json::array();
  FILE* table = TableStream(opt.json);
  std::fprintf(
      table, "%-10s %6s %5s %5s %5s %7s %10s %10s %8s %10s %10s %10s %10s %8s %8s %15s %8s\n",
      "size", "photos", "K", "cap", "used", "sel_ms", "depth_ms", "blend_ms", "fill_ms", "total_ms",
      "first_ms", "wall_ms", "cpu_ms", "valid%", "psnr_all", "resident/MiB", "psnr_res");
  // Per photo count, size, K and cap: the colour of the render with every photo resident, to
  // which a cached budget's render is compared (PSNR, 8-bit scale; "same" when identical).
  std::map<std::tuple<int, int, int, int, int>, cv::Mat> all_resident;
  for (int count : photo_counts) {
    for (double budget : budgets) {
      std::vector<cv::Mat> images;
      const Scene scene = MakeScene(count, pw, ph, cloud, images);
      render::RendererOptions ro;
      ro.photo_images = std::move(images);
      ro.gpu_memory_mb = budget;
      ro.depth.silhouette_trim = opt.silhouette_trim;
      ro.blend = blend;
      // The cache's plan sizes its slots for the largest cap (0 = every photo).
      ro.max_candidates = *std::max_element(caps.begin(), caps.end());
      if (std::find(caps.begin(), caps.end(), 0) != caps.end()) ro.max_candidates = 0;
      const auto s0 = std::chrono::steady_clock::now();
      render::Renderer renderer(shaders, scene, ro);
      const double setup_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
      for (const auto& [w, h] : sizes) {
        const double f = 0.5 * w / std::tan(M_PI / 6.0);
        const Camera cam = Camera::Pinhole(1, w, h, f, f, 0.5 * w, 0.5 * h);
        render::RenderTarget target = render::RenderTarget::Create(w, h);
        for (int k : ks) {
          renderer.blend_options().k_best = k >= count ? 0 : k;
          cv::Mat all_photos;  // this K's render from every photo (cap 0), when measured first
          for (int cap : caps) {
            renderer.SetMaxCandidates(cap);
            // The first frame (with a cache: waiting for its candidates' loads), then warm ones.
            const auto f0 = std::chrono::steady_clock::now();
            renderer.Render(cam, cam_from_world, target);
            glFinish();
            const double first_ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - f0)
                    .count();
            double depth_ms = 0, blend_ms = 0, fill_ms = 0, select_ms = 0, used = 0;
            const auto t0 = std::chrono::steady_clock::now();
            const double cpu0 = ProcessCpuSeconds();
            for (int i = 0; i < opt.frames; ++i) {
              renderer.Render(cam, cam_from_world, target);
              depth_ms += renderer.last_times().depth_ms / opt.frames;
              blend_ms += renderer.last_times().blend_ms / opt.frames;
              fill_ms += renderer.last_times().fill_ms / opt.frames;
              select_ms += renderer.last_candidates().select_ms / opt.frames;
              used += static_cast<double>(renderer.last_candidates().photos.size()) / opt.frames;
            }
            glFinish();
            const double cpu_ms = 1000.0 * (ProcessCpuSeconds() - cpu0) / opt.frames;
            const double wall_ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count() /
                opt.frames;
            const render::RenderImages im = render::Renderer::Read(target);
            const double valid = 100.0 * cv::countNonZero(im.valid) / (w * h);
            const double mean_count =
                cv::countNonZero(im.valid) ? cv::mean(im.count, im.valid)[0] : 0;
            // PSNR (8-bit scale, every pixel) against the render from every photo.
            double psnr_all = -1;
            if (cap == 0) {
              all_photos = im.color.clone();
            } else if (!all_photos.empty()) {
              psnr_all = cv::PSNR(im.color * 255.0, all_photos * 255.0, 255.0);
            }
            char size_text[32], psnr_text[32] = "-";
            std::snprintf(size_text, sizeof(size_text), "%dx%d", w, h);
            if (psnr_all >= 0) std::snprintf(psnr_text, sizeof(psnr_text), "%.2f", psnr_all);
            const render::PhotoResidency res = renderer.residency();
            const auto key = std::make_tuple(count, w, h, k, cap);
            double diff_resident = -1, psnr_resident = -1;
            if (!res.cached) {
              all_resident[key] = im.color.clone();
            } else if (all_resident.count(key)) {
              diff_resident = 255.0 * cv::norm(im.color, all_resident[key], cv::NORM_INF);
              psnr_resident = cv::PSNR(im.color * 255.0, all_resident[key] * 255.0, 255.0);
            }
            char diff_text[32] = "-";
            if (diff_resident == 0) {
              std::snprintf(diff_text, sizeof(diff_text), "same");
            } else if (diff_resident > 0) {
              std::snprintf(diff_text, sizeof(diff_text), "%.2f", psnr_resident);
            }
            char resident_text[48];
            std::snprintf(resident_text, sizeof(resident_text), "%.1f/%.1f",
                          res.resident_bytes / 1048576.0, res.total_bytes / 1048576.0);
            std::fprintf(table,
                         "%-10s %6d %5s %5s %5.1f %7.2f %10.1f %10.1f %8.1f %10.1f %10.1f %10.1f "
                         "%10.1f %8.1f %8s "
                         "%15s %8s\n",
                         size_text, count, k == 0 || k >= count ? "all" : std::to_string(k).c_str(),
                         cap == 0 ? "all" : std::to_string(cap).c_str(), used, select_ms, depth_ms,
                         blend_ms, fill_ms, depth_ms + blend_ms + fill_ms, first_ms, wall_ms,
                         cpu_ms, valid, psnr_text, resident_text, diff_text);
            std::fflush(table);
            results.push_back(
                {{"width", w},
                 {"height", h},
                 {"photos", count},
                 {"k_best", k >= count ? 0 : k},
                 {"refine_depth", blend.refine_depth},
                 {"sampling", render::PhotoSamplingName(blend.sampling)},
                 {"outlier_scale", blend.outlier_scale},
                 {"background", render::BackgroundName(blend.background)},
                 {"fill", blend.fill},
                 {"max_candidates", cap},
                 {"candidates_per_frame", used},
                 {"candidates_ms", select_ms},
                 {"points", opt.points},
                 {"photo_size", opt.photo_size},
                 {"frames", opt.frames},
                 {"depth_ms", depth_ms},
                 {"blend_ms", blend_ms},
                 {"fill_ms", fill_ms},
                 {"wall_ms", wall_ms},
                 {"cpu_ms", cpu_ms},
                 {"valid_percent", valid},
                 {"mean_photos_per_pixel", mean_count},
                 {"psnr_vs_all_photos", psnr_all < 0 ? nlohmann::json() : nlohmann::json(psnr_all)},
                 {"setup_s", setup_s},
                 {"first_frame_ms", first_ms},
                 {"gpu_memory_mb", budget},
                 {"cached", res.cached},
                 {"resident_mib", res.resident_bytes / 1048576.0},
                 {"total_mib", res.total_bytes / 1048576.0},
                 {"full_size_slots", res.slots},
                 {"reduced_slots", res.reduced_slots},
                 {"reduced_photos", res.reduced},
                 {"full_size_photos", res.full_size},
                 {"max_diff_vs_all_resident",
                  diff_resident < 0 ? nlohmann::json() : nlohmann::json(diff_resident)},
                 {"psnr_vs_all_resident",
                  diff_resident <= 0 ? nlohmann::json() : nlohmann::json(psnr_resident)},
                 {"gpu_bytes", res.resident_bytes}});
          }
        }
      }
    }
  }
  const nlohmann::json doc = {{"benchmark", "render"},
                              {"renderer", context.Renderer()},
                              {"egl_platform", context.platform()},
                              {"note",
                               "GPU times from GL timestamp queries; wall = CPU clock; cpu = CPU "
                               "time of every thread of the process"},
                              {"results", results}};
  EmitJson(opt.json, doc);
  return 0;
}

}  // namespace

CommandRunner SetupBenchRender(CLI::App& sub);
HDRIBR_BENCH(render,
             "Renderer frame time: depth pass / blend pass vs size, photos, K best, candidates",
             SetupBenchRender);

CommandRunner SetupBenchRender(CLI::App& sub) {
  auto opt = std::make_shared<BenchRenderOptions>();
  sub.add_option("--sizes", opt->sizes, "Output sizes WxH, comma-separated")
      ->default_val(opt->sizes);
  sub.add_option("--photos", opt->photos, "Photo counts, comma-separated")
      ->default_val(opt->photos);
  sub.add_option("--k-best", opt->k_best, "K best values (0 = all), comma-separated")
      ->default_val(opt->k_best);
  sub.add_option("--candidates", opt->candidates,
                 "Caps on the candidate photos per frame (0 = every photo), comma-separated")
      ->default_val(opt->candidates);
  sub.add_option("--points", opt->points, "Point count")->default_val(opt->points);
  sub.add_option("--photo-size", opt->photo_size, "Size of the generated photos WxH")
      ->default_val(opt->photo_size);
  sub.add_option("--frames", opt->frames, "Timed frames per configuration")
      ->default_val(opt->frames);
  sub.add_option("--gpu-memory", opt->gpu_memory,
                 "GPU memory budgets, MiB, comma-separated (0 = the device's; a budget below the "
                 "photos' size caches them)")
      ->default_val(opt->gpu_memory);
  AddSilhouetteTrimOption(sub, opt->silhouette_trim);
  AddBlendOptions(sub, opt->blend);
  sub.add_option("--json", opt->json, "Write the JSON here instead of stdout")
      ->check(OutputFolderCheck());
  return [opt] { return RunNamingFlags(RendererFlags(), [&] { return Run(*opt); }); };
}

}  // namespace hdribr::cli
