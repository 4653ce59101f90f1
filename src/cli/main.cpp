// The `lagrangian` command: run, inspect, bench, sweep and list scenes.
//
// Exit codes: 0 success; 1 the run failed part-way (non-finite state, step
// size underflow, max_steps, an output that could not be written); 2 bad
// input (unknown option, unreadable or invalid scene file, invalid value); 3
// a run that finished but whose conserved energy drifted beyond what its
// tolerance excuses (RunReport::drift_exceeded; --allow-drift gives 0).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <tuple>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "lagrangian/bench.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/params.hpp"
#include "lagrangian/report.hpp"
#include "lagrangian/scene.hpp"
#include "lagrangian/scene_analysis.hpp"
#include "lagrangian/scene_io.hpp"
#include "lagrangian/scene_models.hpp"
#include "lagrangian/scene_run.hpp"
#include "subcommands.hpp"
#include "completion.hpp"
#include "sweep_command.hpp"
#include "written_files.hpp"

namespace fs = std::filesystem;
using namespace lagrangian;

namespace {

/// Exit codes: 3 when a run finished but the sanity monitor found a conserved
/// energy drifting beyond what its tolerance excuses (RunReport::drift_exceeded).
constexpr int kOk = 0, kRunFailed = 1, kBadInput = 2, kDrift = 3;

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

/// A scene file's name without its extension, for default output folders;
/// "stdin" for a scene read from standard input ("-").
std::string scene_stem(const std::string& path) { return path == "-" ? "stdin" : fs::path(path).stem().string(); }

void check_positive(const char* flag, double v) {
  if (!(v > 0) || !std::isfinite(v))
    throw BadInput{std::string("command line: ") + flag + ": must be a positive finite number, got " +
                   detail::format_number(v)};
}

/// A comma-separated list of numbers given to `flag`; BadInput naming it otherwise.
std::vector<double> parse_numbers(const char* flag, const std::string& text) {
  std::vector<double> out;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) {
    const char* begin = item.c_str();
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    while (end && *end == ' ') ++end;
    if (item.empty() || end == begin || *end != '\0')
      throw BadInput{std::string("command line: ") + flag + ": '" + item + "' is not a number (in '" + text + "')"};
    if (!std::isfinite(v))
      throw BadInput{std::string("command line: ") + flag + ": '" + item + "' is not finite (in '" + text + "')"};
    out.push_back(v);
  }
  if (out.empty()) throw BadInput{std::string("command line: ") + flag + ": no values in '" + text + "'"};
  return out;
}

/// `list MODEL`: one built-in model's coordinates with their units, and its
/// parameters with their defaults, units and meaning.
int list_model(const std::string& name) {
  const scene::ModelInfo* m = scene::find_model(name);
  if (!m) {
    std::vector<std::string> names;
    for (const auto& info : scene::builtin_models()) names.push_back(info.name);
    const std::string near = scene::nearest(name, names);
    std::cerr << "lagrangian: list: unknown model '" << name << "'"
              << (near.empty() ? std::string() : "; did you mean '" + near + "'?")
              << " (`lagrangian list` names them all)\n";
    return kBadInput;
  }
  std::cout << m->name << ": " << m->description << "\n\ncoordinates (q, in this order; qd in their units per second):\n";
  for (std::size_t i = 0; i < m->coordinates.size(); ++i)
    std::printf("  %-12s %s\n", m->coordinates[i].c_str(), i < m->units.size() ? m->units[i].c_str() : "");
  std::cout << "\nparameters ([model.parameters]; default, unit, meaning):\n";
  if (m->parameters.empty()) std::cout << "  (none)\n";
  for (const auto& p : m->parameters)
    std::printf("  %-12s %-14.12g %-10s %s\n", p.name.c_str(), p.default_value, p.unit.c_str(), p.description.c_str());
  return kOk;
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

void print_progress(const std::string& line) { std::cerr << "  " << line << "\n"; }

/// The note on plots and the files written (quiet: only a plot failure, on stderr).
void print_outputs(const std::string& plot_note, const std::vector<std::string>& files, bool quiet) {
  if (!quiet) {
    if (!plot_note.empty()) std::cout << "note: " << plot_note << "\n";
    cli::print_written(files);
  } else if (!plot_note.empty() && plot_note.rfind("plots failed", 0) == 0) {
    std::cerr << "lagrangian: " << plot_note << "\n";
  }
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

int run_bench(const scene::Scene& scene, scene::BenchOptions options, bool quiet) {
  if (!quiet) options.progress = &print_progress;
  return guarded("bench", [&] {
    const scene::BenchResult r = scene::bench(scene, options);
    if (!quiet) std::cout << r.table();
    for (const std::string& w : r.warnings) std::cerr << "lagrangian: bench: warning: " << w << "\n";
    print_outputs(r.plot_note, r.files, quiet);
    return kOk;
  });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lagrangian: run mechanical scenes (particles with effects, constraints and contacts, or built-in "
               "generalized-coordinate models) and see what their accuracy cost.\n"
               "Exit codes: 0 ok, 1 run failed, 2 bad input, 3 a run finished but a conserved energy drifted beyond what its "
               "tolerance excuses (--allow-drift: 0)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "lagrangian 0.1.0");

  std::string scene_path;
  std::optional<double> t_end, rtol, atol;
  std::optional<std::string> method, out_dir;
  bool no_plots = false, no_animation = false, quiet = false, allow_drift = false;

  CLI::App* run = app.add_subcommand(
      "run", "Run a scene: writes trajectory.csv, events.csv, report.json, plots and animation.html (open it in a "
             "browser) into the output directory and prints a summary.");
  run->add_option("scene", scene_path, "scene file (TOML, see docs/scenes.md); - reads it from standard input")
      ->required();
  std::vector<std::string> set_texts;
  const char* set_help = "KEY=VALUE: set a numeric scene key, as if the file said so (e.g. model.parameters.e=0.5, "
                         "bodies[0].velocity[2]=3, run.rtol=1e-8); repeatable";
  run->add_option("--set", set_texts, set_help);
  run->add_option("--t-end", t_end, "end time (s), overrides run.t_end");
  run->add_option("--method", method,
                  "stepper: rk4, dopri5, cash_karp54, fehlberg78, bulirsch_stoer, gauss_radau15, rosenbrock4, variational, "
                  "symplectic_rkn_sb3a_mclachlan, velocity_verlet or event_driven");
  run->add_option("--rtol", rtol, "relative tolerance, overrides run.rtol");
  run->add_option("--atol", atol, "absolute tolerance, overrides run.atol");
  run->add_option("--out", out_dir, "output directory, overrides output.directory");
  run->add_flag("--no-plots", no_plots, "do not make plots");
  run->add_flag("--no-animation", no_animation, "do not write animation.html");
  std::string animate_to;
  double animate_seconds = 10;
  run->add_option("--animate-to", animate_to,
                  "also write the run as a video (.mp4, .webm or .gif, through ffmpeg) for slides and documents");
  run->add_option("--animate-seconds", animate_seconds, "length of that video (s, default 10): the whole run");
  run->add_flag("--allow-drift", allow_drift,
                "exit 0 even when a conserved energy drifts beyond what the tolerance excuses (otherwise exit 3)");
  run->add_flag("-q,--quiet", quiet, "print only errors");

  CLI::App* insp = app.add_subcommand(
      "inspect", "Describe a scene at t0: coordinates, degrees of freedom (rank, redundant constraints), momenta, "
                 "cyclic coordinates and conserved quantities, active effects.");
  insp->add_option("scene", scene_path, "scene file (TOML); - reads it from standard input")->required();
  insp->add_option("--set", set_texts, set_help);
  scene::AnalysisRequest analysis;
  insp->add_flag("--equilibria", analysis.equilibria,
                 "find equilibria (minima by NLopt, saddles and maxima by Newton's method) and say which are stable");
  insp->add_flag("--modes", analysis.modes, "normal modes (frequencies and shapes) about each stable equilibrium");
  insp->add_flag("--at-initial-state", analysis.modes_at_initial,
                 "with --modes: linearise about the scene's initial configuration instead");
  insp->add_option("--starts", analysis.starts, "starts of the equilibrium search (default 16)");
  bool inspect_json = false;
  insp->add_flag("--json", inspect_json,
                 "print the description at t0 as one JSON object (not with --equilibria or --modes)");

  CLI::App* lst = app.add_subcommand(
      "list", "List the built-in models and the example scenes; `list MODEL`: that model's coordinates and parameters.");
  std::string list_name;
  lst->add_option("model", list_name, "a built-in model: show its coordinates (with units) and parameters (defaults)");

  std::string bvp_from, bvp_to, bvp_time;
  scene::BvpRequest bvp_req;
  CLI::App* bvp = app.add_subcommand(
      "solve-bvp", "Boundary-value problem by stationary action: the path of the scene's model from q(t0) = FROM to "
                   "q(t1) = TO that makes the discrete action stationary (Newton's method); writes bvp_path.csv and "
                   "plots, and says whether the action is a minimum there.");
  bvp->add_option("scene", scene_path, "scene file (TOML) naming a built-in model")->required();
  bvp->add_option("--from", bvp_from, "q(t0): comma-separated, one value per coordinate")->required();
  bvp->add_option("--to", bvp_to, "q(t1): comma-separated, one value per coordinate")->required();
  bvp->add_option("--time", bvp_time, "T (from the scene's t0) or t0:t1, in s")->required();
  bvp->add_option("--steps", bvp_req.steps, "number of time steps K (default 200)");
  bvp->add_option("--rule", bvp_req.rule, "discrete Lagrangian: midpoint (default) or trapezoidal");
  bvp->add_option("--out", out_dir, "output directory (default out/bvp/<scene file name>)");
  bvp->add_flag("--no-plots", no_plots, "do not make plots");
  bvp->add_flag("-q,--quiet", quiet, "print only errors");

  scene::BenchOptions bench_opt;
  std::optional<std::string> methods_text, tolerances_text, dt_text, stabilization;
  std::optional<int> repeat, per_decade;
  std::optional<double> reference_tol;
  CLI::App* bench = app.add_subcommand(
      "bench", "Work-precision bench of a scene: runs it with each stepper at each tolerance, measures the error "
               "(against the model's closed form, or a tight reference run) and the median wall time, and writes "
               "work_precision.csv, bench.json and diagrams (error against wall time and against RHS evaluations).");
  bench->add_option("scene", scene_path, "scene file (TOML); - reads it from standard input")->required();
  bench->add_option("--set", set_texts, set_help);
  bench->add_option("--methods", methods_text,
                    "comma-separated steppers (default dopri5,cash_karp54,fehlberg78,bulirsch_stoer,gauss_radau15,rk4)");
  bench->add_option("--tolerances", tolerances_text, "LOOSE:TIGHT rtol = atol range (default 1e-3:1e-13)");
  bench->add_option("--per-decade", per_decade, "tolerances (and rk4 step sizes) per decade (default 1)");
  bench->add_option("--dt", dt_text, "LARGE:SMALL step sizes of rk4 in s (default span/100:span/1e5)");
  bench->add_option("--repeat", repeat, "timed runs per configuration; the median is kept (default 3)");
  bench->add_option("--reference-tol", reference_tol, "rtol = atol of the gauss_radau15 reference run where there is neither a closed form nor a shipped "
                    "reference (default 1e-11, its tightest; below it runs at 1e-11)");
  bench->add_option("--t-end", t_end, "end time (s), overrides run.t_end");
  bench->add_option("--stabilization", stabilization, "constraint drift control: none, baumgarte or projection");
  bench->add_option("--out", out_dir, "output directory (default out/bench/<scene file name>)");
  bench->add_flag("--no-plots", no_plots, "do not draw the diagrams");
  bench->add_flag("-q,--quiet", quiet, "print only errors");

  cli::SweepCommand sweep_command;
  CLI::App* sweep = sweep_command.add(app);

  CLI::App* completion = app.add_subcommand(
      "completion", "Print a shell completion script: source <(lagrangian completion bash), or zsh");
  std::string shell;
  completion->add_option("shell", shell, "the shell: bash or zsh")->required();

  if (const auto word = cli::unknown_subcommand(app, argc, argv)) {
    std::cerr << "lagrangian: " << cli::unknown_subcommand_message(app, *word) << "\n";
    return kBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kOk : kBadInput;
  }

  if (completion->parsed()) {
    if (shell == "bash") {
      std::cout << cli::bash_completion(app);
    } else if (shell == "zsh") {
      std::cout << cli::zsh_completion(app);
    } else {
      std::cerr << "lagrangian: completion: unknown shell '" << shell << "' (bash and zsh are supported)\n";
      return kBadInput;
    }
    return kOk;
  }
  if (lst->parsed()) return list_name.empty() ? list(argv[0]) : list_model(list_name);
  if (sweep->parsed()) return sweep_command.run();

  scene::Scene scene;
  try {
    std::vector<scene::KeySetting> settings;
    for (const std::string& text : set_texts) settings.push_back(scene::parse_key_setting(text));
    scene = scene::load_scene(scene_path, settings);
    if (t_end) {  // run and bench
      if (!std::isfinite(*t_end) || !(*t_end > scene.run.t0))
        throw BadInput{"command line: --t-end: must be finite and > t0 = " + detail::format_number(scene.run.t0) +
                       " s, got " + detail::format_number(*t_end)};
      scene.run.t_end = *t_end;
      scene.source.overrides["run.t_end"] = "--t-end";
    }
    if (run->parsed()) {
      if (rtol) {
        check_positive("--rtol", *rtol);
        scene.run.rtol = *rtol;
        scene.source.overrides["run.rtol"] = "--rtol";
      }
      if (atol) {
        check_positive("--atol", *atol);
        scene.run.atol = *atol;
        scene.source.overrides["run.atol"] = "--atol";
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
        scene.source.overrides["run.method"] = "--method";
        if (*method == "event_driven") scene.run.engine = "event_driven";
        else if (scene.run.engine == "event_driven") scene.run.engine = "ode";
      }
      if (out_dir) {
        scene.output.directory = *out_dir;
        scene.source.overrides["output.directory"] = "--out";
      }
      if (no_plots) scene.output.plots = false;
      if (no_animation) scene.output.animation = false;
      if (!animate_to.empty()) {
        const std::string ext = fs::path(animate_to).extension().string();
        if (ext != ".mp4" && ext != ".webm" && ext != ".gif")
          throw BadInput{"command line: --animate-to: '" + animate_to + "': unknown format '" + ext +
                         "' (use .mp4, .webm or .gif)"};
      }
      if (!(animate_seconds > 0 && animate_seconds <= 3600))
        throw BadInput{"command line: --animate-seconds: must be in (0, 3600] s, got " +
                       std::to_string(animate_seconds)};
    }
    if (bench->parsed()) {
      if (stabilization) {
        if (*stabilization == "none") scene.run.stabilization = Stabilization::none;
        else if (*stabilization == "baumgarte") scene.run.stabilization = Stabilization::baumgarte;
        else if (*stabilization == "projection") scene.run.stabilization = Stabilization::projection;
        else
          throw BadInput{"command line: --stabilization: must be none, baumgarte or projection, got '" +
                         *stabilization + "'"};
      }
      try {
        if (methods_text) {
          bench_opt.methods.clear();
          std::string item;
          std::istringstream in(*methods_text);
          while (std::getline(in, item, ',')) bench_opt.methods.push_back(item);
        }
        if (tolerances_text)
          std::tie(bench_opt.tolerance_loose, bench_opt.tolerance_tight) =
              scene::parse_range("--tolerances", *tolerances_text);
        if (dt_text) std::tie(bench_opt.dt_large, bench_opt.dt_small) = scene::parse_range("--dt", *dt_text);
      } catch (const OptionError& e) {
        throw BadInput{std::string("command line: ") + e.what()};
      }
      if (repeat) bench_opt.repeat = *repeat;
      if (per_decade) bench_opt.per_decade = *per_decade;
      if (reference_tol) bench_opt.reference_tolerance = *reference_tol;
      bench_opt.out_dir = out_dir ? *out_dir : "out/bench/" + scene_stem(scene_path);
      bench_opt.plots = !no_plots;
      bench_opt.png = scene.output.png;
      bench_opt.svg = scene.output.svg;
      try {
        bench_opt.validate();
      } catch (const OptionError& e) {
        const std::string what = e.what();
        // Name the command-line option the field comes from.
        const std::string flag = what.rfind("methods", 0) == 0       ? "--methods"
                                 : what.rfind("tolerances", 0) == 0  ? "--tolerances"
                                 : what.rfind("per_decade", 0) == 0  ? "--per-decade"
                                 : what.rfind("dt", 0) == 0          ? "--dt"
                                 : what.rfind("repeat", 0) == 0      ? "--repeat"
                                 : what.rfind("reference_tolerance", 0) == 0 ? "--reference-tol"
                                                                             : "--out";
        throw BadInput{"command line: " + flag + what.substr(what.find(':'))};
      }
    }
  } catch (const BadInput& e) {
    std::cerr << "lagrangian: " << e.message << "\n";
    return kBadInput;
  } catch (const Error& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
    return kBadInput;
  }

  if (bvp->parsed()) {
    try {
      bvp_req.from = parse_numbers("--from", bvp_from);
      bvp_req.to = parse_numbers("--to", bvp_to);
      const auto colon = bvp_time.find(':');
      if (colon == std::string::npos) {
        const std::vector<double> T = parse_numbers("--time", bvp_time);
        if (T.size() != 1 || !(T[0] > 0))
          throw BadInput{"command line: --time: must be a positive duration T or t0:t1, got '" + bvp_time + "'"};
        bvp_req.t0 = scene.run.t0;
        bvp_req.t1 = scene.run.t0 + T[0];
      } else {
        const std::vector<double> a = parse_numbers("--time", bvp_time.substr(0, colon));
        const std::vector<double> b = parse_numbers("--time", bvp_time.substr(colon + 1));
        if (a.size() != 1 || b.size() != 1 || !(b[0] > a[0]))
          throw BadInput{"command line: --time: need t0:t1 with t1 > t0, got '" + bvp_time + "'"};
        bvp_req.t0 = a[0];
        bvp_req.t1 = b[0];
      }
    } catch (const BadInput& e) {
      std::cerr << "lagrangian: " << e.message << "\n";
      return kBadInput;
    }
    bvp_req.out_dir = out_dir ? *out_dir : "out/bvp/" + scene_stem(scene_path);
    bvp_req.plots = !no_plots;
    bvp_req.png = scene.output.png;
    bvp_req.svg = scene.output.svg;
    return guarded("solve-bvp", [&] {
      const scene::BvpRun r = scene::solve_bvp(scene, bvp_req);
      if (!quiet) std::cout << "scene " << scene.name << "\n" << r.summary();
      print_outputs(r.plot_note, r.files, quiet);
      return kOk;
    });
  }

  if (insp->parsed()) {
    try {
      if (analysis.modes_at_initial && !analysis.modes)
        throw OptionError("command line: --at-initial-state: only with --modes");
      if (inspect_json && (analysis.equilibria || analysis.modes))
        throw OptionError("command line: --json: describes the state at t0; --equilibria and --modes print text");
      if (inspect_json) {
        std::cout << scene::inspect(scene, true);
        return kOk;
      }
      const std::string analysed =
          analysis.equilibria || analysis.modes ? scene::analyse(scene, analysis) : std::string();
      std::cout << scene::inspect(scene) << analysed;
      return kOk;
    } catch (const SimulationError& e) {
      std::cerr << "lagrangian: " << e.what() << "\n";
      return kRunFailed;
    } catch (const Error& e) {
      std::cerr << "lagrangian: " << e.what() << "\n";
      return kBadInput;
    }
  }

  if (bench->parsed()) return run_bench(scene, bench_opt, quiet);

  return guarded("run", [&] {
    scene::RunControls controls;
    controls.progress = !quiet;
    controls.video_path = animate_to;
    controls.video.seconds = animate_seconds;
    const scene::RunResult r = scene::run(scene, controls);
    if (!quiet) {
      std::cout << "scene " << scene.name << " — engine " << r.engine << "\n" << r.report.summary();
      if (r.gas) std::cout << r.gas->summary();
      if (!r.effect_evaluations.empty()) {
        std::cout << "effects evaluated:";
        for (const auto& [name, count] : r.effect_evaluations) std::cout << " " << name << " " << count << ";";
        std::cout << "\n";
      }
    }
    print_outputs(r.plot_note, r.files, quiet);
    if (!r.animation_note.empty()) std::cerr << "lagrangian: " << r.animation_note << "\n";
    if (!animate_to.empty() && !r.video_written) return kRunFailed;  // asked for, not made: said above
    if (r.report.drift_exceeded && !allow_drift) {
      std::cerr << "lagrangian: the run finished, but its energy drifted beyond what its tolerance excuses (see the "
                   "warning; report.json has drift_exceeded = true): exit 3; --allow-drift accepts it\n";
      return kDrift;
    }
    return kOk;
  });
}
