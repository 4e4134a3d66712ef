// `hdribr bench dense`: wall time of the CPU dense stage (hdribr's PatchMatch MVS and fusion)
// alone on an existing workspace's undistorted model and photos, split into depth maps and
// fusion; the workspace is only read.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "core/error.h"
#include "frontend/dense_mvs.h"
#include "io/colmap_model.h"

namespace hdribr::cli {
namespace {
namespace fs = std::filesystem;

struct BenchDenseOptions {
  std::string workspace;
  int repeats = 1;
  DenseOptions dense;
  std::string json_path;
};

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// CPU seconds of the process (all threads, user + system): on a shared machine the wall time
// follows the other jobs' load, the CPU time hardly.
double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

int Run(const BenchDenseOptions& opt) {
  const fs::path ws(opt.workspace);
  if (!fs::is_directory(ws / "sparse") || !fs::is_directory(ws / "images")) {
    throw InputError(ws, "not a reconstructed workspace (no sparse/ and images/)");
  }
  const ColmapModel model = ReadColmapModel(ws / "sparse");
  std::vector<double> total, depth_maps, fusion, cpu_total, cpu_depth_maps;
  DenseResult result;
  for (int r = 0; r < opt.repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = CpuSeconds();
    // The last progress call ends the depth maps (with the photos' loading before them).
    double maps_done = 0, cpu_maps_done = 0;
    result = DensifyCpu(model, ws / "images", opt.dense, [&](int done, int count) {
      if (done == count) {
        maps_done = SecondsSince(start);
        cpu_maps_done = CpuSeconds();
      }
    });
    total.push_back(SecondsSince(start));
    depth_maps.push_back(maps_done);
    fusion.push_back(total.back() - maps_done);
    cpu_total.push_back(CpuSeconds() - cpu_start);
    cpu_depth_maps.push_back(cpu_maps_done - cpu_start);
  }
  std::FILE* table = TableStream(opt.json_path);
  std::fprintf(table, "%-10s %6s %8s %10s %10s %10s %10s\n", "workspace", "maps", "size", "points",
               "total_s", "maps_s", "fusion_s");
  std::fprintf(table, "%-10s %6d %8d %10zu %10.2f %10.2f %10.2f\n", ws.filename().string().c_str(),
               result.num_depth_maps, result.depth_map_size, result.cloud.size(), Median(total),
               Median(depth_maps), Median(fusion));
  const nlohmann::json j = {{"benchmark", "dense"},
                            {"workspace", ws.lexically_normal().string()},
                            {"method", opt.dense.method == DenseMethod::kSweep ? "sweep" : "cpu"},
                            {"depth_maps", result.num_depth_maps},
                            {"depth_map_size", result.depth_map_size},
                            {"points", result.cloud.size()},
                            {"repeats", opt.repeats},
                            {"total_s", Median(total)},
                            {"depth_maps_s", Median(depth_maps)},
                            {"fusion_s", Median(fusion)},
                            {"cpu_total_s", Median(cpu_total)},
                            {"cpu_depth_maps_s", Median(cpu_depth_maps)},
                            {"per_repeat_total_s", total}};
  EmitJson(opt.json_path, j);
  return 0;
}

}  // namespace

CommandRunner SetupBenchDense(CLI::App& sub);
HDRIBR_BENCH(dense, "CPU dense stage (PatchMatch MVS + fusion) alone on a workspace: wall time",
             SetupBenchDense);

CommandRunner SetupBenchDense(CLI::App& sub) {
  auto opt = std::make_shared<BenchDenseOptions>();
  sub.add_option("workspace", opt->workspace, "Reconstructed workspace (read only)")->required();
  sub.add_option("--repeats", opt->repeats, "Runs (the median is reported)")
      ->check(kAtLeastOne)
      ->capture_default_str();
  sub.add_option("--dense-size", opt->dense.max_size,
                 "Largest side of the depth maps (0: from the photo count, as reconstruct)")
      ->check(kAtLeastZero)
      ->capture_default_str();
  sub.add_flag_callback(
      "--sweep", [opt] { opt->dense.method = DenseMethod::kSweep; },
      "The plane sweep instead of PatchMatch");
  sub.add_option("--threads", opt->dense.threads, "Threads (0: all cores)")
      ->check(kAtLeastZero)
      ->capture_default_str();
  sub.add_option("--json", opt->json_path, "Write the JSON here instead of stdout")
      ->check(OutputFolderCheck());
  return [opt] { return Run(*opt); };
}

}  // namespace hdribr::cli
