// `hdribr calibrate WORKSPACE`: the camera response and every photo's exposure from the point
// cloud (render/cloud_calibration.h), written to WORKSPACE/calib/ where `hdr`, `render`,
// `view` and `eval` find them.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/cli_util.h"
#include "cli/command.h"
#include "cli/render_options.h"
#include "cli/workspace_setup.h"
#include "core/error.h"
#include "hdr/response_curve.h"
#include "io/atomic_file.h"

namespace hdribr::cli {
namespace {
namespace fs = std::filesystem;

struct CalibrateOptions {
  std::string workspace;
  int samples = GatherOptions().samples;
  double lambda = MultiViewOptions().lambda;
  bool per_channel = false;
  double response_prior = -1;  // < 0: chosen by cross-validation
  double channel_sigma = MultiViewOptions().channel_sigma;
  bool verbose = false;
  bool no_depth_cache = false;
  std::string truth;  // a synthetic capture: errors against its true response and exposures
};

// Median and largest |ln(a_i / b_i) - median| in percent (exp - 1): errors up to one factor.
std::pair<double, double> FactorFreeErrors(const std::vector<double>& log_ratio) {
  std::vector<double> v = log_ratio;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  const double centre = v[v.size() / 2];
  std::vector<double> err;
  for (double r : log_ratio) err.push_back(std::abs(r - centre));
  std::sort(err.begin(), err.end());
  return {100 * std::expm1(err[err.size() / 2]), 100 * std::expm1(err.back())};
}

void ReportTruth(const RadiometricCalibration& c, const ResponseCurve& got,
                 const fs::path& capture) {
  const ResponseCurve truth = ReadResponseCurve(capture / "calib" / "response.json");
  std::printf("response vs truth, RMS linear error over 10-245 DN: B %.4f  G %.4f  R %.4f\n",
              RmsLinearError(got, truth, 0), RmsLinearError(got, truth, 1),
              RmsLinearError(got, truth, 2));
  const fs::path json_path = capture / "gt" / "capture.json";
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(ReadFileToString(json_path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(json_path, std::string("not a capture description: ") + e.what());
  }
  if (!j.contains("photos")) {
    std::printf("%s has no per-photo exposures (made before them): exposures not compared\n",
                json_path.c_str());
    return;
  }
  const double gain = j.value("iso", 100.0) / 100.0 / std::pow(j.value("f_number", 1.0), 2);
  std::vector<double> calibrated, exif;
  for (const auto& p : j["photos"]) {
    const auto it = c.photos.find(p.at("name").get<std::string>());
    if (it == c.photos.end()) continue;
    const double truth_rel = p.at("exposure_time_s").get<double>() * gain;
    calibrated.push_back(std::log(it->second.relative / truth_rel));
    exif.push_back(std::log(it->second.exif_relative / truth_rel));
  }
  if (calibrated.empty()) return;
  const auto [cal_med, cal_max] = FactorFreeErrors(calibrated);
  const auto [exif_med, exif_max] = FactorFreeErrors(exif);
  std::printf(
      "exposures vs truth (%zu photos, up to one factor): calibrated median %.2f %%, max %.2f "
      "%%; EXIF median %.2f %%, max %.2f %%\n",
      calibrated.size(), cal_med, cal_max, exif_med, exif_max);
}

int Run(const CalibrateOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  render::CloudCalibrationOptions options;
  options.gather.samples = opt.samples;
  options.solve.lambda = opt.lambda;
  options.solve.per_channel_exposure = opt.per_channel;
  if (opt.response_prior >= 0) {
    options.solve.response_prior = opt.response_prior;
    options.solve.response_prior_candidates.clear();
  }
  options.solve.channel_sigma = opt.channel_sigma;
  options.depth_cache_dir = WorkspaceDepthCache(opt.workspace, opt.no_depth_cache);
  const WorkspaceCalibration c = CalibrateWorkspace(opt.workspace, options);
  const render::CloudCalibrationResult& result = c.result;
  const RadiometricCalibration& calibration = c.calibration;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const MultiViewStats& st = result.calibration.stats;
  int solved = 0;
  double lo = HUGE_VAL, hi = 0;
  for (const auto& [name, e] : calibration.photos) {
    solved += e.calibrated ? 1 : 0;
    lo = std::min(lo, e.relative);
    hi = std::max(hi, e.relative);
  }
  std::printf(
      "calibrated %d of %zu photos from %d points (%d observations, %d rejected), residual "
      "%.4f; exposures span %.2f stops; %s\n",
      solved, calibration.photos.size(), st.samples_used, st.observations_used,
      st.observations_rejected, st.residual_rms, std::log2(hi / lo),
      st.exponent_from_prior ? "scale from EXIF"
                             : "no EXIF ratios: exposures up to a factor and an exponent");
  for (const auto& [name, e] : calibration.photos) {
    if (!e.calibrated)
      std::printf("  %s: not calibrated (no usable overlap), EXIF kept\n", name.c_str());
  }
  if (!st.prior_code_error.empty()) {
    std::printf("response prior %g chosen by cross-validation; re-exposure error (DN):",
                st.response_prior);
    for (size_t k = 0; k < st.prior_code_error.size(); ++k) {
      std::printf(" %g: %.3f", options.solve.response_prior_candidates[k], st.prior_code_error[k]);
    }
    std::printf("\n");
  }
  if (opt.verbose) {
    const MultiViewCalibration& m = result.calibration;
    std::printf("photo  ln t  (B-t G-t R-t)  exif-t  obs  rms\n");
    for (size_t i = 0; i < m.log_exposure.size(); ++i) {
      const auto& ch = m.channel_log_exposure[i];
      std::printf("%3zu %7.3f  (%+.3f %+.3f %+.3f)  %+.3f %6d %.4f\n", i, m.log_exposure[i],
                  ch[0] - m.log_exposure[i], ch[1] - m.log_exposure[i], ch[2] - m.log_exposure[i],
                  result.prior_log_exposure[i] - m.log_exposure[i], m.photo_observations[i],
                  m.photo_residual_rms[i]);
    }
  }
  std::printf("wrote %s and %s in %.1f s\n", c.response_file.c_str(), c.exposures_file.c_str(),
              seconds);
  if (!opt.truth.empty()) ReportTruth(calibration, result.calibration.response, opt.truth);
  return 0;
}

}  // namespace

CommandRunner SetupCalibrate(CLI::App& sub);
HDRIBR_COMMAND(calibrate,
               "Camera response and every photo's exposure from the point cloud (calib/)",
               SetupCalibrate, 28);

CommandRunner SetupCalibrate(CLI::App& sub) {
  auto opt = std::make_shared<CalibrateOptions>();
  sub.add_option("workspace", opt->workspace, "Workspace folder")->required();
  sub.add_option("--samples", opt->samples, "Scene points to sample")->capture_default_str();
  sub.add_option("--lambda", opt->lambda, "Smoothness weight of the response")
      ->capture_default_str();
  CLI::Option* prior = sub.add_option(
      "--response-prior", opt->response_prior,
      "Weight of sRGB's slope as a prior on the response (default: chosen by cross-validation)");
  sub.add_flag("--per-channel", opt->per_channel, "One exposure per photo and channel");
  sub.add_option("--channel-sigma", opt->channel_sigma, "Prior sd of a channel's exposure")
      ->capture_default_str();
  sub.add_flag("-v,--verbose", opt->verbose, "Per-photo exposures and residuals");
  AddNoDepthCacheOption(sub, opt->no_depth_cache);
  sub.add_option("--truth", opt->truth,
                 "Synthetic capture folder: report the errors against its true response and "
                 "exposures");
  return [opt, prior] {
    if (opt->samples < 16) throw UsageError("--samples must be at least 16");
    if (!(opt->lambda > 0)) throw UsageError("--lambda must be > 0");
    if (prior->count() > 0 && !(opt->response_prior >= 0)) {
      throw UsageError("--response-prior must be >= 0");
    }
    if (!(opt->channel_sigma > 0)) throw UsageError("--channel-sigma must be > 0");
    return Run(*opt);
  };
}

}  // namespace hdribr::cli
