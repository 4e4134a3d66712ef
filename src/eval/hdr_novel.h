// HDR-NeRF's three figures at the ground-truth novel views of a synthetic capture with several
// exposures: LDR-OE (re-exposed at the input exposures), LDR-NE (at exposures no photo had) and
// HDR (mu-law PSNR of the radiance), plus the median |log ratio| of the radiance.
#pragma once

#include <string>
#include <vector>

#include "core/scene.h"
#include "eval/leave_one_out.h"
#include "eval/metrics.h"
#include "gl/shader_library.h"

namespace hdribr::eval {

struct HdrNovelScores {
  std::string method;    // "hdribr", "nearest_photo"
  ImageScores ldr_oe;    // mean over views and input exposures
  ImageScores ldr_ne;    // mean over views and new exposures
  ImageScores hdr;       // mean over views (CompareHdr)
  double log_ratio = 0;  // mean over views of the median |log ratio|, per-channel scale
};

struct HdrNovelReport {
  std::vector<double> oe_times_s;  // the input exposures (the series' EXIF times)
  std::vector<double> ne_times_s;  // halfway (in stops) between them, and a stop beyond each end
  std::vector<HdrNovelScores> methods;
  int views = 0;
  std::string response_source;
};

// Renders every GT novel view of options.gt_capture in radiance from all photos (hdribr and the
// nearest photo, both re-exposed through the response of RadianceSetup), and scores them on
// the GT surface pixels both cover. Throws UsageError when the workspace has one exposure.
HdrNovelReport RunHdrNovelEvaluation(const Scene& scene, const gl::ShaderLibrary& shaders,
                                     const EvalOptions& options);

// The report as a table (and JSON, format "hdribr-eval-hdr").
std::string FormatHdrNovelTable(const HdrNovelReport& report);
std::string FormatHdrNovelJson(const HdrNovelReport& report);

}  // namespace hdribr::eval
