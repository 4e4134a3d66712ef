// `hdribr bench NAME`: benchmarks, each registered with HDRIBR_BENCH in its own file. Each
// prints JSON (stdout, or --json FILE) and a readable table.
#include <algorithm>
#include <string>

#include "cli/command.h"

namespace hdribr::cli {

std::vector<CommandEntry>& BenchTable() {
  static std::vector<CommandEntry> table;
  return table;
}

BenchRegistrar::BenchRegistrar(const char* name, const char* help, CommandSetup setup) {
  auto& table = BenchTable();
  table.push_back({name, help, setup, 0});
  std::sort(table.begin(), table.end(), [](const CommandEntry& a, const CommandEntry& b) {
    return std::string(a.name) < b.name;
  });
}

namespace {

CommandRunner SetupBench(CLI::App& sub) {
  sub.require_subcommand(1);
  auto runners = std::make_shared<std::vector<std::pair<CLI::App*, CommandRunner>>>();
  for (const auto& entry : BenchTable()) {
    CLI::App* bench = sub.add_subcommand(entry.name, entry.help);
    runners->emplace_back(bench, entry.setup(*bench));
  }
  return [runners] {
    for (auto& [bench, run] : *runners) {
      if (bench->parsed()) return run();
    }
    return 64;
  };
}

}  // namespace

HDRIBR_COMMAND(bench, "Benchmarks (JSON + table): see `hdribr bench --help`", SetupBench, 90);

}  // namespace hdribr::cli
