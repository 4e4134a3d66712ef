// `hdribr bench quality`: the quality suite. Makes or reconstructs every capture of a manifest
// (datasets/quality-suite.json), evaluates it end to end with the executable's own
// subcommands, and prints one table (per capture, and the mean and worst of each split).
// Resumable: every stage's output is kept under --dir and reused.
#include <spdlog/spdlog.h>

#include <sys/utsname.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "cli/render_options.h"
#include "core/error.h"
#include "eval/quality_suite.h"
#include "frontend/colmap_cli.h"
#include "gl/context.h"
#include "gl/shader_library.h"
#include "io/atomic_file.h"
#include "io/workspace.h"
#include "render/renderer.h"

namespace hdribr::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct QualityOptions {
  std::string manifest = "datasets/quality-suite.json";
  std::string dir = "quality-suite";
  std::string datasets = "../shared/datasets";
  std::vector<std::string> only;
  std::string split;
  bool quick = false;
  std::string tag = "default";
  std::string render_args;
  bool redo_eval = false;
  bool gt_only = false;
  std::string json;
  std::string markdown;
};

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

std::string Duration(double s) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%d:%02d", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  return buf;
}

std::vector<std::string> Words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// Runs this executable with `args`, its output logged to `log`; throws with the log's tail
// when it fails.
void RunSelf(const std::vector<std::string>& args, const fs::path& log) {
  const fs::path exe = fs::read_symlink("/proc/self/exe");
  std::string line = "hdribr";
  for (const std::string& a : args) line += " " + a;
  spdlog::info("  {}", line);
  std::error_code ec;
  fs::remove(log, ec);
  const int rc = RunLogged(exe, args, log, [](const std::string&) {});
  if (rc != 0) {
    throw InputError(
        log, "`" + line + "` failed (exit " + std::to_string(rc) + "):\n" + LastLines(log, 8));
  }
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct ParsedRenderArgs {
  render::RendererOptions options;
  bool no_depth_cache = false;
};

// The renderer options of --render-args, parsed as `render` parses them.
ParsedRenderArgs ParseRenderArgs(const std::vector<std::string>& words) {
  ParsedRenderArgs p;
  CLI::App app;
  AddRendererOptions(app, p.options, p.no_depth_cache);
  std::vector<std::string> args(words.rbegin(), words.rend());  // CLI11 takes them reversed
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    throw UsageError(std::string("--render-args: ") + e.what());
  }
  CheckBlendOptions(p.options.blend);
  return p;
}

double ReadNumber(const fs::path& path, const char* key) {
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.contains(key) || !j.at(key).is_number()) {
    throw InputError(path, std::string("has no number '") + key + "'");
  }
  return j.at(key).get<double>();
}

// Median wall time of the render at 512x512 from the first photo's viewpoint: one warm-up
// frame, then 3 timed frames (each read back, so the GPU has finished).
double FrameMs(const Scene& scene, const fs::path& workspace, const ParsedRenderArgs& args,
               std::string* gl_renderer) {
  render::RendererOptions ro = args.options;
  ro.depth_cache_dir = WorkspaceDepthCache(workspace, args.no_depth_cache);
  if (scene.photos.empty()) throw InputError(workspace, "the workspace has no photos");
  gl::HeadlessContext context;
  *gl_renderer = context.Renderer();
  const gl::ShaderLibrary shaders;
  render::Renderer renderer(shaders, scene, ro);
  const Photo& photo = scene.photos.front();
  std::vector<double> ms;
  for (int i = 0; i < 4; ++i) {
    const auto t0 = Clock::now();
    renderer.RenderToImages(scene.CameraOf(photo), photo.cam_from_world, 512, 512);
    if (i > 0) ms.push_back(1000 * Seconds(t0));
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

std::string Provenance(const std::string& gl_renderer) {
  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof(date), "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  std::string commit = "unknown";
  if (std::FILE* p = popen("git rev-parse --short HEAD 2>/dev/null", "r")) {
    char buf[64] = {};
    if (std::fgets(buf, sizeof(buf), p)) commit = std::string(buf, std::strcspn(buf, "\n"));
    pclose(p);
  }
  utsname u{};
  uname(&u);
  return "Measured " + std::string(date) + " at commit " + commit + " on " + u.machine + ", " +
         std::to_string(std::thread::hardware_concurrency()) + " cores, " +
         (gl_renderer.empty() ? std::string("GL renderer not probed") : gl_renderer);
}

class SuiteRunner {
 public:
  explicit SuiteRunner(const QualityOptions& o)
      : o_(o), render_args_(Words(o.render_args)), parsed_(ParseRenderArgs(render_args_)) {}

  // Runs every stage not yet done for one capture; returns its figures, or nullopt when the
  // capture's photos are absent (a shared dataset that is not there).
  std::optional<eval::CaptureFigures> Run(const eval::SuiteCapture& c) {
    const fs::path root = fs::path(o_.dir) / c.name;
    const fs::path tag = root / o_.tag;
    eval::CaptureFigures f;
    f.name = c.name;
    f.split = c.split;
    f.synthetic = c.synth.has_value();
    const fs::path capture = root / "capture";
    fs::path photos = fs::path(o_.datasets) / c.photos;
    if (c.synth) {
      photos = capture / "photos";
      if (!fs::exists(capture)) {
        Stage(c, "synth");
        synth::WriteCapture(*c.synth, capture);
      }
    } else if (!fs::is_directory(photos)) {
      spdlog::warn("{}: skipped, {} is absent", c.name, photos.string());
      return std::nullopt;
    }
    fs::create_directories(tag);
    if (o_.gt_only) {
      EvalOnGt(c, capture, tag, f);
      WriteFileAtomic(tag / "figures.json", eval::FiguresToJson(f).dump(2) + "\n");
      return f;
    }
    const fs::path ws = root / "ws";
    const fs::path recon = root / "reconstruct.json";
    if (!fs::exists(recon)) {
      Stage(c, "reconstruct");
      const auto t0 = Clock::now();
      RunSelf({"reconstruct", photos.string(), ws.string()}, root / "reconstruct.log");
      WriteFileAtomic(recon, nlohmann::json{{"seconds", Seconds(t0)}}.dump() + "\n");
    }
    f.reconstruct_s = ReadNumber(recon, "seconds");
    const Scene scene = LoadWorkspace(ws);
    size_t inputs = 0;
    for (const auto& e : fs::directory_iterator(photos)) inputs += e.is_regular_file();
    if (inputs > 0) f.registered = double(scene.photos.size()) / double(inputs);
    // Calibrated as `view PHOTOS/` does: when the photos have several exposures.
    const fs::path calib_log = root / "calibrate.log";
    if (scene.series.size() >= 2 && !fs::exists(calib_log)) {
      Stage(c, "calibrate");
      std::vector<std::string> args = {"calibrate", ws.string()};
      if (c.synth) args.insert(args.end(), {"--truth", capture.string()});
      RunSelf(args, root / "calibrate.partial.log");
      fs::rename(root / "calibrate.partial.log", calib_log);
    }
    if (fs::exists(calib_log)) eval::ParseExposureTruth(ReadText(calib_log), f);

    Eval(c, "leave-one-out", ws, {"--leave-one-out"}, c.eval_args, tag / "loo");
    eval::ReadLeaveOneOut(tag / "loo", f);
    if (c.synth) EvalOnGt(c, capture, tag, f);
    // Measured on every run (seconds), so that a run of finished captures on an idle machine
    // times every frame alike.
    Stage(c, "frame cost");
    f.frame_ms = FrameMs(scene, ws, parsed_, &gl_renderer_);
    WriteFileAtomic(tag / "figures.json", eval::FiguresToJson(f).dump(2) + "\n");
    return f;
  }

  void Begin(size_t total) {
    total_ = total;
    start_ = Clock::now();
  }
  void Finished() { ++done_; }
  const std::string& gl_renderer() const { return gl_renderer_; }

 private:
  void Stage(const eval::SuiteCapture& c, const char* stage) const {
    const double elapsed = Seconds(start_);
    std::string eta = "ETA unknown";
    if (done_ > 0) eta = "ETA " + Duration(elapsed / done_ * double(total_ - done_));
    spdlog::info("[{}/{}] {}: {} (elapsed {}, {})", done_ + 1, total_, c.name, stage,
                 Duration(elapsed), eta);
  }

  // The evaluations on a synthetic capture's GT points and cameras.
  void EvalOnGt(const eval::SuiteCapture& c, const fs::path& capture, const fs::path& tag,
                eval::CaptureFigures& f) {
    const fs::path gt_ws = capture / "workspace";
    Eval(c, "leave-one-out on GT geometry", gt_ws, {"--leave-one-out", "--no-baselines"},
         c.eval_args, tag / "gt_loo");
    eval::ReadGtLeaveOneOut(tag / "gt_loo", f);
    Eval(c, "GT novel views", gt_ws,
         {"--gt", capture.string(), "--size-scale", "1", "--no-baselines"}, {}, tag / "gt_novel");
    eval::ReadGtNovel(tag / "gt_novel", f);
  }

  void Eval(const eval::SuiteCapture& c, const char* what, const fs::path& ws,
            std::vector<std::string> mode, const std::vector<std::string>& extra,
            const fs::path& out) {
    // `done` is written once the command has finished: a run killed between eval.json and
    // eval_hdr.json is run again.
    if (fs::exists(out / "done") && !o_.redo_eval) return;
    Stage(c, what);
    std::error_code ec;
    fs::remove_all(out, ec);
    std::vector<std::string> args = {"eval", ws.string()};
    args.insert(args.end(), mode.begin(), mode.end());
    args.insert(args.end(), extra.begin(), extra.end());
    args.insert(args.end(), render_args_.begin(), render_args_.end());
    args.insert(args.end(), {"--out", out.string()});
    fs::create_directories(out.parent_path());
    RunSelf(args, out.string() + ".log");
    WriteFileAtomic(out / "done", "");
  }

  QualityOptions o_;
  std::vector<std::string> render_args_;
  ParsedRenderArgs parsed_;
  std::string gl_renderer_;
  Clock::time_point start_ = Clock::now();
  size_t total_ = 0, done_ = 0;
};

int Run(const QualityOptions& o) {
  if (o.split != "" && o.split != "tune" && o.split != "check") {
    throw UsageError("--split must be tune or check, got '" + o.split + "'");
  }
  const auto safe = [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_';
  };
  if (o.tag.empty() || !std::all_of(o.tag.begin(), o.tag.end(), safe)) {
    throw UsageError("--tag must be [A-Za-z0-9_-]+, got '" + o.tag + "'");
  }
  const std::vector<eval::SuiteCapture> manifest = eval::ReadSuiteManifest(o.manifest);
  for (const std::string& name : o.only) {
    if (std::none_of(manifest.begin(), manifest.end(),
                     [&](const eval::SuiteCapture& c) { return c.name == name; })) {
      throw UsageError("--only: no capture named '" + name + "' in " + o.manifest);
    }
  }
  std::vector<eval::SuiteCapture> chosen;
  for (const eval::SuiteCapture& c : manifest) {
    if (!o.only.empty() && std::find(o.only.begin(), o.only.end(), c.name) == o.only.end()) {
      continue;
    }
    if (!o.split.empty() && c.split != o.split) continue;
    if (o.quick && !c.quick) continue;
    if (o.gt_only && !c.synth) continue;
    chosen.push_back(c);
  }
  if (chosen.empty()) throw UsageError("bench quality: no capture matches the selection");
  SuiteRunner runner(o);  // checks --render-args before any work
  runner.Begin(chosen.size());
  std::vector<eval::CaptureFigures> rows;
  for (const eval::SuiteCapture& c : chosen) {
    if (auto f = runner.Run(c)) rows.push_back(*f);
    runner.Finished();
  }
  if (rows.empty()) throw UsageError("bench quality: every chosen capture is absent");
  const std::string provenance = Provenance(runner.gl_renderer()) + "; tag " + o.tag +
                                 (o.render_args.empty() ? "" : " (" + o.render_args + ")");
  std::FILE* table = TableStream(o.json);
  std::fprintf(table, "%s\n%s", provenance.c_str(), eval::FormatSuiteTable(rows).c_str());
  if (!o.markdown.empty()) {
    WriteFileAtomic(o.markdown, eval::FormatSuiteMarkdown(rows, provenance));
  }
  EmitJson(o.json, nlohmann::json::parse(eval::FormatSuiteJson(rows, provenance)));
  return 0;
}

CommandRunner SetupBenchQuality(CLI::App& sub) {
  auto opt = std::make_shared<QualityOptions>();
  sub.add_option("--manifest", opt->manifest, "The suite's captures (JSON)")->capture_default_str();
  sub.add_option("--dir", opt->dir, "Work folder: captures, workspaces and evaluations")
      ->capture_default_str();
  sub.add_option("--datasets", opt->datasets, "Folder of the real captures' photos")
      ->capture_default_str();
  sub.add_option("--only", opt->only, "Only these captures (names)");
  sub.add_option("--split", opt->split, "Only this split: tune or check");
  sub.add_flag("--quick", opt->quick, "Only the captures marked quick");
  sub.add_option("--tag", opt->tag, "Name of this evaluation (a variant of the options)")
      ->capture_default_str();
  sub.add_option("--render-args", opt->render_args,
                 "Renderer options for every evaluation and the frame cost (quoted)");
  sub.add_flag("--redo-eval", opt->redo_eval, "Evaluate again (keeps captures and workspaces)");
  sub.add_flag("--gt-only", opt->gt_only,
               "Synthetic captures on their GT geometry only (no reconstruction): a quick screen");
  sub.add_option("--json", opt->json, "Write the JSON here instead of stdout")
      ->check(OutputFolderCheck());
  sub.add_option("--markdown", opt->markdown, "Write the table as markdown here")
      ->check(OutputFolderCheck());
  return [opt] { return Run(*opt); };
}

}  // namespace

HDRIBR_BENCH(quality, "The quality suite: many captures end to end, one table", SetupBenchQuality);

}  // namespace hdribr::cli
