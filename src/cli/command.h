// The subcommand table of the hdribr executable: one Setup function per subcommand.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace hdribr::cli {

// Runs a parsed subcommand; returns the process exit code.
using CommandRunner = std::function<int()>;
// Binds a subcommand's options on `sub` and returns its runner (called after parsing).
using CommandSetup = CommandRunner (*)(CLI::App& sub);

struct CommandEntry {
  const char* name;
  const char* help;
  CommandSetup setup;
};

// One line per subcommand, each defined in its own cmd_<name>.cc.
CommandRunner SetupInspect(CLI::App& sub);

}  // namespace hdribr::cli
