// The `lagrangian` command: run, inspect, list, solve-bvp, lyapunov, floquet, sensitivity, bench, sweep and
// completion, one file each (commands.hpp, sweep_command.hpp); exit codes
// in command_support.hpp. The parser (CLI11) is compiled here only.

#include <functional>
#include <iostream>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "subcommands.hpp"
#include "sweep_command.hpp"

using namespace lagrangian::cli;

namespace {

/// A subcommand's declared options as CLI11 options of `command`.
class Cli11Options final : public OptionList {
 public:
  explicit Cli11Options(CLI::App* command) : c_(command) {}
  void positional(const std::string& name, std::string& v, const std::string& help, bool required) override {
    CLI::Option* o = c_->add_option(name, v, help);
    if (required) o->required();
  }
  void value(const std::string& names, std::string& v, const std::string& help, bool required) override {
    CLI::Option* o = c_->add_option(names, v, help);
    if (required) o->required();
  }
  void value(const std::string& names, std::optional<std::string>& v, const std::string& help) override {
    c_->add_option(names, v, help);
  }
  void value(const std::string& names, std::optional<double>& v, const std::string& help) override {
    c_->add_option(names, v, help);
  }
  void value(const std::string& names, std::optional<int>& v, const std::string& help) override {
    c_->add_option(names, v, help);
  }
  void value(const std::string& names, double& v, const std::string& help) override { c_->add_option(names, v, help); }
  void value(const std::string& names, int& v, const std::string& help) override { c_->add_option(names, v, help); }
  void values(const std::string& names, std::vector<std::string>& v, const std::string& help) override {
    c_->add_option(names, v, help);
  }
  void flag(const std::string& names, bool& v, const std::string& help) override { c_->add_flag(names, v, help); }

 private:
  CLI::App* c_;
};

/// Adds `command` as a subcommand of `app`; returns the subcommand and how to run it.
template <class Command>
std::pair<CLI::App*, std::function<int()>> add(CLI::App& app, Command& command) {
  CLI::App* sub = app.add_subcommand(Command::kInfo.name, Command::kInfo.description);
  Cli11Options options(sub);
  command.declare(options);
  return {sub, [&command] { return command.run(); }};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lagrangian: run mechanical scenes (particles with effects, constraints and contacts, or built-in "
               "generalized-coordinate models) and see what their accuracy cost.\n"
               "Exit codes: 0 ok, 1 run failed, 2 bad input, 3 a run finished but a monitored invariant (energy, "
               "momentum, constraint residual, closed-form error) drifted beyond what its tolerance excuses "
               "(--allow-drift: 0)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "lagrangian 0.1.0");

  RunCommand run;
  InspectCommand inspect;
  ListCommand list;
  BvpCommand bvp;
  LyapunovCommand lyapunov;
  FloquetCommand floquet;
  SensitivityCommand sensitivity;
  BenchCommand bench;
  SweepCommand sweep;
  CompletionScriptCommand completion;
  completion.set_application(app);
  // In this order in --help and in the completion scripts.
  const std::vector<std::pair<CLI::App*, std::function<int()>>> commands = {
      add(app, run), add(app, inspect), add(app, list), add(app, bvp), add(app, lyapunov), add(app, floquet),
      add(app, sensitivity), add(app, bench),
      {sweep.add(app), [&] { return sweep.run(); }}, add(app, completion)};

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
