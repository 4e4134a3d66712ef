// `hdribr merge IMG... --times ... --out OUT.exr`: Debevec-Malik calibration and merge of an
// already aligned exposure stack, optionally tone-mapped with Reinhard 2002.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "core/error.h"
#include "hdr/debevec.h"
#include "hdr/exposure_stack.h"
#include "hdr/response_curve.h"
#include "hdr/tonemap.h"
#include "io/exr.h"
#include "io/image.h"

namespace hdribr::cli {
namespace {
namespace fs = std::filesystem;

struct MergeOptions {
  std::vector<std::string> images;
  std::vector<std::string> times;
  std::string times_file;
  std::vector<std::string> masks;
  std::string response;
  double lambda = CalibrationOptions().lambda;
  int samples = CalibrationOptions().samples;
  bool plain_debevec = false;
  std::string out;
  bool float_exr = false;
  std::string save_response;
  std::string tonemap;
  ReinhardOptions reinhard;
  double log_average = 0;  // 0: computed per image
};

std::vector<double> ResolveTimes(const MergeOptions& opt) {
  if (opt.times_file.empty()) {
    if (opt.times.size() != opt.images.size()) {
      throw UsageError(std::to_string(opt.images.size()) + " images but " +
                       std::to_string(opt.times.size()) + " --times");
    }
    std::vector<double> times;
    for (size_t i = 0; i < opt.times.size(); ++i) {
      times.push_back(ParseExposureTime(opt.times[i], "--times"));
    }
    return times;
  }
  const ShutterTimes file = ReadShutterTimes(opt.times_file);
  const bool named = std::any_of(file.names.begin(), file.names.end(),
                                 [](const std::string& n) { return !n.empty(); });
  if (!named) {
    if (file.times.size() != opt.images.size()) {
      throw InputError(opt.times_file, "lists " + std::to_string(file.times.size()) +
                                           " exposure times for " +
                                           std::to_string(opt.images.size()) + " images");
    }
    return file.times;
  }
  std::map<std::string, double> by_name;
  for (size_t i = 0; i < file.times.size(); ++i) {
    if (file.names[i].empty()) {
      throw InputError(opt.times_file, "mixes lines with and without image names");
    }
    by_name[file.names[i]] = file.times[i];
  }
  std::vector<double> times;
  for (const auto& image : opt.images) {
    const auto it = by_name.find(fs::path(image).filename().string());
    if (it == by_name.end()) {
      throw InputError(opt.times_file,
                       "has no exposure time for '" + fs::path(image).filename().string() + "'");
    }
    times.push_back(it->second);
  }
  return times;
}

int Run(const MergeOptions& opt) {
  if (!(opt.lambda >= 0) || !std::isfinite(opt.lambda)) {
    throw UsageError("--lambda must be a non-negative number");
  }
  if (!(opt.reinhard.key > 0) || !(opt.reinhard.gamma > 0) || !(opt.reinhard.exposure >= 0) ||
      opt.log_average < 0) {
    throw UsageError("--key and --gamma must be positive, --exposure and --log-average >= 0");
  }
  if (opt.images.size() == 1 && opt.response.empty()) {
    throw UsageError(
        "one image cannot calibrate a response (it needs two or more exposures); "
        "pass --response FILE to convert a single image to radiance");
  }
  if (!opt.masks.empty() && opt.masks.size() != opt.images.size()) {
    throw UsageError(std::to_string(opt.images.size()) + " images but " +
                     std::to_string(opt.masks.size()) + " --masks");
  }
  ExposureStack stack;
  stack.times = ResolveTimes(opt);
  for (const auto& path : opt.images) {
    stack.images.push_back(ReadImage(path));
    const cv::Mat& im = stack.images.back();
    const cv::Mat& first = stack.images.front();
    if (im.size() != first.size()) {
      throw InputError(path, "is " + std::to_string(im.cols) + "x" + std::to_string(im.rows) +
                                 " but " + opt.images.front() + " is " +
                                 std::to_string(first.cols) + "x" + std::to_string(first.rows) +
                                 " (the stack must be aligned)");
    }
  }
  for (size_t i = 0; i < opt.masks.size(); ++i) {
    const cv::Mat bgr = ReadImage(opt.masks[i]);
    if (bgr.size() != stack.images[0].size()) {
      throw InputError(opt.masks[i], "mask size differs from the images'");
    }
    cv::Mat grey;
    cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
    stack.masks.push_back(grey > 0);
  }
  for (size_t i = 0; i < stack.times.size(); ++i) {
    spdlog::debug("{}: exposure {} s", opt.images[i], stack.times[i]);
  }

  ResponseCurve response;
  if (!opt.response.empty()) {
    response = ReadResponseCurve(opt.response);
  } else {
    CalibrationOptions calibration;
    calibration.lambda = opt.lambda;
    calibration.samples = opt.samples;
    if (opt.plain_debevec) calibration = PlainDebevec(calibration);
    CalibrationStats stats;
    try {
      response = CalibrateDebevec(stack, calibration, &stats);
    } catch (const UsageError& e) {
      throw InputError(
          opt.images.front() + " (stack of " + std::to_string(opt.images.size()) + " images)",
          e.what());
    }
    spdlog::info(
        "calibrated response (lambda {}, samples used B/G/R {}/{}/{}, monotonicity "
        "fixes {}/{}/{})",
        opt.lambda, stats.samples_used[0], stats.samples_used[1], stats.samples_used[2],
        stats.monotone_fixes[0], stats.monotone_fixes[1], stats.monotone_fixes[2]);
  }

  cv::Mat valid;
  MergeStats merge_stats;
  cv::Mat radiance = MergeDebevec(stack, response, &valid, &merge_stats);
  const long channels = static_cast<long>(radiance.total()) * 3;
  spdlog::info(
      "merged {} images {}x{}: {} pixel-channels saturated everywhere (shortest "
      "exposure used), {} black everywhere (longest used), {} pixels valid nowhere",
      stack.images.size(), radiance.cols, radiance.rows, merge_stats.saturated, merge_stats.dark,
      merge_stats.invalid);
  if (merge_stats.saturated == channels || merge_stats.dark == channels) {
    spdlog::warn("every pixel is {} in every image: the radiance is only a bound",
                 merge_stats.saturated == channels ? "saturated" : "black");
  }
  if (!opt.float_exr) {
    constexpr float kHalfMax = 65504.0f;
    const int clamped = cv::countNonZero(radiance.reshape(1) > kHalfMax);
    if (clamped > 0) {
      spdlog::warn(
          "{} values exceed the half-float range and are clamped to 65504 (use "
          "--float)",
          clamped);
      cv::min(radiance, kHalfMax, radiance);
    }
  }
  cv::Mat display;
  if (!opt.tonemap.empty()) {
    ReinhardOptions reinhard = opt.reinhard;
    if (opt.log_average > 0) reinhard.log_average = opt.log_average;
    const double l_a =
        reinhard.log_average.value_or(LogAverageLuminance(radiance, valid, reinhard.epsilon));
    spdlog::info("tone mapping: log-average luminance {:.6g}, key {}, exposure {}, gamma {}", l_a,
                 reinhard.key, reinhard.exposure, reinhard.gamma);
    reinhard.log_average = l_a;
    display = DisplayToBgr8(ToneMapReinhard(radiance, reinhard, valid));
  }

  WriteExr(opt.out, radiance, opt.float_exr ? ExrPixel::kFloat : ExrPixel::kHalf);
  if (!opt.save_response.empty()) WriteResponseCurve(opt.save_response, response);
  if (!display.empty()) WriteImage(opt.tonemap, display);
  spdlog::info("wrote {}", opt.out);
  return 0;
}

}  // namespace

CommandRunner SetupMerge(CLI::App& sub);
HDRIBR_COMMAND(merge, "Calibrate (Debevec-Malik) and merge an aligned exposure stack to EXR",
               SetupMerge, 65);

CommandRunner SetupMerge(CLI::App& sub) {
  auto opt = std::make_shared<MergeOptions>();
  sub.add_option("images", opt->images, "Aligned 8-bit images of one view (PNG, JPEG)")->required();
  auto* times = sub.add_option("--times", opt->times,
                               "Exposure time of each image in seconds ('1/250' or '0.004')");
  auto* times_file = sub.add_option("--times-file", opt->times_file,
                                    "Text file: one time per line in image order, or "
                                    "'NAME TIME' lines");
  times->excludes(times_file);
  sub.callback([times, times_file] {
    if (times->count() == 0 && times_file->count() == 0) {
      throw CLI::RequiredError("--times or --times-file");
    }
  });
  sub.add_option("--masks", opt->masks,
                 "Validity mask per image (nonzero = valid); invalid pixels do not contribute");
  auto* response = sub.add_option("--response", opt->response,
                                  "Response file (docs/formats.md): skip calibration");
  sub.add_option("--lambda", opt->lambda, "Smoothness weight of the calibration")
      ->excludes(response)
      ->capture_default_str();
  sub.add_option("--samples", opt->samples, "Pixel samples per channel for the calibration")
      ->excludes(response)
      ->check(kAtLeastOne)
      ->capture_default_str();
  sub.add_flag("--plain-debevec", opt->plain_debevec,
               "Calibrate as Debevec-Malik published (smoothness in z, all samples, one solve)")
      ->excludes(response);
  sub.add_option("--out", opt->out, "Output radiance map (.exr, half RGB)")
      ->required()
      ->check(OutputFolderCheck())
      ->check(ExtensionCheck({".exr"}));
  sub.add_flag("--float", opt->float_exr, "Write 32-bit float instead of half");
  sub.add_option("--save-response", opt->save_response, "Write the response curve used (JSON)")
      ->check(OutputFolderCheck());
  sub.add_option("--tonemap", opt->tonemap, "Also write a Reinhard tone-mapped image (.png/.jpg)")
      ->check(OutputFolderCheck())
      ->check(ExtensionCheck({".png", ".jpg", ".jpeg"}));
  sub.add_option("--key", opt->reinhard.key, "Reinhard key k")->capture_default_str();
  sub.add_option("--exposure", opt->reinhard.exposure, "Display exposure multiplier")
      ->capture_default_str();
  sub.add_option("--gamma", opt->reinhard.gamma, "Display gamma")->capture_default_str();
  sub.add_option("--log-average", opt->log_average,
                 "Fixed log-average luminance L_a (default: computed from the image)");
  return [opt] { return Run(*opt); };
}

}  // namespace hdribr::cli
