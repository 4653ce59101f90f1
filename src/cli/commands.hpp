#pragma once
// The subcommands of `lagrangian`, one class and one file each
// (run_command.cpp, …; `sweep` is in sweep_command.hpp, shared with
// `lagrangian-mpi`). Each has a name and a description (kInfo), declares
// its options (declare; main.cpp turns them into the parser's) and, when the
// command line named it, does its work and returns the exit code (run;
// codes in command_support.hpp).

#include <optional>
#include <string>

#include "command_support.hpp"
#include "lagrangian/scene/bench.hpp"
#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/scene/run.hpp"

namespace CLI {
class App;
}

namespace lagrangian::cli {

/// A subcommand's name and its description in --help.
struct Subcommand {
  const char* name;
  const char* description;
};

/// `run SCENE`: integrates the scene and writes its outputs.
class RunCommand {
 public:
  static const Subcommand kInfo;
  void declare(OptionList& options);
  int run();

 private:
  SceneArgument scene_;
  RunOverrides overrides_;
  std::optional<std::string> out_dir_;
  bool no_plots_ = false, no_animation_ = false, quiet_ = false, allow_drift_ = false;
  std::string animate_to_;
  double animate_seconds_ = 10;
  void apply(scene::Scene& scene) const;
};

/// `inspect SCENE`: the scene at t0, optionally its equilibria and modes.
class InspectCommand {
 public:
  static const Subcommand kInfo;
  void declare(OptionList& options);
  int run();

 private:
  SceneArgument scene_;
  scene::AnalysisRequest analysis_;
  bool json_ = false;
};

/// `list [MODEL]`: the built-in models and example scenes, or one model.
class ListCommand {
 public:
  static const Subcommand kInfo;
  void declare(OptionList& options);
  int run();

 private:
  std::string model_;
};

/// `solve-bvp SCENE --from --to --time`: the stationary-action path.
class BvpCommand {
 public:
  static const Subcommand kInfo;
  void declare(OptionList& options);
  int run();

 private:
  SceneArgument scene_;
  std::string from_, to_, time_;
  scene::BvpRequest request_;
  std::optional<std::string> out_dir_;
  bool no_plots_ = false, quiet_ = false;
  void read_times(const scene::Scene& scene);
};

/// `lyapunov SCENE`: Lyapunov exponents and MEGNO of the scene's model.
class LyapunovCommand {
 public:
  static const Subcommand kInfo;
  void declare(OptionList& options);
  int run();

 private:
  SceneArgument scene_;
  RunOverrides overrides_;
  scene::LyapunovRequest request_;
  bool json_ = false, quiet_ = false;
};

/// `sensitivity SCENE`: ∂x(t_end)/∂x(t0) and ∂x(t_end)/∂p of the scene's model.
class SensitivityCommand {
 public:
  static const Subcommand kInfo;
  void declare(OptionList& options);
  int run();

 private:
  SceneArgument scene_;
  RunOverrides overrides_;
  scene::SensitivityRequest request_;
  bool parameters_only_ = false, json_ = false, quiet_ = false;
};

/// `floquet SCENE --period T`: Floquet multipliers of the scene's model.
class FloquetCommand {
 public:
  static const Subcommand kInfo;
  void declare(OptionList& options);
  int run();

 private:
  SceneArgument scene_;
  RunOverrides overrides_;
  scene::FloquetRequest request_;
  bool any_energy_ = false;
  std::optional<double> period_;
  bool json_ = false, quiet_ = false;
};

/// `bench SCENE`: the work-precision bench.
class BenchCommand {
 public:
  static const Subcommand kInfo;
  void declare(OptionList& options);
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
  static const Subcommand kInfo;
  void declare(OptionList& options);
  /// The application whose completion it writes.
  void set_application(const CLI::App& app) { app_ = &app; }
  int run() const;

 private:
  const CLI::App* app_ = nullptr;
  std::string shell_;
};

}  // namespace lagrangian::cli
