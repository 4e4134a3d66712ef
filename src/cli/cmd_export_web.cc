// `hdribr export-web WORKSPACE OUT`: the capture as a static folder that a WebGL2 viewer opens
// in any browser (docs/usage/web.md).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "core/error.h"
#include "io/web_bundle.h"
#include "io/workspace.h"

namespace hdribr::cli {
namespace {

struct ExportWebOptions {
  std::string workspace;
  std::string out;
  WebBundleOptions bundle;
};

double MiB(std::uintmax_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

int Run(const ExportWebOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::filesystem::path out = std::filesystem::absolute(opt.out);
  CheckOutsideInputs(opt.workspace, out);
  const Scene scene = LoadWorkspace(opt.workspace);
  WebBundleOptions bo = opt.bundle;
  bo.progress = [](int i, int n) {
    std::printf("photos %d/%d\r", i, n);
    std::fflush(stdout);
  };
  const WebBundleReport r = WriteWebBundle(scene, out, bo);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("\nwrote %s in %.1f s: %.2f MiB in all\n", out.c_str(), s, MiB(r.total()));
  std::printf("  photos  %3d   %8.2f MiB (JPEG)\n", r.photo_count, MiB(r.photos));
  std::printf("  points  %zu   %8.2f MiB\n", r.point_count, MiB(r.points));
  std::printf("  viewer + scene  %8.2f MiB\n", MiB(r.viewer + r.other));
  std::printf("  bundle / photos: %.2fx\n",
              r.photos > 0 ? static_cast<double>(r.total()) / static_cast<double>(r.photos) : 0.0);
  std::printf("serve it: python3 -m http.server -d %s 8000, then open http://localhost:8000/\n",
              out.c_str());
  return 0;
}

}  // namespace

CommandRunner SetupExportWeb(CLI::App& sub);
// Registered by hand: HDRIBR_COMMAND's name must be an identifier.
static const CommandRegistrar kExportWebCommand(
    "export-web", "A static folder that shows the capture in a web browser (WebGL2)",
    &SetupExportWeb, 75);

CommandRunner SetupExportWeb(CLI::App& sub) {
  auto opt = std::make_shared<ExportWebOptions>();
  sub.add_option("workspace", opt->workspace, "Workspace folder")->required();
  sub.add_option("out", opt->out, "Output folder (must not exist or be empty)")->required();
  sub.add_option("--max-photo-size", opt->bundle.max_photo_size,
                 "Longest side of the photos in the bundle, pixels (0 = as they are)")
      ->capture_default_str();
  sub.add_option("--jpeg-quality", opt->bundle.jpeg_quality,
                 "JPEG quality of the photos that are resized or re-encoded")
      ->capture_default_str();
  return [opt] {
    if (opt->bundle.max_photo_size < 0) throw UsageError("--max-photo-size must be >= 0");
    if (opt->bundle.jpeg_quality < 1 || opt->bundle.jpeg_quality > 100) {
      throw UsageError("--jpeg-quality must be in [1, 100]");
    }
    return Run(*opt);
  };
}

}  // namespace hdribr::cli
