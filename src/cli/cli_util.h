// Small parsers and output helpers shared by the subcommands.
#pragma once

#include <CLI/CLI.hpp>
#include <climits>
#include <cstdio>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace hdribr::cli {

// Option checks for integer counts and sizes (CLI::NonNegativeNumber and CLI::PositiveNumber
// print the largest double in their errors).
inline const CLI::Range kAtLeastZero(0, INT_MAX);
inline const CLI::Range kAtLeastOne(1, INT_MAX);

// Member of an options struct (OptionError::field) -> the command-line flag that sets it.
using FlagNames = std::map<std::string, std::string>;
// The flags of synth::CaptureOptions and ReconstructOptions (shared by the subcommands that
// bind them: synth, reconstruct, demo).
const FlagNames& CaptureFlags();
const FlagNames& ReconstructFlags();
// Runs `run`; an OptionError it throws is rethrown as a UsageError that names the flag of its
// field, so that library code speaks of its own fields and the CLI of its flags.
int RunNamingFlags(const FlagNames& flags, const std::function<int()>& run);

// "640x480" (or "640X480") -> size; throws UsageError naming `option` for anything else,
// including non-positive sizes or sides above 16384.
cv::Size ParseSize(const std::string& text, const std::string& option = "--size");

// CLI11 check of a WxH option by ParseSize's rule: a bad size stops the command as it parses,
// before any work.
CLI::Validator SizeCheck();

// CLI11 check of an output file's folder: it must exist, so that a command does not do its
// work and then fail to write the result.
CLI::Validator OutputFolderCheck();

// CLI11 check of an output file's format: its LowerExtension is one of `extensions` (".exr").
CLI::Validator ExtensionCheck(std::vector<std::string> extensions);

// Items of a comma-separated list, empty items dropped ("a,,b" -> {"a", "b"}).
std::vector<std::string> SplitList(const std::string& text);

// A benchmark's JSON: printed to stdout (2-space indent) when `path` is empty, else written
// there atomically.
void EmitJson(const std::string& path, const nlohmann::json& doc);

// Where a benchmark's readable table goes: stderr when its JSON goes to stdout (`json_path`
// empty, see EmitJson), else stdout.
std::FILE* TableStream(const std::string& json_path);

}  // namespace hdribr::cli
