// The `lagrangian` command: run, inspect, list, solve-bvp, bench, sweep and
// completion, one file each (commands.hpp, sweep_command.hpp); exit codes
// in command_support.hpp.

#include <functional>
#include <iostream>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "subcommands.hpp"
#include "sweep_command.hpp"

using namespace lagrangian::cli;

int main(int argc, char** argv) {
  CLI::App app{"lagrangian: run mechanical scenes (particles with effects, constraints and contacts, or built-in "
               "generalized-coordinate models) and see what their accuracy cost.\n"
               "Exit codes: 0 ok, 1 run failed, 2 bad input, 3 a run finished but a conserved energy drifted beyond what its "
               "tolerance excuses (--allow-drift: 0)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "lagrangian 0.1.0");

  RunCommand run;
  InspectCommand inspect;
  ListCommand list;
  BvpCommand bvp;
  BenchCommand bench;
  SweepCommand sweep;
  CompletionScriptCommand completion;
  // In this order in --help and in the completion scripts.
  const std::vector<std::pair<CLI::App*, std::function<int()>>> commands = {
      {run.add(app), [&] { return run.run(); }},
      {inspect.add(app), [&] { return inspect.run(); }},
      {list.add(app), [&] { return list.run(); }},
      {bvp.add(app), [&] { return bvp.run(); }},
      {bench.add(app), [&] { return bench.run(); }},
      {sweep.add(app), [&] { return sweep.run(); }},
      {completion.add(app), [&] { return completion.run(); }},
  };

  if (const auto word = unknown_subcommand(app, argc, argv)) {
    std::cerr << "lagrangian: " << unknown_subcommand_message(app, *word) << "\n";
    return kBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kOk : kBadInput;
  }
  for (const auto& [command, body] : commands)
    if (command->parsed()) return body();
  return kBadInput;  // require_subcommand(1) leaves no other case
}
