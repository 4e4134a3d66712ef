// Small parsers shared by the subcommands.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace hdribr::cli {

// "640x480" (or "640X480") -> size; throws UsageError naming `option` for anything else,
// including non-positive sizes or sides above 16384.
cv::Size ParseSize(const std::string& text, const std::string& option = "--size");

// Items of a comma-separated list, empty items dropped ("a,,b" -> {"a", "b"}).
std::vector<std::string> SplitList(const std::string& text);

}  // namespace hdribr::cli
