// `hdribr bench merge`: hdribr's Debevec-Malik calibration + merge against OpenCV's
// (cv::CalibrateDebevec + cv::MergeDebevec) on the same stack, wall time and agreement.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <string>
#include <vector>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "core/error.h"
#include "hdr/debevec.h"
#include "hdr/opencv_reference.h"
#include "hdr/radiance_compare.h"
#include "io/image.h"

namespace hdribr::cli {
namespace {
namespace fs = std::filesystem;

struct BenchMergeOptions {
  std::string dataset = "../shared/datasets/memorial";
  int repeats = 5;
  int samples = CalibrationOptions().samples;
  double lambda = CalibrationOptions().lambda;
  int opencv_samples = OpenCvDebevecOptions().samples;
  double opencv_lambda = OpenCvDebevecOptions().lambda;
  std::string json_path;
};

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

template <typename F>
double TimeMs(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// Images of the stack: the *.png/*.jpg files of the folder sorted by name, with
// shutter_times.txt (one time per line in that order, or 'NAME TIME' lines).
ExposureStack LoadStack(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw InputError(dir, "no such dataset folder");
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string ext = LowerExtension(entry.path());
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  const ShutterTimes times = ReadShutterTimes(dir / "shutter_times.txt");
  ExposureStack stack;
  for (size_t i = 0; i < files.size(); ++i) {
    if (!times.names[0].empty()) {
      const auto it =
          std::find(times.names.begin(), times.names.end(), files[i].filename().string());
      if (it == times.names.end()) continue;
      stack.times.push_back(times.times[it - times.names.begin()]);
    }
    stack.images.push_back(ReadImage(files[i]));
  }
  if (times.names[0].empty()) {
    if (times.times.size() != stack.images.size()) {
      throw InputError(dir / "shutter_times.txt",
                       "lists " + std::to_string(times.times.size()) + " times for " +
                           std::to_string(stack.images.size()) + " images");
    }
    stack.times = times.times;
  }
  stack.Validate();
  return stack;
}

int Run(const BenchMergeOptions& opt) {
  if (opt.repeats < 1) throw UsageError("--repeats must be at least 1");
  const ExposureStack stack = LoadStack(opt.dataset);
  CalibrationOptions calibration;
  calibration.samples = opt.samples;
  calibration.lambda = opt.lambda;
  OpenCvDebevecOptions cv_options;
  cv_options.samples = opt.opencv_samples;
  cv_options.lambda = static_cast<float>(opt.opencv_lambda);

  std::vector<double> ours_cal, ours_merge, ours_total, cv_cal, cv_merge, cv_total;
  cv::Mat ours, theirs;
  for (int r = 0; r < opt.repeats; ++r) {
    ResponseCurve curve;
    const double a = TimeMs([&] { curve = CalibrateDebevec(stack, calibration); });
    const double b = TimeMs([&] { ours = MergeDebevec(stack, curve); });
    cv::Mat response;
    const double c =
        TimeMs([&] { response = OpenCvCalibrateDebevec(stack.images, stack.times, cv_options); });
    const double d =
        TimeMs([&] { theirs = OpenCvMergeDebevec(stack.images, stack.times, response); });
    ours_cal.push_back(a);
    ours_merge.push_back(b);
    ours_total.push_back(a + b);
    cv_cal.push_back(c);
    cv_merge.push_back(d);
    cv_total.push_back(c + d);
  }
  const double agreement = MedianAbsLogRatio(ours, theirs);
  nlohmann::json j;
  j["benchmark"] = "merge";
  j["dataset"] = fs::path(opt.dataset).lexically_normal().string();
  j["images"] = stack.images.size();
  j["width"] = stack.images[0].cols;
  j["height"] = stack.images[0].rows;
  j["repeats"] = opt.repeats;
  j["threads"] = cv::getNumThreads();
  j["hdribr"] = {{"samples", opt.samples},
                 {"lambda", opt.lambda},
                 {"calibrate_ms", Median(ours_cal)},
                 {"merge_ms", Median(ours_merge)},
                 {"total_ms", Median(ours_total)}};
  j["opencv"] = {{"version", CV_VERSION},        {"samples", opt.opencv_samples},
                 {"lambda", opt.opencv_lambda},  {"calibrate_ms", Median(cv_cal)},
                 {"merge_ms", Median(cv_merge)}, {"total_ms", Median(cv_total)}};
  j["opencv_over_hdribr_time"] = Median(cv_total) / Median(ours_total);
  j["median_abs_log_ratio"] = agreement;

  FILE* table = TableStream(opt.json_path);
  std::fprintf(table, "merge benchmark: %zu images %dx%d, %d repeats (median), %d threads\n",
               stack.images.size(), stack.images[0].cols, stack.images[0].rows, opt.repeats,
               cv::getNumThreads());
  std::fprintf(table, "%-28s %12s %10s %10s\n", "", "calibrate ms", "merge ms", "total ms");
  std::fprintf(table, "%-28s %12.1f %10.1f %10.1f\n",
               ("hdribr (" + std::to_string(opt.samples) + " samples)").c_str(), Median(ours_cal),
               Median(ours_merge), Median(ours_total));
  std::fprintf(
      table, "%-28s %12.1f %10.1f %10.1f\n",
      ("OpenCV " CV_VERSION " (" + std::to_string(opt.opencv_samples) + " samples)").c_str(),
      Median(cv_cal), Median(cv_merge), Median(cv_total));
  std::fprintf(table, "OpenCV / hdribr time: %.1fx; radiance median |log ratio| %.4f\n",
               Median(cv_total) / Median(ours_total), agreement);
  EmitJson(opt.json_path, j);
  return 0;
}

}  // namespace

CommandRunner SetupBenchMerge(CLI::App& sub);
HDRIBR_BENCH(merge, "Debevec calibration + merge: hdribr vs OpenCV (memorial)", SetupBenchMerge);

CommandRunner SetupBenchMerge(CLI::App& sub) {
  auto opt = std::make_shared<BenchMergeOptions>();
  sub.add_option("--dataset", opt->dataset, "Folder with the images and shutter_times.txt")
      ->capture_default_str();
  sub.add_option("--repeats", opt->repeats, "Repetitions (the median is reported)")
      ->capture_default_str();
  sub.add_option("--samples", opt->samples, "hdribr calibration samples per channel")
      ->capture_default_str()
      ->check(kAtLeastOne);
  sub.add_option("--opencv-samples", opt->opencv_samples, "OpenCV calibration samples")
      ->capture_default_str();
  sub.add_option("--lambda", opt->lambda, "hdribr smoothness weight")->capture_default_str();
  sub.add_option("--opencv-lambda", opt->opencv_lambda, "OpenCV smoothness weight")
      ->capture_default_str();
  sub.add_option("--json", opt->json_path, "Write the JSON here instead of stdout")
      ->check(OutputFolderCheck());
  return [opt] {
    if (!(opt->lambda >= 0) || !std::isfinite(opt->lambda)) {
      throw UsageError("--lambda must be a non-negative number");
    }
    return Run(*opt);
  };
}

}  // namespace hdribr::cli
