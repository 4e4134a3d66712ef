// The subcommand table of the hdribr executable. Each subcommand lives in its own
// cmd_<name>.cc and adds itself to the table with HDRIBR_COMMAND, so that subcommands can be
// added without touching main.cc.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <vector>

namespace hdribr::cli {

// Runs a parsed subcommand; returns the process exit code.
using CommandRunner = std::function<int()>;
// Binds a subcommand's options on `sub` and returns its runner (called after parsing).
using CommandSetup = CommandRunner (*)(CLI::App& sub);

struct CommandEntry {
  const char* name;
  const char* help;
  CommandSetup setup;
  int order;  // position in `hdribr --help` (pipeline order), then by name
};

// The table, sorted by order then name.
std::vector<CommandEntry>& CommandTable();

// Adds an entry at static-initialisation time; use through HDRIBR_COMMAND.
struct CommandRegistrar {
  CommandRegistrar(const char* name, const char* help, CommandSetup setup, int order);
};

}  // namespace hdribr::cli

// Registers a subcommand: HDRIBR_COMMAND(inspect, "Summarise a workspace", SetupInspect, 10).
#define HDRIBR_COMMAND(name, help, setup, order) \
  static const ::hdribr::cli::CommandRegistrar hdribr_command_##name(#name, help, &setup, order)

namespace hdribr::cli {

// Benchmarks are sub-subcommands of `hdribr bench`, registered like commands (cmd_bench.cc).
std::vector<CommandEntry>& BenchTable();

struct BenchRegistrar {
  BenchRegistrar(const char* name, const char* help, CommandSetup setup);
};

}  // namespace hdribr::cli

// Registers `hdribr bench NAME`: HDRIBR_BENCH(depth, "Depth pass speed", SetupBenchDepth).
#define HDRIBR_BENCH(name, help, setup) \
  static const ::hdribr::cli::BenchRegistrar hdribr_bench_##name(#name, help, &setup)
