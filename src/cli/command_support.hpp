#pragma once
// What the subcommands of `lagrangian` share: exit codes, the one-line
// error for bad command-line input, reading a scene with --set settings,
// number lists, and turning what a command throws into its exit code.

#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/scene.hpp"
#include "option_list.hpp"

namespace lagrangian::cli {

/// Exit codes: 0 success; 1 the run failed part-way (non-finite state, step
/// size underflow, max_steps, an output that could not be written); 2 bad
/// input (unknown option, unreadable or invalid scene file, invalid value);
/// 3 a run that finished but whose monitored invariants drifted beyond what
/// its tolerance excuses (RunReport::drift_exceeded; --allow-drift gives 0).
constexpr int kOk = 0, kRunFailed = 1, kBadInput = 2, kDrift = 3;

/// Bad command-line input: `message` is the whole line after "lagrangian: ".
struct BadInput {
  std::string message;
};

/// The scene argument and the --set settings of a subcommand.
struct SceneArgument {
  std::string path;
  std::vector<std::string> settings;
  /// Declares the positional scene argument (described by `help`).
  void add(OptionList& options, const std::string& help);
  /// Declares --set (repeatable KEY=VALUE).
  void add_settings(OptionList& options);
  /// The scene read from `path` with the settings applied (SceneError,
  /// OptionError on bad input).
  scene::Scene load() const;
};

/// Sets scene.run.t_end from --t-end (BadInput unless finite and > t0).
void override_t_end(scene::Scene& scene, const std::optional<double>& t_end);

/// The command line's overrides of a scene's run: --t-end, --method, --rtol
/// and --atol (declared in that order).
struct RunOverrides {
  std::optional<double> t_end, rtol, atol;
  std::optional<std::string> method;
  /// Declares the four options (without --t-end when `with_t_end` is
  /// false); `method_help` describes --method.
  void add(OptionList& options, const std::string& method_help, bool with_t_end = true);
  /// Applies them to scene.run (BadInput naming the flag for a bad value).
  /// With `event_driven`, --method event_driven selects the event-driven
  /// engine instead of a stepper.
  void apply(scene::Scene& scene, bool event_driven) const;
};

/// A scene file's name without its extension, for default output folders;
/// "stdin" for a scene read from standard input ("-").
std::string scene_stem(const std::string& path);

/// BadInput naming `flag` unless v is positive and finite.
void check_positive(const char* flag, double v);

/// A comma-separated list of numbers given to `flag`; BadInput naming it otherwise.
std::vector<double> parse_numbers(const char* flag, const std::string& text);

/// A comma-separated list of words.
std::vector<std::string> comma_list(const std::string& text);

/// Prints a progress line of a long command on standard error.
void print_progress(const std::string& line);

/// The note on plots and the files written (quiet: only a plot failure, on stderr).
void print_outputs(const std::string& plot_note, const std::vector<std::string>& files, bool quiet);

/// Runs `load` (which reads the scene and applies the command line to it)
/// and returns the scene; on bad input prints "lagrangian: …" and returns
/// nothing (the command then exits with kBadInput).
template <class Load>
std::optional<scene::Scene> scene_or_say(Load&& load) {
  try {
    return load();
  } catch (const BadInput& e) {
    std::cerr << "lagrangian: " << e.message << "\n";
  } catch (const Error& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
  }
  return std::nullopt;
}

/// Runs `body` (which returns the exit code) and turns what it throws into
/// a one-line message and the exit code: bad input 2, "<what> failed" 1.
template <class Body>
int guarded(const std::string& what, Body&& body) {
  try {
    return body();
  } catch (const scene::SceneError& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
    return kBadInput;
  } catch (const SimulationError& e) {
    std::cerr << "lagrangian: " << what << " failed at t = " << e.time() << " s: " << e.what() << "\n";
    return kRunFailed;
  } catch (const ParameterError& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
    return kBadInput;
  } catch (const OptionError& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
    return kBadInput;
  } catch (const Error& e) {
    std::cerr << "lagrangian: " << what << " failed: " << e.what() << "\n";
    return kRunFailed;
  } catch (const std::exception& e) {
    std::cerr << "lagrangian: " << what << " failed: " << e.what() << "\n";
    return kRunFailed;
  }
}

/// The body of an analysis subcommand (lyapunov, floquet, sensitivity): reads the scene
/// with the run overrides (after `prepare`, which may throw BadInput), runs
/// `compute(scene)` and prints its json() or, unless quiet, the scene's
/// name and its summary(); exit codes as guarded().
template <class Prepare, class Compute>
int run_analysis(const std::string& what, const SceneArgument& scene_argument, const RunOverrides& overrides,
                 bool json, bool quiet, Prepare&& prepare, Compute&& compute) {
  const std::optional<scene::Scene> scene = scene_or_say([&] {
    prepare();
    scene::Scene s = scene_argument.load();
    overrides.apply(s, false);
    return s;
  });
  if (!scene) return kBadInput;
  return guarded(what, [&] {
    const auto r = compute(*scene);
    if (json) {
      std::cout << r.json();
    } else if (!quiet) {
      std::cout << "scene " << scene->name << "\n" << r.summary();
    }
    return kOk;
  });
}

}  // namespace lagrangian::cli
