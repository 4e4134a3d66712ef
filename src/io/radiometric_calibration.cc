#include "io/radiometric_calibration.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr {
using nlohmann::json;

RadiometricCalibration ReadRadiometricCalibration(const std::filesystem::path& path) {
  RadiometricCalibration c;
  try {
    const json doc = json::parse(ReadFileToString(path));
    if (doc.value("format", "") != "hdribr-exposures") {
      throw InputError(path, "not an hdribr exposure calibration (format 'hdribr-exposures')");
    }
    if (doc.value("version", 0) != 1) throw InputError(path, "unsupported version");
    c.response_file = doc.value("response", std::string(kCalibResponse));
    c.method = doc.value("method", c.method);
    c.samples = doc.value("samples", 0);
    c.residual_rms = doc.value("residual_rms", 0.0);
    c.exponent_from_exif = doc.value("exponent_from_exif", false);
    for (const auto& [name, p] : doc.at("photos").items()) {
      PhotoExposureCalibration e;
      e.exif_relative = p.at("exif_relative").get<double>();
      e.relative = p.at("relative_exposure").get<double>();
      e.calibrated = p.at("calibrated").get<bool>();
      if (!(std::isfinite(e.relative) && e.relative > 0 && std::isfinite(e.exif_relative) &&
            e.exif_relative > 0)) {
        throw InputError(path, "photo '" + name + "': exposures must be positive numbers");
      }
      c.photos[name] = e;
    }
  } catch (const json::exception& e) {
    throw InputError(path, std::string("malformed exposure calibration: ") + e.what());
  }
  return c;
}

void WriteRadiometricCalibration(const std::filesystem::path& path,
                                 const RadiometricCalibration& c) {
  json photos = json::object();
  for (const auto& [name, e] : c.photos) {
    photos[name] = {{"exif_relative", e.exif_relative},
                    {"relative_exposure", e.relative},
                    {"calibrated", e.calibrated}};
  }
  const json doc = {{"format", "hdribr-exposures"},
                    {"version", 1},
                    {"method", c.method},
                    {"response", c.response_file},
                    {"samples", c.samples},
                    {"residual_rms", c.residual_rms},
                    {"exponent_from_exif", c.exponent_from_exif},
                    {"photos", photos}};
  WriteFileAtomic(path, doc.dump(2) + "\n");
}

}  // namespace hdribr
