#include "hdr/exposure_stack.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr {

void ExposureStack::Validate() const {
  if (images.empty()) throw UsageError("the exposure stack is empty");
  if (times.size() != images.size()) {
    throw UsageError(std::to_string(images.size()) + " images but " + std::to_string(times.size()) +
                     " exposure times");
  }
  if (!masks.empty() && masks.size() != images.size()) {
    throw UsageError(std::to_string(images.size()) + " images but " + std::to_string(masks.size()) +
                     " masks");
  }
  const cv::Size size = images[0].size();
  for (size_t i = 0; i < images.size(); ++i) {
    if (images[i].type() != CV_8UC3 || images[i].empty()) {
      throw UsageError("image " + std::to_string(i) + " is not an 8-bit 3-channel image");
    }
    if (images[i].size() != size) {
      throw UsageError("image " + std::to_string(i) + " is " + std::to_string(images[i].cols) +
                       "x" + std::to_string(images[i].rows) + ", the first is " +
                       std::to_string(size.width) + "x" + std::to_string(size.height));
    }
    if (!std::isfinite(times[i]) || times[i] <= 0) {
      throw UsageError("exposure time " + std::to_string(i) + " is not a positive number");
    }
    if (!masks.empty() && (masks[i].type() != CV_8UC1 || masks[i].size() != size)) {
      throw UsageError("mask " + std::to_string(i) +
                       " is not 8-bit single-channel of the "
                       "image size");
    }
  }
}

std::vector<int> ExposureStack::OrderByTime() const {
  std::vector<int> order(images.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return times[a] < times[b]; });
  return order;
}

double ParseExposureTime(const std::string& text, const std::string& what) {
  auto number = [&](const std::string& s) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != s.size()) {
      throw UsageError(what + ": '" + text + "' is not an exposure time");
    }
    return v;
  };
  double t = 0;
  const size_t slash = text.find('/');
  if (slash == std::string::npos) {
    t = number(text);
  } else {
    t = number(text.substr(0, slash)) / number(text.substr(slash + 1));
  }
  if (!std::isfinite(t) || t <= 0) {
    throw UsageError(what + ": exposure time '" + text + "' must be positive and finite");
  }
  return t;
}

ShutterTimes ReadShutterTimes(const std::filesystem::path& path) {
  std::istringstream in(ReadFileToString(path));
  ShutterTimes result;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::vector<std::string> tokens;
    for (std::string t; fields >> t;) tokens.push_back(t);
    if (tokens.empty()) continue;
    const std::string where = "line " + std::to_string(line_number);
    if (tokens.size() > 2) throw InputError(path, where + ": expected 'TIME' or 'NAME TIME'");
    try {
      result.times.push_back(ParseExposureTime(tokens.back(), where));
    } catch (const UsageError& e) {
      throw InputError(path, e.what());
    }
    result.names.push_back(tokens.size() == 2 ? tokens[0] : "");
  }
  if (result.times.empty()) throw InputError(path, "no exposure times");
  return result;
}

}  // namespace hdribr
