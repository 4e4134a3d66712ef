#include "cli/cli_util.h"

#include <cstdio>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"

namespace hdribr::cli {

cv::Size ParseSize(const std::string& text, const std::string& option) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
      w <= 0 || h <= 0 || w > 16384 || h > 16384) {
    throw UsageError(option + " must be WxH with integers from 1 to 16384, got '" + text + "'");
  }
  return {w, h};
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

void EmitJson(const std::string& path, const nlohmann::json& doc) {
  if (path.empty()) {
    std::printf("%s\n", doc.dump(2).c_str());
  } else {
    WriteFileAtomic(path, doc.dump(2) + "\n");
  }
}

std::FILE* TableStream(const std::string& json_path) { return json_path.empty() ? stderr : stdout; }

}  // namespace hdribr::cli
