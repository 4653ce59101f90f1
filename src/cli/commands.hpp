#pragma once
// The subcommands of `lagrangian`, one class and one file each
// (run_command.cpp, …; `sweep` is in sweep_command.hpp, shared with
// `lagrangian-mpi`). Each adds itself and its options to the application
// (add) and, when the command line named it, does its work and returns the
// exit code (run; codes in command_support.hpp).

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "command_support.hpp"
#include "lagrangian/bench.hpp"
#include "lagrangian/scene_analysis.hpp"
#include "lagrangian/scene_run.hpp"

namespace lagrangian::cli {

/// `run SCENE`: integrates the scene and writes its outputs.
class RunCommand {
 public:
  CLI::App* add(CLI::App& app);
  int run();

 private:
  SceneArgument scene_;
  std::optional<double> t_end_, rtol_, atol_;
  std::optional<std::string> method_, out_dir_;
  bool no_plots_ = false, no_animation_ = false, quiet_ = false, allow_drift_ = false;
  std::string animate_to_;
  double animate_seconds_ = 10;
  void apply(scene::Scene& scene) const;
};

/// `inspect SCENE`: the scene at t0, optionally its equilibria and modes.
class InspectCommand {
 public:
  CLI::App* add(CLI::App& app);
  int run();

 private:
  SceneArgument scene_;
  scene::AnalysisRequest analysis_;
  bool json_ = false;
};

/// `list [MODEL]`: the built-in models and example scenes, or one model.
class ListCommand {
 public:
  CLI::App* add(CLI::App& app);
  int run();

 private:
  std::string model_;
};

/// `solve-bvp SCENE --from --to --time`: the stationary-action path.
class BvpCommand {
 public:
  CLI::App* add(CLI::App& app);
  int run();

 private:
  SceneArgument scene_;
  std::string from_, to_, time_;
  scene::BvpRequest request_;
  std::optional<std::string> out_dir_;
  bool no_plots_ = false, quiet_ = false;
  void read_times(const scene::Scene& scene);
};

/// `bench SCENE`: the work-precision bench.
class BenchCommand {
 public:
  CLI::App* add(CLI::App& app);
  int run();

 private:
  SceneArgument scene_;
  scene::BenchOptions options_;
  std::optional<std::string> methods_, tolerances_, dt_, stabilization_, out_dir_;
  std::optional<int> repeat_, per_decade_;
  std::optional<double> reference_tol_, t_end_;
  bool no_plots_ = false, quiet_ = false;
  void apply(scene::Scene& scene);
};

/// `completion bash|zsh`: the shell completion script of `app`.
class CompletionScriptCommand {
 public:
  CLI::App* add(CLI::App& app);
  int run() const;

 private:
  const CLI::App* app_ = nullptr;
  std::string shell_;
};

}  // namespace lagrangian::cli
