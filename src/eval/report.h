// Evaluation reports: per-view scores of several rendering methods on common pixels, written
// as CSV, JSON and side-by-side PNGs (photo | render | error map). OpenGL-free.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "eval/depth_accuracy.h"
#include "eval/metrics.h"

namespace hdribr::eval {

// Scores of one method on one view.
struct MethodScores {
  std::string method;          // "hdribr", "nearest_photo", "point_colors"
  ImageScores scores;          // on the view's common mask (see ViewReport)
  double own_coverage = 0;     // share of the view's pixels this method rendered as valid
  double point_coverage = 0;   // share it rendered from points (the background left out)
  ImageScores own_scores;      // on every pixel it rendered
  double filled_coverage = 0;  // share it filled where no photo shows (render::FillPass)
  ImageScores fill_scores;     // on the pixels it filled
};

// One evaluated view: every method is scored on the same pixels, the intersection of all the
// methods' valid masks (and of the reference's, when it has one).
struct ViewReport {
  std::string name;
  int width = 0, height = 0;
  std::vector<MethodScores> methods;
  // hdribr's depth pass against the view's GT depth (synthetic captures, full size only).
  std::optional<DepthCounts> depth;
};

struct EvalReport {
  std::string kind;  // "leave-one-out" or "gt-novel"
  std::string workspace;
  std::string series;                           // the exposure series evaluated
  std::map<std::string, std::string> settings;  // free-form (size scale, blend mode, ...)
  std::vector<ViewReport> views;
};

// Mean of each method's scores over the views (views where the method has no pixel counted
// with coverage 0 and excluded from the PSNR/SSIM means), in first-appearance order.
std::vector<MethodScores> MeanScores(const EvalReport& report);

// The views' depth counts added up; nullopt when no view has them.
std::optional<DepthCounts> TotalDepthCounts(const EvalReport& report);

// CSV: header "view,method,psnr_db,ssim,coverage,own_coverage,point_coverage,own_psnr_db,
// own_ssim,pixels,filled_coverage,fill_psnr_db", one row per view and method, then rows named
// "mean". JSON: {kind, workspace, series, settings, views: [...], mean: [...], depth}
// (docs/formats.md). Both written atomically.
std::string FormatCsv(const EvalReport& report);
std::string FormatJson(const EvalReport& report);
void WriteReport(const EvalReport& report, const std::filesystem::path& csv_path,
                 const std::filesystem::path& json_path);

// A readable table of the means for the terminal.
std::string FormatMeanTable(const EvalReport& report);

// One line on the depth pass's accuracy over the views (TotalDepthCounts); empty without it.
std::string FormatDepthLine(const EvalReport& report);

// Intersection of 8-bit masks (non-zero = valid) of equal size; CV_8UC1 of 0/255.
cv::Mat CommonMask(const std::vector<cv::Mat>& masks);

// A float image in [0, 1] (CV_32FC3, as the renderer returns display values) as 8-bit,
// rounded and clamped. 8-bit input is returned as is.
cv::Mat ToLdr8(const cv::Mat& image);

// Per-pixel error map: the mean absolute channel difference of two 8-bit BGR images, scaled
// so that `full_scale` grey levels reach the top of the turbo colour map; pixels outside the
// mask are black.
cv::Mat ErrorMap(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& mask,
                 double full_scale = 32.0);

// Panels (8-bit BGR, equal size) placed left to right with a 4-pixel grey gap and a caption
// above each; pixels outside `mask` (when given) are darkened in every panel after the first.
cv::Mat SideBySide(const std::vector<cv::Mat>& panels, const std::vector<std::string>& captions,
                   const cv::Mat& mask = {});

}  // namespace hdribr::eval
