// The `lagrangian` command: run, inspect and list scenes.
//
// Exit codes: 0 success; 1 the run failed part-way (non-finite state, step
// size underflow, max_steps, an output that could not be written); 2 bad
// input (unknown option, unreadable or invalid scene file, invalid value).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "lagrangian/errors.hpp"
#include "lagrangian/report.hpp"
#include "lagrangian/scene.hpp"
#include "lagrangian/scene_io.hpp"
#include "lagrangian/scene_models.hpp"
#include "lagrangian/scene_run.hpp"

namespace fs = std::filesystem;
using namespace lagrangian;

namespace {

constexpr int kOk = 0, kRunFailed = 1, kBadInput = 2;

/// Directories searched for the example scenes `lagrangian list` shows.
std::vector<fs::path> scene_dirs(const char* argv0) {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("LAGRANGIAN_SCENES")) dirs.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  if (!ec) dirs.push_back(exe.parent_path().parent_path() / "share" / "lagrangian" / "scenes");
  (void)argv0;
#ifdef LAGRANGIAN_SOURCE_SCENES
  dirs.emplace_back(LAGRANGIAN_SOURCE_SCENES);
#endif
  return dirs;
}

struct BadInput {
  std::string message;
};

void check_positive(const char* flag, double v) {
  if (!(v > 0) || !std::isfinite(v))
    throw BadInput{std::string("command line: ") + flag + ": must be a positive finite number, got " + std::to_string(v)};
}

int list(const char* argv0) {
  std::cout << "Built-in models (use in a scene as [model] name = \"...\"):\n";
  for (const auto& m : scene::builtin_models()) {
    std::printf("  %-28s %s\n", m.name.c_str(), m.description.c_str());
  }
  for (const fs::path& dir : scene_dirs(argv0)) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.path().extension() == ".toml") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    std::cout << "\nExample scenes (" << dir.string() << "):\n";
    for (const auto& f : files) {
      std::string what;
      try {
        const scene::Scene s = scene::load_scene(f.string());
        what = s.description.empty() ? s.name : s.description;
      } catch (const Error& e) {
        what = std::string("(does not load: ") + e.what() + ")";
      }
      std::printf("  %-28s %s\n", f.filename().string().c_str(), what.c_str());
    }
    break;  // the first directory that exists
  }
  return kOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lagrangian: run mechanical scenes (particles with effects, constraints and contacts, or built-in "
               "generalized-coordinate models) and see what their accuracy cost.\n"
               "Exit codes: 0 ok, 1 run failed, 2 bad input."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "lagrangian 0.1.0");

  std::string scene_path;
  std::optional<double> t_end, rtol, atol;
  std::optional<std::string> method, out_dir;
  bool no_plots = false, quiet = false;

  CLI::App* run = app.add_subcommand(
      "run", "Run a scene: writes trajectory.csv, events.csv, report.json and plots into the output directory and "
             "prints a summary.");
  run->add_option("scene", scene_path, "scene file (TOML, see docs/scenes.md)")->required();
  run->add_option("--t-end", t_end, "end time (s), overrides run.t_end");
  run->add_option("--method", method,
                  "stepper: rk4, dopri5, cash_karp54, fehlberg78, bulirsch_stoer, rosenbrock4, variational, "
                  "symplectic_rkn_sb3a_mclachlan, velocity_verlet or event_driven");
  run->add_option("--rtol", rtol, "relative tolerance, overrides run.rtol");
  run->add_option("--atol", atol, "absolute tolerance, overrides run.atol");
  run->add_option("--out", out_dir, "output directory, overrides output.directory");
  run->add_flag("--no-plots", no_plots, "do not make plots");
  run->add_flag("-q,--quiet", quiet, "print only errors");

  CLI::App* insp = app.add_subcommand(
      "inspect", "Describe a scene at t0: coordinates, degrees of freedom (rank, redundant constraints), momenta, "
                 "cyclic coordinates and conserved quantities, active effects.");
  insp->add_option("scene", scene_path, "scene file (TOML)")->required();

  CLI::App* lst = app.add_subcommand("list", "List the built-in models and the example scenes.");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kOk : kBadInput;
  }

  if (lst->parsed()) return list(argv[0]);

  scene::Scene scene;
  try {
    scene = scene::load_scene(scene_path);
    if (run->parsed()) {
      if (t_end) {
        if (!std::isfinite(*t_end) || !(*t_end > scene.run.t0))
          throw BadInput{"command line: --t-end: must be finite and > t0 = " + std::to_string(scene.run.t0) +
                         " s, got " + std::to_string(*t_end)};
        scene.run.t_end = *t_end;
      }
      if (rtol) {
        check_positive("--rtol", *rtol);
        scene.run.rtol = *rtol;
      }
      if (atol) {
        check_positive("--atol", *atol);
        scene.run.atol = *atol;
      }
      if (method) {
        auto names = stepper_names();
        names.push_back("event_driven");
        if (std::find(names.begin(), names.end(), *method) == names.end()) {
          const std::string near = scene::nearest(*method, names);
          throw BadInput{"command line: --method: unknown stepper '" + *method + "'" +
                         (near.empty() ? std::string() : "; did you mean '" + near + "'?")};
        }
        scene.run.method = *method;
        if (*method == "event_driven") scene.run.engine = "event_driven";
        else if (scene.run.engine == "event_driven") scene.run.engine = "ode";
      }
      if (out_dir) scene.output.directory = *out_dir;
      if (no_plots) scene.output.plots = false;
    }
  } catch (const BadInput& e) {
    std::cerr << "lagrangian: " << e.message << "\n";
    return kBadInput;
  } catch (const Error& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
    return kBadInput;
  }

  if (insp->parsed()) {
    try {
      std::cout << scene::inspect(scene);
      return kOk;
    } catch (const SimulationError& e) {
      std::cerr << "lagrangian: " << e.what() << "\n";
      return kRunFailed;
    } catch (const Error& e) {
      std::cerr << "lagrangian: " << e.what() << "\n";
      return kBadInput;
    }
  }

  try {
    scene::RunControls controls;
    controls.progress = !quiet;
    const scene::RunResult r = scene::run(scene, controls);
    if (!quiet) {
      std::cout << "scene " << scene.name << " — engine " << r.engine << "\n" << r.report.summary();
      if (!r.effect_evaluations.empty()) {
        std::cout << "effects evaluated:";
        for (const auto& [name, count] : r.effect_evaluations) std::cout << " " << name << " " << count << ";";
        std::cout << "\n";
      }
      if (!r.plot_note.empty()) std::cout << "note: " << r.plot_note << "\n";
      std::cout << "wrote:";
      for (const auto& f : r.files) std::cout << " " << f;
      std::cout << "\n";
    } else if (!r.plot_note.empty() && r.plot_note.rfind("plots failed", 0) == 0) {
      std::cerr << "lagrangian: " << r.plot_note << "\n";
    }
    return kOk;
  } catch (const scene::SceneError& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
    return kBadInput;
  } catch (const SimulationError& e) {
    std::cerr << "lagrangian: run failed at t = " << e.time() << " s: " << e.what() << "\n";
    return kRunFailed;
  } catch (const ParameterError& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
    return kBadInput;
  } catch (const OptionError& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
    return kBadInput;
  } catch (const Error& e) {
    std::cerr << "lagrangian: run failed: " << e.what() << "\n";
    return kRunFailed;
  } catch (const std::exception& e) {
    std::cerr << "lagrangian: run failed: " << e.what() << "\n";
    return kRunFailed;
  }
}
