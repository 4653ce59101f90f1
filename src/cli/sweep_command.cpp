// The `sweep` subcommand (see sweep_command.hpp and docs/sweeps.md).

#include "sweep_command.hpp"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/io.hpp"
#include "command_support.hpp"
#include "written_files.hpp"

namespace lagrangian::cli {
namespace {

constexpr int kInterrupted = 130;  // 128 + SIGINT, as shells report it

// Set by the first SIGINT or SIGTERM: the sweep starts no further run and
// cleans up. The handler restores the default action, so a second Ctrl-C
// ends the process at once.
std::atomic<bool> interrupt_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");
extern "C" void on_interrupt(int sig) {
  interrupt_requested.store(true);
  std::signal(sig, SIG_DFL);
}

}  // namespace

CLI::App* SweepCommand::add(CLI::App& app) {
  CLI::App* c = app.add_subcommand(
      "sweep",
      "Run a scene at many points: --vary scene keys (or variables) over grids or, with --monte-carlo, random "
      "distributions; writes sweep.csv (one row per point: values, status, final state, events, energy, error, "
      "cost) and plots (curves for one key, heat maps for two). Exit 1 when some runs failed.");
  c->add_option("scene", scene_path_, "scene file (TOML, see docs/scenes.md)")->required();
  c->add_option("--vary", vary_,
                "KEY=START:STOP:COUNT[:log] (a grid), KEY=uniform:A:B or KEY=normal:MU:SIGMA (with --monte-carlo); "
                "KEY is a scene key (model.parameters.e, bodies[0].velocity[2], run.rtol) or a variable name for --set")
      ->required()
      ->allow_extra_args(false);
  c->add_option("--set", set_, "KEY=EXPRESSION: a scene key computed from the variables, e.g. 'model.qd[0]=20*cos(a)'")
      ->allow_extra_args(false);
  c->add_option("--first-time", first_time_,
                "NAME=EXPRESSION: column t_NAME, the first time the expression of the coordinates (theta1, "
                "theta1_dot, t, ...) becomes positive, from the run's samples")
      ->allow_extra_args(false);
  c->add_option("--monte-carlo", monte_carlo_, "number of random points (each --vary a distribution)");
  c->add_option("--seed", seed_, "random seed of --monte-carlo (default 1)");
  c->add_option("--threads", threads_, "worker threads (default: the number of cores)");
  c->add_option("--output", outputs_,
                "comma-separated column groups: final, events, energy, error, cost, wall, chaos (the largest "
                "Lyapunov exponent and MEGNO; default final,events,energy,error,cost)");
  c->add_option("--plot", plot_, "comma-separated columns to plot (default: t_final, q_*, impact_energy_loss, first_*, "
                "lyapunov_max, megno)");
  c->add_option("--out", out_dir_, "output directory (default out/sweep/<scene file name>)");
  c->add_flag("--no-plots", no_plots_, "do not draw plots");
  c->add_flag("-q,--quiet", quiet_, "print only errors");
  return c;
}

int SweepCommand::fail(bool speak, const std::string& message, int code) {
  error_ = message;
  if (speak) std::cerr << "lagrangian: " << message << "\n";
  return code;
}

int SweepCommand::run(int rank, int ranks, std::function<std::string(const std::string&)> gather) {
  const bool speak = rank == 0;
  scene::SweepOptions o;
  try {
    for (const auto& v : vary_) o.vary.push_back(scene::parse_vary(v));
    for (const auto& s : set_) o.set.push_back(scene::parse_set(s));
    for (const auto& f : first_time_) o.first_times.push_back(scene::parse_first_time(f));
    // Read as signed integers: "-5" must not wrap to 2^64 - 5.
    if (monte_carlo_) {
      if (*monte_carlo_ < 1) throw OptionError("--monte-carlo: must be >= 1, got " + std::to_string(*monte_carlo_));
      o.monte_carlo = static_cast<std::uint64_t>(*monte_carlo_);
    }
    if (seed_ < 0) throw OptionError("--seed: must be a non-negative integer, got " + std::to_string(seed_));
    o.seed = static_cast<std::uint64_t>(seed_);
    if (threads_) {
      if (*threads_ < 1) throw OptionError("--threads: must be >= 1, got " + std::to_string(*threads_));
      o.threads = *threads_;
    }
    if (outputs_) o.outputs = comma_list(*outputs_);
    if (plot_) o.plot_columns = comma_list(*plot_);
    o.out_dir = out_dir_ ? *out_dir_ : "out/sweep/" + std::filesystem::path(scene_path_).stem().string();
    o.plots = !no_plots_;
    o.progress = !quiet_;
    o.rank = rank;
    o.ranks = ranks;
    o.gather = std::move(gather);
    o.validate();
  } catch (const Error& e) {
    return fail(speak, std::string("command line: ") + e.what(), kBadInput);
  }
  try {
    // The scene's own format (png, svg) for the plots.
    const scene::Scene s = scene::load_scene(scene_path_);
    o.png = s.output.png;
    o.svg = s.output.svg;
    o.cancel = &interrupt_requested;
    if (speak)  // before the runs, which may be long
      for (const std::string& w : scene::sweep_warnings(o)) std::cerr << "lagrangian: warning: " << w << "\n";
    std::signal(SIGINT, on_interrupt);
    std::signal(SIGTERM, on_interrupt);
    const scene::SweepResult r = scene::sweep(scene_path_, o);
    if (!speak) return r.failed > 0 ? kRunFailed : kOk;
    if (!quiet_) {
      std::printf("sweep of %s: %llu runs (%llu failed) in %.3f s on %d thread%s x %d rank%s: %.2f runs/s\n",
                  scene_path_.c_str(), static_cast<unsigned long long>(r.points),
                  static_cast<unsigned long long>(r.failed), r.run_time_s, r.threads, r.threads == 1 ? "" : "s",
                  r.ranks, r.ranks == 1 ? "" : "s", static_cast<double>(r.points) / r.run_time_s);
      if (!r.plot_note.empty()) std::cout << "note: " << r.plot_note << "\n";
      print_written(r.files);
    } else if (r.plot_note.rfind("plots failed", 0) == 0) {
      std::cerr << "lagrangian: " << r.plot_note << "\n";
    }
    if (r.failed > 0) {
      std::cerr << "lagrangian: sweep: " << r.failed << " of " << r.points
                << " runs failed (their rows in sweep.csv say why)\n";
      return kRunFailed;
    }
    return kOk;
  } catch (const scene::SweepInterrupted& e) {
    return fail(speak, e.what(), kInterrupted);
  } catch (const SimulationError& e) {
    return fail(speak, std::string("sweep failed: ") + e.what(), kRunFailed);
  } catch (const OptionError& e) {  // SceneError too: bad input
    return fail(speak, e.what(), kBadInput);
  } catch (const ParameterError& e) {
    return fail(speak, e.what(), kBadInput);
  } catch (const std::exception& e) {
    return fail(speak, std::string("sweep failed: ") + e.what(), kRunFailed);
  }
}

}  // namespace lagrangian::cli
