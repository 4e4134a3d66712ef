// An aligned stack of 8-bit exposures of one view, the input of calibration and merge.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace hdribr {

// Images of one viewpoint at different exposures, pixel-aligned.
struct ExposureStack {
  std::vector<cv::Mat> images;  // CV_8UC3 BGR, all the same size
  std::vector<double> times;    // exposure time (or relative exposure) of each image, > 0
  std::vector<cv::Mat> masks;   // empty, or one CV_8UC1 per image: nonzero = pixel valid

  // Throws UsageError when the stack is empty or inconsistent (types, sizes, counts, times).
  void Validate() const;
  // Image indices sorted by increasing exposure time.
  std::vector<int> OrderByTime() const;
};

// Parses an exposure time: a decimal ("0.25", "2") or a fraction ("1/1024"); nullopt-free:
// throws UsageError naming `what` when the text is not a positive finite number.
double ParseExposureTime(const std::string& text, const std::string& what);

// Exposure times from a text file such as memorial's shutter_times.txt: one time per line
// ("1/1024", "0.5"), optionally preceded by an image file name ("img.png 1/1024"); blank lines
// and '#' comments are skipped. `names[i]` is empty for lines without a name.
struct ShutterTimes {
  std::vector<std::string> names;
  std::vector<double> times;
};
// Throws InputError naming the file and line on a bad line.
ShutterTimes ReadShutterTimes(const std::filesystem::path& path);

}  // namespace hdribr
