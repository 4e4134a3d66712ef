// hdribr: point-cloud HDR image-based rendering. A table of subcommands (see command.h).
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "cli/command.h"
#include "core/error.h"

namespace {}  // namespace

namespace hdribr::cli {

std::vector<CommandEntry>& CommandTable() {
  static std::vector<CommandEntry> table;
  return table;
}

CommandRegistrar::CommandRegistrar(const char* name, const char* help, CommandSetup setup,
                                   int order) {
  auto& table = CommandTable();
  table.push_back({name, help, setup, order});
  std::sort(table.begin(), table.end(), [](const CommandEntry& a, const CommandEntry& b) {
    return a.order != b.order ? a.order < b.order : std::string(a.name) < b.name;
  });
}

}  // namespace hdribr::cli

int main(int argc, char** argv) {
  CLI::App app{"hdribr: point-cloud HDR image-based rendering"};
  app.require_subcommand(1);
  bool verbose = false;
  bool quiet = false;
  app.add_flag("-v,--verbose", verbose, "Debug logging");
  app.add_flag("-q,--quiet", quiet, "Warnings and errors only");
  app.set_version_flag("--version", "hdribr 0.1.0");
  // Usage errors as one line, like every other error (CLI11's default adds a second line).
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "error: " + std::string(e.what()) + " (see --help)\n";
  });

  std::vector<std::pair<CLI::App*, hdribr::cli::CommandRunner>> runners;
  for (const auto& entry : hdribr::cli::CommandTable()) {
    CLI::App* sub = app.add_subcommand(entry.name, entry.help);
    runners.emplace_back(sub, entry.setup(*sub));
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every other parse error is bad usage, like UsageError.
    return app.exit(e) == 0 ? 0 : 64;
  }
  // Log lines go to stderr: stdout carries the data of the commands that print it (JSON).
  spdlog::set_default_logger(spdlog::stderr_color_mt("hdribr"));
  spdlog::set_pattern("[%H:%M:%S.%e] %^%l%$ %v");
  spdlog::set_level(verbose ? spdlog::level::debug
                            : (quiet ? spdlog::level::warn : spdlog::level::info));
  try {
    for (auto& [sub, run] : runners) {
      if (sub->parsed()) return run();
    }
  } catch (const hdribr::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const hdribr::UsageError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 64;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 1;
}
