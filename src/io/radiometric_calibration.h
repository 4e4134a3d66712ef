// The workspace's radiometric calibration (WORKSPACE/calib/): the camera response and each
// photo's refined exposure, as `hdribr calibrate` finds them from the point cloud
// (docs/formats.md, "Radiometric calibration").
#pragma once

#include <filesystem>
#include <map>
#include <string>

namespace hdribr {

// Folder and files of the calibration inside a workspace.
inline constexpr const char* kCalibFolder = "calib";
inline constexpr const char* kCalibExposures = "exposures.json";
inline constexpr const char* kCalibResponse = "response.json";

// One photo's exposure: EXIF's and the calibrated one, both relative exposures in the units of
// Exposure::Relative() (time x ISO / 100 / N^2).
struct PhotoExposureCalibration {
  double exif_relative = 1;
  double relative = 1;
  bool calibrated = false;  // false: not solved (no usable observation), EXIF's kept
};

struct RadiometricCalibration {
  std::map<std::string, PhotoExposureCalibration> photos;  // by photo name
  std::string response_file = kCalibResponse;              // relative to the calib folder
  std::string method = "multiview";
  int samples = 0;                  // scene points used
  double residual_rms = 0;          // natural log
  bool exponent_from_exif = false;  // false: exposures known up to a factor and an exponent
};

// Reads calib/exposures.json. Throws InputError naming the file when it is malformed.
RadiometricCalibration ReadRadiometricCalibration(const std::filesystem::path& path);
// Writes it atomically.
void WriteRadiometricCalibration(const std::filesystem::path& path,
                                 const RadiometricCalibration& calibration);

}  // namespace hdribr
