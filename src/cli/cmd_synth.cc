// `hdribr synth OUT`: a ground-truth synthetic hand-held multi-exposure capture.
#include <spdlog/spdlog.h>

#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "core/error.h"
#include "io/image.h"
#include "synth/capture.h"

namespace hdribr::cli {
namespace {

struct SynthCliOptions {
  std::string out;
  std::string size = "640x480";
  std::string preview;
  synth::CaptureOptions capture;
};

int Run(SynthCliOptions opt) {
  const cv::Size size = ParseSize(opt.size);
  opt.capture.width = size.width;
  opt.capture.height = size.height;
  if (!opt.preview.empty()) {
    const synth::CapturePlan plan = synth::PlanCapture(opt.capture);
    WriteImage(opt.preview, synth::MakePreview(plan));
    spdlog::info("preview of {} written to {}", plan.photos.front().name, opt.preview);
    if (opt.out.empty()) return 0;
  }
  if (opt.out.empty()) throw UsageError("synth: give an output folder (or only --preview)");
  const synth::CaptureSummary s = synth::WriteCapture(opt.capture, opt.out);
  spdlog::info("{}: {} photos ({} series x {}), {} novel views, {} points", opt.out, s.photos,
               opt.capture.series, opt.capture.views, s.novel, s.points);
  spdlog::info("radiance (luminance) 0.1st..99.9th percentile {:.4g}..{:.4g} ({:.0f}:1)",
               s.radiance_p001, s.radiance_p999,
               s.radiance_p001 > 0 ? s.radiance_p999 / s.radiance_p001 : 0.0);
  spdlog::info("rendered in {:.1f} s, total {:.1f} s", s.render_seconds, s.total_seconds);
  return 0;
}

struct BenchSynthOptions {
  std::string size = "640x480";
  std::string json;
  int repeat = 1;
  synth::CaptureOptions capture;
};

// Writes whole captures into a temporary folder and reports the time of each (render and total).
int RunBench(BenchSynthOptions opt) {
  const cv::Size size = ParseSize(opt.size);
  opt.capture.width = size.width;
  opt.capture.height = size.height;
  if (opt.repeat < 1) throw UsageError("bench synth: --repeat must be at least 1");
  namespace fs = std::filesystem;
  const fs::path tmp =
      fs::temp_directory_path() / ("hdribr-bench-synth-" + std::to_string(getpid()));
  nlohmann::json runs = nlohmann::json::array();
  double best_total = 1e300, best_render = 1e300;
  synth::CaptureSummary s;
  for (int i = 0; i < opt.repeat; ++i) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    s = synth::WriteCapture(opt.capture, tmp);
    fs::remove_all(tmp, ec);
    runs.push_back({{"render_s", s.render_seconds}, {"total_s", s.total_seconds}});
    best_total = std::min(best_total, s.total_seconds);
    best_render = std::min(best_render, s.render_seconds);
  }
  const unsigned threads =
      opt.capture.threads > 0 ? unsigned(opt.capture.threads) : std::thread::hardware_concurrency();
  nlohmann::json j = {{"benchmark", "synth"},
                      {"scene", opt.capture.scene},
                      {"size", opt.size},
                      {"series", opt.capture.series},
                      {"views", opt.capture.views},
                      {"novel_views", opt.capture.novel_views},
                      {"threads", threads},
                      {"points", s.points},
                      {"runs", runs},
                      {"best_render_s", best_render},
                      {"best_total_s", best_total}};
  EmitJson(opt.json, j);
  std::printf("%-8s %-9s %6s %6s %7s %10s %9s\n", "scene", "size", "series", "views", "threads",
              "render s", "total s");
  std::printf("%-8s %-9s %6d %6d %7u %10.2f %9.2f\n", opt.capture.scene.c_str(), opt.size.c_str(),
              opt.capture.series, opt.capture.views, threads, best_render, best_total);
  return 0;
}

}  // namespace

CommandRunner SetupBenchSynth(CLI::App& sub);
HDRIBR_BENCH(synth, "Synthetic capture rendering speed (hdribr synth)", SetupBenchSynth);

CommandRunner SetupBenchSynth(CLI::App& sub) {
  auto opt = std::make_shared<BenchSynthOptions>();
  sub.add_option(
         "--scene", opt->capture.scene,
         "Scene: default, thin, arches, railing, corner, facade, glossy, open, random (by --seed)")
      ->capture_default_str();
  sub.add_option("--series", opt->capture.series, "Exposure series")->capture_default_str();
  sub.add_option("--views", opt->capture.views, "Views per series")->capture_default_str();
  sub.add_option("--size", opt->size, "Image size WxH")->capture_default_str()->check(SizeCheck());
  sub.add_option("--novel", opt->capture.novel_views, "Novel views")->capture_default_str();
  sub.add_option("--threads", opt->capture.threads, "Threads (0 = all cores)")
      ->capture_default_str();
  sub.add_option("--repeat", opt->repeat, "Runs (the best is reported)")->capture_default_str();
  sub.add_option("--json", opt->json, "Write the JSON to this file instead of stdout")
      ->check(OutputFolderCheck());
  return [opt] { return RunNamingFlags(CaptureFlags(), [&] { return RunBench(*opt); }); };
}

CommandRunner SetupSynth(CLI::App& sub);
HDRIBR_COMMAND(synth, "Make a ground-truth synthetic multi-exposure capture", SetupSynth, 15);

CommandRunner SetupSynth(CLI::App& sub) {
  auto opt = std::make_shared<SynthCliOptions>();
  sub.add_option("out", opt->out, "Output folder (must not exist or be empty)");
  sub.add_option(
         "--scene", opt->capture.scene,
         "Scene: default, thin, arches, railing, corner, facade, glossy, open, random (by --seed)")
      ->capture_default_str();
  sub.add_option("--series", opt->capture.series, "Exposure series (2 EV apart)")
      ->capture_default_str();
  sub.add_option("--views", opt->capture.views, "Views per series")->capture_default_str();
  sub.add_option("--size", opt->size, "Image size WxH")->capture_default_str()->check(SizeCheck());
  sub.add_option("--seed", opt->capture.seed, "Random seed (same seed, same bytes)")
      ->capture_default_str();
  sub.add_option("--novel", opt->capture.novel_views, "Ground-truth novel test views")
      ->capture_default_str();
  sub.add_option("--ev-step", opt->capture.ev_step, "Stops between series")->capture_default_str();
  sub.add_option("--exposure", opt->capture.exposure,
                 "series: one exposure per series; auto: each photo metered on its view, biased "
                 "by its series' offset, EXIF rounded to 1/3 stop")
      ->capture_default_str();
  sub.add_option("--exif-error", opt->capture.exif_error,
                 "Std. dev. of ln(true / EXIF exposure time), per photo (0.05 = about 5 %)")
      ->capture_default_str();
  sub.add_option("--toe", opt->capture.toe,
                 "Camera response: end of its linear toe, share of saturation (0 = pure power law)")
      ->capture_default_str();
  sub.add_option("--threads", opt->capture.threads, "Render threads (0 = all cores)")
      ->capture_default_str();
  sub.add_option("--preview", opt->preview,
                 "Also write a PNG: the first view at every series' exposure + its depth map");
  return [opt] { return RunNamingFlags(CaptureFlags(), [&] { return Run(*opt); }); };
}

}  // namespace hdribr::cli
