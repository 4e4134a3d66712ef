#include "eval/quality_suite.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <regex>
#include <set>

#include "core/error.h"
#include "synth/scene_layouts.h"

namespace hdribr::eval {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be read");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(path, std::string("is not valid JSON: ") + e.what());
  }
}

// A size "WxH" into the capture options.
void ParseCaptureSize(const std::string& size, synth::CaptureOptions& o) {
  int w = 0, h = 0;
  char x = 0;
  if (std::sscanf(size.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x') {
    throw std::invalid_argument("size must be WxH, got '" + size + "'");
  }
  o.width = w;
  o.height = h;
}

SuiteCapture ParseCapture(const json& c) {
  SuiteCapture s;
  s.name = c.at("name").get<std::string>();
  static const std::regex kSafe("[A-Za-z0-9_-]+");
  if (!std::regex_match(s.name, kSafe)) {
    throw std::invalid_argument("capture name '" + s.name + "' is not [A-Za-z0-9_-]+");
  }
  s.split = c.at("split").get<std::string>();
  if (s.split != "tune" && s.split != "check") {
    throw std::invalid_argument(s.name + ": split must be tune or check, got '" + s.split + "'");
  }
  s.quick = c.value("quick", false);
  s.note = c.value("note", "");
  s.eval_args = c.value("eval", std::vector<std::string>{});
  if (c.contains("synth") == c.contains("photos")) {
    throw std::invalid_argument(s.name + ": give exactly one of synth and photos");
  }
  if (c.contains("photos")) {
    s.photos = c.at("photos").get<std::string>();
    if (s.photos.is_absolute()) throw std::invalid_argument(s.name + ": photos must be relative");
    return s;
  }
  const json& j = c.at("synth");
  synth::CaptureOptions o;
  o.scene = j.value("scene", o.scene);
  o.seed = j.value("seed", o.seed);
  o.series = j.value("series", o.series);
  o.views = j.value("views", o.views);
  o.novel_views = j.value("novel_views", o.novel_views);
  o.exposure = j.value("exposure", o.exposure);
  o.exif_error = j.value("exif_error", o.exif_error);
  o.ev_step = j.value("ev_step", o.ev_step);
  if (j.contains("size")) ParseCaptureSize(j.at("size").get<std::string>(), o);
  const std::vector<std::string> scenes = synth::SceneNames();
  if (std::find(scenes.begin(), scenes.end(), o.scene) == scenes.end()) {
    throw std::invalid_argument(s.name + ": unknown scene '" + o.scene + "'");
  }
  s.synth = o;
  return s;
}

std::optional<double> Get(const json& j, const char* key) {
  if (!j.contains(key) || !j.at(key).is_number()) return std::nullopt;
  return j.at(key).get<double>();
}

// The mean scores of one method in an eval.json.
const json* MeanOf(const json& eval, const std::string& method) {
  for (const json& m : eval.at("mean")) {
    if (m.at("method") == method) return &m;
  }
  return nullptr;
}

json ReadEval(const fs::path& dir) {
  const fs::path path = dir / "eval.json";
  const json j = ReadJson(path);
  if (j.value("format", "") != "hdribr-eval" || !j.contains("mean")) {
    throw InputError(path, "is not an hdribr eval report");
  }
  return j;
}

// One column of the table: how to read it from the figures, how to print it, which way is
// better (for the worst capture of a split).
struct Column {
  const char* title;
  std::function<std::optional<double>(const CaptureFigures&)> get;
  const char* format;  // printf of one double
  double scale;        // printed value = figure * scale
  bool higher_is_better;
};

const std::vector<Column>& Columns() {
  using F = CaptureFigures;
  static const std::vector<Column> columns = {
      {"LOO dB", [](const F& f) { return f.psnr; }, "%.2f", 1, true},
      {"nearest dB", [](const F& f) { return f.nearest_psnr; }, "%.2f", 1, true},
      {"margin dB", [](const F& f) { return f.margin(); }, "%+.2f", 1, true},
      {"SSIM", [](const F& f) { return f.ssim; }, "%.3f", 1, true},
      {"nearest SSIM", [](const F& f) { return f.nearest_ssim; }, "%.3f", 1, true},
      {"own dB", [](const F& f) { return f.own_psnr; }, "%.2f", 1, true},
      {"own cov. %", [](const F& f) { return f.own_coverage; }, "%.1f", 100, true},
      {"GT own dB", [](const F& f) { return f.gt_own_psnr; }, "%.2f", 1, true},
      {"gap dB", [](const F& f) { return f.gap(); }, "%.2f", 1, false},
      {"novel dB", [](const F& f) { return f.novel_psnr; }, "%.2f", 1, true},
      {"depth 1% %", [](const F& f) { return f.depth_accuracy; }, "%.2f", 100, true},
      {"HDR |log|", [](const F& f) { return f.hdr_log_ratio; }, "%.4f", 1, false},
      {"mu-law dB", [](const F& f) { return f.hdr_mulaw_psnr; }, "%.2f", 1, true},
      {"exp. med %", [](const F& f) { return f.exposure_median; }, "%.2f", 100, false},
      {"exp. max %", [](const F& f) { return f.exposure_max; }, "%.2f", 100, false},
      {"frame ms", [](const F& f) { return f.frame_ms; }, "%.0f", 1, false},
      {"reconstruct s", [](const F& f) { return f.reconstruct_s; }, "%.0f", 1, false},
  };
  return columns;
}

std::string Cell(const Column& c, std::optional<double> v) {
  if (!v) return "-";
  char buf[32];
  std::snprintf(buf, sizeof(buf), c.format, *v * c.scale);
  return buf;
}

// Rows of cells: the captures, then "mean" and "worst" of each split present.
std::vector<std::vector<std::string>> Cells(const std::vector<CaptureFigures>& rows) {
  std::vector<std::vector<std::string>> out;
  for (const CaptureFigures& f : rows) {
    std::vector<std::string> r = {f.name, f.split};
    for (const Column& c : Columns()) r.push_back(Cell(c, c.get(f)));
    out.push_back(r);
  }
  for (const char* split : {"tune", "check"}) {
    std::vector<const CaptureFigures*> in;
    for (const CaptureFigures& f : rows) {
      if (f.split == split) in.push_back(&f);
    }
    if (in.empty()) continue;
    std::vector<std::string> mean = {"mean", split}, worst = {"worst", split};
    for (const Column& c : Columns()) {
      double sum = 0;
      int n = 0;
      std::optional<double> w;
      std::string who;
      for (const CaptureFigures* f : in) {
        const std::optional<double> v = c.get(*f);
        if (!v) continue;
        sum += *v;
        ++n;
        if (!w || (c.higher_is_better ? *v < *w : *v > *w)) {
          w = v;
          who = f->name;
        }
      }
      mean.push_back(n ? Cell(c, sum / n) : "-");
      worst.push_back(w ? Cell(c, w) + " " + who : "-");
    }
    out.push_back(mean);
    out.push_back(worst);
  }
  return out;
}

std::vector<std::string> Header() {
  std::vector<std::string> h = {"capture", "split"};
  for (const Column& c : Columns()) h.push_back(c.title);
  return h;
}

}  // namespace

std::vector<SuiteCapture> ReadSuiteManifest(const fs::path& path) {
  const json j = ReadJson(path);
  std::vector<SuiteCapture> captures;
  try {
    if (j.value("format", "") != "hdribr-quality-suite") {
      throw std::invalid_argument("format is not hdribr-quality-suite");
    }
    if (j.value("version", 0) != 1) throw std::invalid_argument("version must be 1");
    std::set<std::string> names;
    for (const json& c : j.at("captures")) {
      captures.push_back(ParseCapture(c));
      if (!names.insert(captures.back().name).second) {
        throw std::invalid_argument("capture '" + captures.back().name + "' is listed twice");
      }
    }
  } catch (const json::exception& e) {
    throw InputError(path, e.what());
  } catch (const std::invalid_argument& e) {
    throw InputError(path, e.what());
  }
  if (captures.empty()) throw InputError(path, "lists no capture");
  return captures;
}

std::optional<double> CaptureFigures::margin() const {
  if (!psnr || !nearest_psnr) return std::nullopt;
  return *psnr - *nearest_psnr;
}

std::optional<double> CaptureFigures::gap() const {
  if (!gt_own_psnr || !own_psnr) return std::nullopt;
  return *gt_own_psnr - *own_psnr;
}

json FiguresToJson(const CaptureFigures& f) {
  json j = {{"name", f.name}, {"split", f.split}, {"synthetic", f.synthetic}};
  const auto put = [&](const char* key, std::optional<double> v) {
    if (v) j[key] = *v;
  };
  put("reconstruct_s", f.reconstruct_s);
  put("registered", f.registered);
  put("psnr_db", f.psnr);
  put("ssim", f.ssim);
  put("nearest_psnr_db", f.nearest_psnr);
  put("nearest_ssim", f.nearest_ssim);
  put("own_psnr_db", f.own_psnr);
  put("own_coverage", f.own_coverage);
  put("gt_own_psnr_db", f.gt_own_psnr);
  put("novel_psnr_db", f.novel_psnr);
  put("depth_accuracy", f.depth_accuracy);
  put("hdr_median_abs_log_ratio", f.hdr_log_ratio);
  put("hdr_mulaw_psnr_db", f.hdr_mulaw_psnr);
  put("exposure_error_median", f.exposure_median);
  put("exposure_error_max", f.exposure_max);
  put("frame_ms", f.frame_ms);
  put("margin_db", f.margin());
  put("gap_db", f.gap());
  return j;
}

CaptureFigures FiguresFromJson(const json& j) {
  CaptureFigures f;
  f.name = j.value("name", "");
  f.split = j.value("split", "");
  f.synthetic = j.value("synthetic", false);
  f.reconstruct_s = Get(j, "reconstruct_s");
  f.registered = Get(j, "registered");
  f.psnr = Get(j, "psnr_db");
  f.ssim = Get(j, "ssim");
  f.nearest_psnr = Get(j, "nearest_psnr_db");
  f.nearest_ssim = Get(j, "nearest_ssim");
  f.own_psnr = Get(j, "own_psnr_db");
  f.own_coverage = Get(j, "own_coverage");
  f.gt_own_psnr = Get(j, "gt_own_psnr_db");
  f.novel_psnr = Get(j, "novel_psnr_db");
  f.depth_accuracy = Get(j, "depth_accuracy");
  f.hdr_log_ratio = Get(j, "hdr_median_abs_log_ratio");
  f.hdr_mulaw_psnr = Get(j, "hdr_mulaw_psnr_db");
  f.exposure_median = Get(j, "exposure_error_median");
  f.exposure_max = Get(j, "exposure_error_max");
  f.frame_ms = Get(j, "frame_ms");
  return f;
}

void ReadLeaveOneOut(const fs::path& eval_dir, CaptureFigures& f) {
  const json j = ReadEval(eval_dir);
  const json* h = MeanOf(j, "hdribr");
  if (!h) throw InputError(eval_dir / "eval.json", "has no hdribr scores");
  f.psnr = Get(*h, "psnr_db");
  f.ssim = Get(*h, "ssim");
  f.own_psnr = Get(*h, "own_psnr_db");
  f.own_coverage = Get(*h, "own_coverage");
  if (const json* n = MeanOf(j, "nearest_photo")) {
    f.nearest_psnr = Get(*n, "psnr_db");
    f.nearest_ssim = Get(*n, "ssim");
  }
}

void ReadGtLeaveOneOut(const fs::path& eval_dir, CaptureFigures& f) {
  if (!fs::exists(eval_dir / "eval.json")) return;
  const json j = ReadEval(eval_dir);
  if (const json* h = MeanOf(j, "hdribr")) f.gt_own_psnr = Get(*h, "own_psnr_db");
}

void ReadGtNovel(const fs::path& eval_dir, CaptureFigures& f) {
  if (fs::exists(eval_dir / "eval.json")) {
    const json j = ReadEval(eval_dir);
    if (const json* h = MeanOf(j, "hdribr")) f.novel_psnr = Get(*h, "psnr_db");
    if (j.contains("depth")) f.depth_accuracy = Get(j.at("depth"), "accuracy");
  }
  const fs::path hdr = eval_dir / "eval_hdr.json";
  if (!fs::exists(hdr)) return;
  const json j = ReadJson(hdr);
  if (j.value("format", "") != "hdribr-eval-hdr") throw InputError(hdr, "is not an HDR report");
  for (const json& m : j.at("methods")) {
    if (m.value("method", "") != "hdribr") continue;
    f.hdr_log_ratio = Get(m, "median_abs_log_ratio");
    f.hdr_mulaw_psnr = Get(m, "hdr_psnr_db");
  }
}

bool ParseExposureTruth(const std::string& text, CaptureFigures& f) {
  static const std::regex kLine(R"(calibrated median ([0-9.]+) %, max ([0-9.]+) %)");
  std::smatch m;
  if (!std::regex_search(text, m, kLine)) return false;
  f.exposure_median = std::stod(m[1]) / 100;
  f.exposure_max = std::stod(m[2]) / 100;
  return true;
}

std::string FormatSuiteTable(const std::vector<CaptureFigures>& rows) {
  std::vector<std::vector<std::string>> cells = Cells(rows);
  const std::vector<std::string> header = Header();
  std::vector<size_t> width(header.size());
  for (size_t c = 0; c < header.size(); ++c) {
    width[c] = header[c].size();
    for (const auto& r : cells) width[c] = std::max(width[c], r[c].size());
  }
  const auto line = [&](const std::vector<std::string>& r) {
    std::string s;
    for (size_t c = 0; c < r.size(); ++c) {
      const std::string pad(width[c] - r[c].size(), ' ');
      s += c < 2 ? r[c] + pad : pad + r[c];
      s += c + 1 < r.size() ? "  " : "\n";
    }
    return s;
  };
  std::string s = line(header);
  for (const auto& r : cells) s += line(r);
  return s;
}

std::string FormatSuiteMarkdown(const std::vector<CaptureFigures>& rows,
                                const std::string& provenance) {
  const auto line = [](const std::vector<std::string>& r) {
    std::string s = "|";
    for (const std::string& c : r) {
      s += " " + std::regex_replace(c, std::regex("\\|"), "\\|") + " |";  // "HDR |log|"
    }
    return s + "\n";
  };
  std::string s = provenance + "\n\n";
  const std::vector<std::string> header = Header();
  s += line(header);
  s += line(std::vector<std::string>(header.size(), "---"));
  for (const auto& r : Cells(rows)) s += line(r);
  return s;
}

std::string FormatSuiteJson(const std::vector<CaptureFigures>& rows,
                            const std::string& provenance) {
  json captures = json::array();
  for (const CaptureFigures& f : rows) captures.push_back(FiguresToJson(f));
  json splits = json::object();
  const std::vector<std::vector<std::string>> cells = Cells(rows);
  const std::vector<std::string> header = Header();
  for (const auto& r : cells) {
    if (r[0] != "mean" && r[0] != "worst") continue;
    json row = json::object();
    for (size_t c = 2; c < r.size(); ++c) row[header[c]] = r[c];
    splits[r[1]][r[0]] = row;
  }
  const json j = {{"format", "hdribr-bench-quality"},
                  {"version", 1},
                  {"provenance", provenance},
                  {"captures", captures},
                  {"splits", splits}};
  return j.dump(2) + "\n";
}

}  // namespace hdribr::eval
