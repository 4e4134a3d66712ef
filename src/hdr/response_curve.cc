#include "hdr/response_curve.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kChannelNames[3] = {"B", "G", "R"};

}  // namespace

bool ResponseCurve::IsValid() const {
  for (const auto& g : log_inverse) {
    if (g.size() != 256) return false;
    for (size_t z = 0; z < g.size(); ++z) {
      if (!std::isfinite(g[z])) return false;
      if (z > 0 && g[z] < g[z - 1]) return false;
    }
  }
  return true;
}

double ResponseCurve::Linear(int channel, int z) const {
  HDRIBR_CHECK(channel >= 0 && channel < 3 && z >= 0 && z < 256);
  return std::exp(log_inverse[channel][z]);
}

ResponseCurve ReadResponseCurve(const fs::path& path) {
  json doc;
  try {
    doc = json::parse(ReadFileToString(path));
  } catch (const json::parse_error& e) {
    throw InputError(path, std::string("invalid JSON: ") + e.what());
  }
  if (!doc.is_object() || doc.value("format", json()) != "hdribr-response") {
    throw InputError(path, "not a response file (expected \"format\": \"hdribr-response\")");
  }
  if (!doc.contains("version") || !doc["version"].is_number_integer() || doc["version"] != 1) {
    throw InputError(path, "unsupported response file version (expected 1)");
  }
  ResponseCurve curve;
  if (doc.contains("source")) {
    if (!doc["source"].is_string()) throw InputError(path, "'source' must be a string");
    curve.source = doc["source"].get<std::string>();
  }
  if (doc.contains("lambda") && !doc["lambda"].is_null()) {
    if (!doc["lambda"].is_number() || !(doc["lambda"].get<double>() >= 0)) {
      throw InputError(path, "'lambda' must be a non-negative number");
    }
    curve.lambda = doc["lambda"].get<double>();
  }
  if (!doc.contains("log_inverse") || !doc["log_inverse"].is_object()) {
    throw InputError(path, "missing 'log_inverse' object with B, G, R arrays");
  }
  const json& g = doc["log_inverse"];
  for (int c = 0; c < 3; ++c) {
    const std::string name = kChannelNames[c];
    if (!g.contains(name) || !g[name].is_array() || g[name].size() != 256) {
      throw InputError(path, "'log_inverse." + name + "' must be an array of 256 numbers");
    }
    auto& out = curve.log_inverse[c];
    out.resize(256);
    for (int z = 0; z < 256; ++z) {
      const json& v = g[name][z];
      if (!v.is_number()) {
        throw InputError(path,
                         "'log_inverse." + name + "[" + std::to_string(z) + "]' is not a number");
      }
      out[z] = v.get<double>();
      if (!std::isfinite(out[z])) {
        throw InputError(path,
                         "'log_inverse." + name + "[" + std::to_string(z) + "]' is not finite");
      }
      if (z > 0 && out[z] < out[z - 1]) {
        throw InputError(path, "'log_inverse." + name + "' decreases at " + std::to_string(z) +
                                   " (a response must be non-decreasing)");
      }
    }
  }
  return curve;
}

void WriteResponseCurve(const fs::path& path, const ResponseCurve& curve) {
  HDRIBR_CHECK_MSG(curve.IsValid(), "response curve must be 3 x 256 finite non-decreasing");
  std::ostringstream s;
  s << "{\n  \"format\": \"hdribr-response\",\n  \"version\": 1,\n";
  s << "  \"source\": " << json(curve.source).dump() << ",\n";
  if (curve.lambda) s << "  \"lambda\": " << json(*curve.lambda).dump() << ",\n";
  s << "  \"log_inverse\": {\n";
  for (int c = 0; c < 3; ++c) {
    s << "    \"" << kChannelNames[c] << "\": " << json(curve.log_inverse[c]).dump()
      << (c < 2 ? ",\n" : "\n");
  }
  s << "  }\n}\n";
  WriteFileAtomic(path, s.str());
}

double RmsLinearError(const ResponseCurve& got, const ResponseCurve& truth, int c, int lo) {
  HDRIBR_CHECK(c >= 0 && c < 3 && lo >= 0 && lo <= 245);
  const int n = 245 - lo + 1;
  double offset = 0;
  for (int z = lo; z <= 245; ++z) offset += got.log_inverse[c][z] - truth.log_inverse[c][z];
  offset /= n;
  double sum = 0;
  for (int z = lo; z <= 245; ++z) {
    const double e = std::exp(got.log_inverse[c][z] - truth.log_inverse[c][z] - offset) - 1.0;
    sum += e * e;
  }
  return std::sqrt(sum / n);
}

}  // namespace hdribr
