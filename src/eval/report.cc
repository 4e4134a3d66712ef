#include "eval/report.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.h"
#include "io/false_colour.h"

namespace hdribr::eval {
namespace {

std::string Num(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
  return buf;
}

nlohmann::json ScoresJson(const MethodScores& m) {
  return {{"method", m.method},
          {"psnr_db", m.scores.psnr_db},
          {"ssim", m.scores.ssim},
          {"coverage", m.scores.coverage},
          {"own_coverage", m.own_coverage},
          {"point_coverage", m.point_coverage},
          {"own_psnr_db", m.own_scores.psnr_db},
          {"own_ssim", m.own_scores.ssim},
          {"pixels", m.scores.pixels},
          {"filled_coverage", m.filled_coverage},
          {"fill_psnr_db", m.fill_scores.psnr_db}};
}

nlohmann::json DepthJson(const DepthCounts& c) {
  return {{"accuracy", c.accuracy()},        {"too_near", c.Share(c.too_near)},
          {"too_deep", c.Share(c.too_deep)}, {"missing", c.Share(c.missing)},
          {"leakage", c.leakage()},          {"gt_pixels", c.covered}};
}

std::string CsvRow(const std::string& view, const MethodScores& m) {
  return view + "," + m.method + "," + Num(m.scores.psnr_db, 4) + "," + Num(m.scores.ssim, 5) +
         "," + Num(m.scores.coverage, 5) + "," + Num(m.own_coverage, 5) + "," +
         Num(m.point_coverage, 5) + "," + Num(m.own_scores.psnr_db, 4) + "," +
         Num(m.own_scores.ssim, 5) + "," + std::to_string(m.scores.pixels) + "," +
         Num(m.filled_coverage, 5) + "," + Num(m.fill_scores.psnr_db, 4) + "\n";
}

}  // namespace

std::vector<MethodScores> MeanScores(const EvalReport& report) {
  struct Acc {
    double psnr = 0, ssim = 0, coverage = 0, own = 0, points = 0, own_psnr = 0, own_ssim = 0;
    double filled = 0, fill_psnr = 0;
    long long pixels = 0;
    int scored = 0, own_scored = 0, fill_scored = 0, views = 0;
  };
  std::vector<std::string> order;
  std::map<std::string, Acc> acc;
  for (const ViewReport& v : report.views) {
    for (const MethodScores& m : v.methods) {
      if (!acc.count(m.method)) order.push_back(m.method);
      Acc& a = acc[m.method];
      ++a.views;
      a.coverage += m.scores.coverage;
      a.own += m.own_coverage;
      a.points += m.point_coverage;
      a.filled += m.filled_coverage;
      a.pixels += m.scores.pixels;
      if (m.fill_scores.pixels > 0) {
        ++a.fill_scored;
        a.fill_psnr += m.fill_scores.psnr_db;
      }
      if (m.own_scores.pixels > 0) {
        ++a.own_scored;
        a.own_psnr += m.own_scores.psnr_db;
        a.own_ssim += m.own_scores.ssim;
      }
      if (m.scores.pixels > 0) {
        ++a.scored;
        a.psnr += m.scores.psnr_db;
        a.ssim += m.scores.ssim;
      }
    }
  }
  std::vector<MethodScores> out;
  for (const std::string& name : order) {
    const Acc& a = acc[name];
    MethodScores m;
    m.method = name;
    m.scores.psnr_db = a.scored ? a.psnr / a.scored : 0.0;
    m.scores.ssim = a.scored ? a.ssim / a.scored : 0.0;
    m.scores.coverage = a.views ? a.coverage / a.views : 0.0;
    m.scores.pixels = a.pixels;
    m.own_coverage = a.views ? a.own / a.views : 0.0;
    m.point_coverage = a.views ? a.points / a.views : 0.0;
    m.own_scores.psnr_db = a.own_scored ? a.own_psnr / a.own_scored : 0.0;
    m.own_scores.ssim = a.own_scored ? a.own_ssim / a.own_scored : 0.0;
    m.filled_coverage = a.views ? a.filled / a.views : 0.0;
    m.fill_scores.psnr_db = a.fill_scored ? a.fill_psnr / a.fill_scored : 0.0;
    out.push_back(m);
  }
  return out;
}

std::optional<DepthCounts> TotalDepthCounts(const EvalReport& report) {
  std::optional<DepthCounts> total;
  for (const ViewReport& v : report.views) {
    if (!v.depth) continue;
    if (!total) total.emplace();
    *total += *v.depth;
  }
  return total;
}

std::string FormatCsv(const EvalReport& report) {
  std::string s =
      "view,method,psnr_db,ssim,coverage,own_coverage,point_coverage,own_psnr_db,own_ssim,"
      "pixels,filled_coverage,fill_psnr_db\n";
  for (const ViewReport& v : report.views) {
    for (const MethodScores& m : v.methods) s += CsvRow(v.name, m);
  }
  for (const MethodScores& m : MeanScores(report)) s += CsvRow("mean", m);
  return s;
}

std::string FormatJson(const EvalReport& report) {
  nlohmann::json j;
  j["format"] = "hdribr-eval";
  j["version"] = 1;
  j["kind"] = report.kind;
  j["workspace"] = report.workspace;
  j["series"] = report.series;
  j["settings"] = report.settings;
  nlohmann::json views = nlohmann::json::array();
  for (const ViewReport& v : report.views) {
    nlohmann::json methods = nlohmann::json::array();
    for (const MethodScores& m : v.methods) methods.push_back(ScoresJson(m));
    nlohmann::json view = {
        {"view", v.name}, {"width", v.width}, {"height", v.height}, {"methods", methods}};
    if (v.depth) view["depth"] = DepthJson(*v.depth);
    views.push_back(view);
  }
  j["views"] = views;
  nlohmann::json mean = nlohmann::json::array();
  for (const MethodScores& m : MeanScores(report)) mean.push_back(ScoresJson(m));
  j["mean"] = mean;
  if (const auto depth = TotalDepthCounts(report)) j["depth"] = DepthJson(*depth);
  return j.dump(2) + "\n";
}

void WriteReport(const EvalReport& report, const std::filesystem::path& csv_path,
                 const std::filesystem::path& json_path) {
  WriteFileAtomic(csv_path, FormatCsv(report));
  WriteFileAtomic(json_path, FormatJson(report));
}

std::string FormatMeanTable(const EvalReport& report) {
  std::ostringstream s;
  char line[200];
  std::snprintf(line, sizeof(line), "%-16s %9s %8s %9s %9s %9s %9s %9s %9s %9s\n", "method",
                "PSNR dB", "SSIM", "coverage", "own cov.", "filled", "missing", "pts cov.",
                "own PSNR", "fill PSNR");
  s << line;
  for (const MethodScores& m : MeanScores(report)) {
    std::snprintf(line, sizeof(line),
                  "%-16s %9.2f %8.4f %8.1f%% %8.1f%% %8.1f%% %8.1f%% %8.1f%% %9.2f %9.2f\n",
                  m.method.c_str(), m.scores.psnr_db, m.scores.ssim, 100.0 * m.scores.coverage,
                  100.0 * m.own_coverage, 100.0 * m.filled_coverage,
                  100.0 * std::max(0.0, 1.0 - m.own_coverage - m.filled_coverage),
                  100.0 * m.point_coverage, m.own_scores.psnr_db, m.fill_scores.psnr_db);
    s << line;
  }
  return s.str();
}

std::string FormatDepthLine(const EvalReport& report) {
  const auto c = TotalDepthCounts(report);
  if (!c) return "";
  char line[256];
  std::snprintf(line, sizeof(line),
                "depth pass: %.2f%% of the GT surface pixels within %g%% of GT depth (too near "
                "%.2f%%, too deep %.2f%%, missing %.2f%%), leakage %.3f%%\n",
                100.0 * c->accuracy(), 100.0 * kDepthTolerance, 100.0 * c->Share(c->too_near),
                100.0 * c->Share(c->too_deep), 100.0 * c->Share(c->missing), 100.0 * c->leakage());
  return line;
}

cv::Mat CommonMask(const std::vector<cv::Mat>& masks) {
  if (masks.empty()) throw std::invalid_argument("CommonMask: no masks");
  cv::Mat out(masks[0].size(), CV_8UC1, cv::Scalar(255));
  for (const cv::Mat& m : masks) {
    if (m.size() != out.size() || m.type() != CV_8UC1) {
      throw std::invalid_argument("CommonMask: masks must be CV_8UC1 of equal size");
    }
    out.setTo(0, m == 0);
  }
  return out;
}

cv::Mat ToLdr8(const cv::Mat& image) {
  if (image.depth() == CV_8U) return image;
  cv::Mat out;
  image.convertTo(out, CV_MAKETYPE(CV_8U, image.channels()), 255.0);  // rounds and saturates
  return out;
}

cv::Mat ErrorMap(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& mask,
                 double full_scale) {
  if (reference.size() != test.size() || reference.type() != CV_8UC3 || test.type() != CV_8UC3) {
    throw std::invalid_argument("ErrorMap: needs two 8-bit BGR images of equal size");
  }
  cv::Mat diff, sum;
  cv::absdiff(reference, test, diff);
  diff.convertTo(diff, CV_32F);
  cv::transform(diff, sum, cv::Matx13f(1, 1, 1));
  return FalseColour(sum, 0, 3 * std::max(full_scale, 1e-6), mask);
}

cv::Mat SideBySide(const std::vector<cv::Mat>& panels, const std::vector<std::string>& captions,
                   const cv::Mat& mask) {
  if (panels.empty()) throw std::invalid_argument("SideBySide: no panels");
  const cv::Size size = panels[0].size();
  constexpr int kGap = 4;
  constexpr int kCaption = 20;
  const int n = static_cast<int>(panels.size());
  cv::Mat out(size.height + kCaption, n * size.width + (n - 1) * kGap, CV_8UC3,
              cv::Scalar(96, 96, 96));
  for (int i = 0; i < n; ++i) {
    const cv::Mat& p = panels[static_cast<size_t>(i)];
    if (p.size() != size || p.type() != CV_8UC3) {
      throw std::invalid_argument("SideBySide: panels must be 8-bit BGR of equal size");
    }
    cv::Mat panel = p.clone();
    if (i > 0 && !mask.empty()) {
      cv::Mat dark;
      panel.convertTo(dark, CV_8UC3, 0.3);
      dark.copyTo(panel, mask == 0);
    }
    const int x0 = i * (size.width + kGap);
    panel.copyTo(out(cv::Rect(x0, kCaption, size.width, size.height)));
    if (static_cast<size_t>(i) < captions.size()) {
      cv::putText(out, captions[static_cast<size_t>(i)], cv::Point(x0 + 3, kCaption - 6),
                  cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    }
  }
  return out;
}

}  // namespace hdribr::eval
