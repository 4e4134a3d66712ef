#include "io/series_json.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::optional<double> OptionalNumber(const json& j, const char* key, const fs::path& path) {
  if (!j.contains(key) || j.at(key).is_null()) return std::nullopt;
  if (!j.at(key).is_number()) throw InputError(path, std::string("'") + key + "' is not a number");
  const double v = j.at(key).get<double>();
  if (!std::isfinite(v) || v <= 0) {
    throw InputError(path, std::string("'") + key + "' must be a positive number");
  }
  return v;
}

}  // namespace

std::vector<ExposureSeries> ReadSeriesJson(const fs::path& path, std::vector<Photo>& photos) {
  json doc;
  try {
    doc = json::parse(ReadFileToString(path));
  } catch (const json::parse_error& e) {
    throw InputError(path, std::string("invalid JSON: ") + e.what());
  }
  if (!doc.is_object() || !doc.contains("series") || !doc["series"].is_array()) {
    throw InputError(path, "expected an object with a 'series' array");
  }
  std::map<std::string, int> by_name;
  for (size_t i = 0; i < photos.size(); ++i) by_name[photos[i].name] = static_cast<int>(i);

  // Optional per-photo exposure overrides.
  if (doc.contains("photos")) {
    if (!doc["photos"].is_object()) throw InputError(path, "'photos' must be an object");
    for (const auto& [name, fields] : doc["photos"].items()) {
      auto it = by_name.find(name);
      if (it == by_name.end()) throw InputError(path, "unknown photo '" + name + "'");
      if (!fields.is_object()) throw InputError(path, "photo '" + name + "' must be an object");
      Exposure& e = photos[it->second].exposure;
      if (auto v = OptionalNumber(fields, "exposure_time", path)) e.time_s = v;
      if (auto v = OptionalNumber(fields, "iso", path)) e.iso = v;
      if (auto v = OptionalNumber(fields, "f_number", path)) e.f_number = v;
    }
  }

  for (auto& p : photos) p.series_id = -1;
  std::vector<ExposureSeries> series;
  for (const auto& js : doc["series"]) {
    if (!js.is_object() || !js.contains("photos") || !js["photos"].is_array()) {
      throw InputError(path, "each series needs a 'photos' array");
    }
    ExposureSeries s;
    s.id = static_cast<int>(series.size());
    s.name = js.value("name", "series" + std::to_string(s.id));
    for (const auto& jn : js["photos"]) {
      if (!jn.is_string()) throw InputError(path, "photo names must be strings");
      const std::string name = jn.get<std::string>();
      auto it = by_name.find(name);
      if (it == by_name.end()) throw InputError(path, "unknown photo '" + name + "'");
      if (photos[it->second].series_id != -1) {
        throw InputError(path, "photo '" + name + "' is listed in two series");
      }
      photos[it->second].series_id = s.id;
      s.photo_indices.push_back(it->second);
    }
    if (s.photo_indices.empty()) throw InputError(path, "series '" + s.name + "' has no photos");
    if (auto v = OptionalNumber(js, "relative_exposure", path)) {
      s.relative_exposure = *v;
    } else {
      double sum = 0;
      for (int i : s.photo_indices) sum += std::log2(photos[i].exposure.Relative());
      s.relative_exposure = std::exp2(sum / static_cast<double>(s.photo_indices.size()));
    }
    std::sort(s.photo_indices.begin(), s.photo_indices.end());
    series.push_back(std::move(s));
  }
  for (const auto& p : photos) {
    if (p.series_id == -1) throw InputError(path, "photo '" + p.name + "' is in no series");
  }
  return series;
}

void WriteSeriesJson(const fs::path& path, const std::vector<ExposureSeries>& series,
                     const std::vector<Photo>& photos) {
  json doc;
  doc["format"] = "hdribr-series";
  doc["version"] = 1;
  json js = json::array();
  json jp = json::object();
  for (const auto& s : series) {
    json names = json::array();
    for (int i : s.photo_indices) {
      const Photo& p = photos.at(i);
      names.push_back(p.name);
      json fields = json::object();
      if (p.exposure.time_s) fields["exposure_time"] = *p.exposure.time_s;
      if (p.exposure.iso) fields["iso"] = *p.exposure.iso;
      if (p.exposure.f_number) fields["f_number"] = *p.exposure.f_number;
      if (!fields.empty()) jp[p.name] = fields;
    }
    js.push_back({{"name", s.name}, {"relative_exposure", s.relative_exposure}, {"photos", names}});
  }
  doc["series"] = js;
  doc["photos"] = jp;
  WriteFileAtomic(path, doc.dump(2) + "\n");
}

}  // namespace hdribr
