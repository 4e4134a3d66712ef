// Camera response curves in Debevec-Malik form, and their file format (docs/formats.md).
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hdribr {

// g = ln f^-1 per channel (Debevec & Malik 1997): g(z) is the natural log of the linear
// exposure X = E * t that gives pixel value z in [0, 255]. Channels in BGR order like cv::Mat.
struct ResponseCurve {
  std::array<std::vector<double>, 3> log_inverse;  // 3 x 256 entries
  std::string source;                              // "debevec", "synthetic-truth", ...
  std::optional<double> lambda;                    // smoothness weight used by a calibration

  bool IsValid() const;  // 3 x 256 finite, non-decreasing entries
  // Linear exposure X = exp(g(z)) of an 8-bit value in channel c (0 = B, 1 = G, 2 = R).
  double Linear(int channel, int z) const;
};

// Reads a response file (JSON, format "hdribr-response"). Throws InputError naming the file.
ResponseCurve ReadResponseCurve(const std::filesystem::path& path);
// Writes it atomically. The curve must be valid (IsValid()).
void WriteResponseCurve(const std::filesystem::path& path, const ResponseCurve& curve);

// Error of a recovered curve against a true one in channel c: the RMS over lo..245 DN of
// exp(g - g_true - offset) - 1, offset the mean log difference there (a response is known up
// to a scale), i.e. the relative error of the linear exposure the curve gives back.
double RmsLinearError(const ResponseCurve& got, const ResponseCurve& truth, int c, int lo = 10);

}  // namespace hdribr
