#include "cli/cli_util.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/image.h"

namespace hdribr::cli {

const FlagNames& CaptureFlags() {
  static const FlagNames flags = {{"series", "--series"},     {"views", "--views"},
                                  {"novel_views", "--novel"}, {"ev_step", "--ev-step"},
                                  {"threads", "--threads"},   {"toe", "--toe"},
                                  {"width", "--size width"},  {"height", "--size height"},
                                  {"exposure", "--exposure"}, {"exif_error", "--exif-error"}};
  return flags;
}

const FlagNames& ReconstructFlags() {
  static const FlagNames flags = {
      {"max_features", "--max-features"},
      {"sift_max_size", "--sift-size"},
      {"undistort_max_size", "--image-size"},
      {"dense_options.max_size", "--dense-size"},
      {"dense_options.num_depths", "--dense-depths"},
      {"dense_options.num_neighbors", "--dense-neighbors"},
      {"dense_options.patch_match.num_levels", "--dense-levels"},
      {"dense_options.patch_match.iterations", "--dense-iterations"},
      {"dense_options.patch_match.geom_iterations", "--dense-geom-iterations"},
      {"dense_options.patch_match.min_ncc", "--dense-min-ncc"},
      {"dense_options.single_agreement_ncc", "--fusion-single-ncc"},
      {"threads", "--threads"},
      {"vocab_tree", "--vocab-tree"},
      {"dense", "--dense"},
      {"matching", "--matching"}};
  return flags;
}

int RunNamingFlags(const FlagNames& flags, const std::function<int()>& run) {
  try {
    return run();
  } catch (const OptionError& e) {
    const auto flag = flags.find(e.field());
    if (flag == flags.end()) throw;
    throw UsageError(flag->second + " " + e.problem());
  }
}

namespace {

// The size `text` names, or nothing when it is not WxH with sides from 1 to 16384.
std::optional<cv::Size> SizeOf(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
      w <= 0 || h <= 0 || w > 16384 || h > 16384) {
    return std::nullopt;
  }
  return cv::Size(w, h);
}

std::string SizeProblem(const std::string& text) {
  return "must be WxH with integers from 1 to 16384, got '" + text + "'";
}

}  // namespace

cv::Size ParseSize(const std::string& text, const std::string& option) {
  const std::optional<cv::Size> size = SizeOf(text);
  if (!size) throw UsageError(option + " " + SizeProblem(text));
  return *size;
}

CLI::Validator SizeCheck() {
  return CLI::Validator(
      [](std::string& value) -> std::string { return SizeOf(value) ? "" : SizeProblem(value); },
      "WxH");
}

CLI::Validator OutputFolderCheck() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        const std::filesystem::path folder = std::filesystem::path(value).parent_path();
        if (folder.empty() || std::filesystem::is_directory(folder)) return {};
        return "folder " + folder.string() + " does not exist";
      },
      "");
}

CLI::Validator ExtensionCheck(std::vector<std::string> extensions) {
  std::string names;
  for (size_t i = 0; i < extensions.size(); ++i) {
    names += (i == 0 ? "" : i + 1 == extensions.size() ? " or " : ", ") + extensions[i];
  }
  return CLI::Validator(
      [extensions, names](std::string& value) -> std::string {
        const std::string ext = LowerExtension(value);
        if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end()) return {};
        return "must end in " + names + ", got '" + value + "'";
      },
      "");
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
