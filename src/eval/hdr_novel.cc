#include "eval/hdr_novel.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "core/error.h"
#include "eval/gt_views.h"
#include "eval/hdr_metrics.h"
#include "eval/radiance_setup.h"
#include "hdr/radiance_compare.h"
#include "io/exr.h"
#include "render/renderer.h"

namespace hdribr::eval {
namespace {

// Running means of ImageScores.
struct Mean {
  double psnr = 0, ssim = 0;
  int n = 0;
  void Add(const ImageScores& s) {
    psnr += s.psnr_db;
    ssim += s.ssim;
    ++n;
  }
  ImageScores Get() const {
    ImageScores s;
    if (n > 0) {
      s.psnr_db = psnr / n;
      s.ssim = ssim / n;
    }
    return s;
  }
};

// The series' EXIF exposure times (seconds), darkest first, distinct.
std::vector<double> InputTimes(const Scene& scene) {
  std::set<double> times;
  for (const ExposureSeries& s : scene.series) {
    for (int i : s.photo_indices) {
      const Exposure& e = scene.photos[static_cast<size_t>(i)].exposure;
      if (e.time_s) {
        times.insert(*e.time_s);
        break;
      }
    }
  }
  return {times.begin(), times.end()};
}

}  // namespace

HdrNovelReport RunHdrNovelEvaluation(const Scene& scene, const gl::ShaderLibrary& shaders,
                                     const EvalOptions& options) {
  HdrNovelReport report;
  report.oe_times_s = InputTimes(scene);
  if (report.oe_times_s.size() < 2) {
    throw UsageError("HDR figures need photos of at least two exposure times");
  }
  const std::vector<double>& oe = report.oe_times_s;
  report.ne_times_s.push_back(oe.front() / 2);
  for (size_t i = 0; i + 1 < oe.size(); ++i)
    report.ne_times_s.push_back(std::sqrt(oe[i] * oe[i + 1]));
  report.ne_times_s.push_back(oe.back() * 2);

  const RadianceSetup setup(scene, shaders, options.response, options.renderer);
  report.response_source = setup.source();
  const Scene& s = setup.scene();
  const double gain = s.ExposureGain();
  const synth::SyntheticResponse truth = ReadCaptureResponse(options.gt_capture);
  render::Renderer renderer(shaders, s, setup.RendererOptionsFor(options.renderer));
  const render::BlendMode mode = renderer.blend_options().mode;
  const std::vector<std::string> names = {"hdribr", "nearest_photo"};
  std::vector<Mean> oe_mean(names.size()), ne_mean(names.size()), hdr_mean(names.size());
  std::vector<double> log_ratio(names.size(), 0.0);

  for (const GtView& v : ReadGtNovelViews(options.gt_capture)) {
    const cv::Size size(
        std::max(1, static_cast<int>(std::lround(v.camera.width * options.size_scale))),
        std::max(1, static_cast<int>(std::lround(v.camera.height * options.size_scale))));
    cv::Mat gt = ReadExr(v.radiance_path);
    if (gt.type() != CV_32FC3) throw InputError(v.radiance_path, "expected RGB radiance");
    cv::resize(gt, gt, size, 0, 0, cv::INTER_AREA);
    cv::Mat mask(size, CV_8UC1, cv::Scalar(255));
    if (std::filesystem::exists(v.depth_path)) {
      cv::resize(ReadExr(v.depth_path) > 0, mask, size, 0, 0, cv::INTER_NEAREST);
    }
    std::vector<cv::Mat> radiance;
    for (const std::string& name : names) {
      renderer.blend_options().mode = name == "hdribr" ? mode : render::BlendMode::kNearestPhoto;
      const render::RenderImages r =
          renderer.RenderToImages(v.camera, v.cam_from_world, size.width, size.height);
      radiance.push_back(r.color);
      cv::bitwise_and(mask, r.valid, mask);
    }
    renderer.blend_options().mode = mode;
    if (cv::countNonZero(mask) == 0) {
      spdlog::warn("view {}: no pixel both methods render on the GT surface", v.name);
      continue;
    }
    ++report.views;
    for (size_t m = 0; m < names.size(); ++m) {
      for (double t : report.oe_times_s) {
        oe_mean[m].Add(
            CompareImages(RadianceToLdr(gt, truth, t), setup.Expose(radiance[m], t * gain), mask));
      }
      for (double t : report.ne_times_s) {
        ne_mean[m].Add(
            CompareImages(RadianceToLdr(gt, truth, t), setup.Expose(radiance[m], t * gain), mask));
      }
      hdr_mean[m].Add(CompareHdr(gt, radiance[m], mask));
      log_ratio[m] += MedianAbsLogRatio(radiance[m], gt, mask, true);
    }
  }
  if (report.views == 0) throw UsageError("no GT novel view could be scored");
  for (size_t m = 0; m < names.size(); ++m) {
    report.methods.push_back({names[m], oe_mean[m].Get(), ne_mean[m].Get(), hdr_mean[m].Get(),
                              log_ratio[m] / report.views});
  }
  return report;
}

std::string FormatHdrNovelTable(const HdrNovelReport& report) {
  std::string out = fmt::format(
      "HDR at {} GT novel views (response {}; LDR-OE at {} input exposures, LDR-NE at {} new "
      "ones, HDR = mu-law PSNR):\n",
      report.views, report.response_source, report.oe_times_s.size(), report.ne_times_s.size());
  out += fmt::format("{:<16} {:>10} {:>8} {:>10} {:>8} {:>8} {:>8} {:>10}\n", "method", "LDR-OE dB",
                     "SSIM", "LDR-NE dB", "SSIM", "HDR dB", "SSIM", "|log r|");
  for (const HdrNovelScores& m : report.methods) {
    out += fmt::format("{:<16} {:>10.2f} {:>8.4f} {:>10.2f} {:>8.4f} {:>8.2f} {:>8.4f} {:>10.4f}\n",
                       m.method, m.ldr_oe.psnr_db, m.ldr_oe.ssim, m.ldr_ne.psnr_db, m.ldr_ne.ssim,
                       m.hdr.psnr_db, m.hdr.ssim, m.log_ratio);
  }
  return out;
}

std::string FormatHdrNovelJson(const HdrNovelReport& report) {
  nlohmann::json methods = nlohmann::json::array();
  for (const HdrNovelScores& m : report.methods) {
    methods.push_back({{"method", m.method},
                       {"ldr_oe_psnr_db", m.ldr_oe.psnr_db},
                       {"ldr_oe_ssim", m.ldr_oe.ssim},
                       {"ldr_ne_psnr_db", m.ldr_ne.psnr_db},
                       {"ldr_ne_ssim", m.ldr_ne.ssim},
                       {"hdr_psnr_db", m.hdr.psnr_db},
                       {"hdr_ssim", m.hdr.ssim},
                       {"median_abs_log_ratio", m.log_ratio}});
  }
  const nlohmann::json j = {{"format", "hdribr-eval-hdr"},
                            {"version", 1},
                            {"views", report.views},
                            {"response", report.response_source},
                            {"oe_times_s", report.oe_times_s},
                            {"ne_times_s", report.ne_times_s},
                            {"methods", methods}};
  return j.dump(2) + "\n";
}

}  // namespace hdribr::eval
