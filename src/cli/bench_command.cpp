// `lagrangian bench SCENE`: the work-precision bench of a scene (every
// stepper at every tolerance: error against wall time and evaluations).

#include <iostream>
#include <tuple>

#include "commands.hpp"
#include "lagrangian/scene/io.hpp"

namespace lagrangian::cli {

const Subcommand BenchCommand::kInfo{"bench",
                               "Work-precision bench of a scene: runs it with each stepper at each tolerance, measures the error "
               "(against the model's closed form, or a tight reference run) and the median wall time, and writes "
               "work_precision.csv, bench.json and diagrams (error against wall time and against RHS evaluations)."};

void BenchCommand::declare(OptionList& o) {
  scene_.add(o, "scene file (TOML); - reads it from standard input");
  scene_.add_settings(o);
  o.value("--methods", methods_,
                "comma-separated steppers (default dopri5,cash_karp54,fehlberg78,bulirsch_stoer,gauss_radau15,rk4)");
  o.value("--tolerances", tolerances_, "LOOSE:TIGHT rtol = atol range (default 1e-3:1e-13)");
  o.value("--per-decade", per_decade_, "tolerances (and rk4 step sizes) per decade (default 1)");
  o.value("--dt", dt_, "LARGE:SMALL step sizes of rk4 in s (default span/100:span/1e5)");
  o.value("--repeat", repeat_, "timed runs per configuration; the median is kept (default 3)");
  o.value("--reference-tol", reference_tol_,
                "rtol = atol of the gauss_radau15 reference run where there is neither a closed form nor a shipped "
                "reference (default 1e-11, its tightest; below it runs at 1e-11)");
  o.value("--t-end", t_end_, "end time (s), overrides run.t_end");
  o.value("--stabilization", stabilization_, "constraint drift control: none, baumgarte or projection");
  o.value("--out", out_dir_, "output directory (default out/bench/<scene file name>)");
  o.flag("--no-plots", no_plots_, "do not draw the diagrams");
  o.flag("-q,--quiet", quiet_, "print only errors");
}

/// The command line's overrides of the scene and the bench's options.
void BenchCommand::apply(scene::Scene& scene) {
  override_t_end(scene, t_end_);
  if (stabilization_) {
    if (*stabilization_ == "none") scene.run.stabilization = Stabilization::none;
    else if (*stabilization_ == "baumgarte") scene.run.stabilization = Stabilization::baumgarte;
    else if (*stabilization_ == "projection") scene.run.stabilization = Stabilization::projection;
    else
      throw BadInput{"command line: --stabilization: must be none, baumgarte or projection, got '" + *stabilization_ +
                     "'"};
  }
  try {
    if (methods_) {
      options_.methods.clear();
      for (const std::string& name : comma_list(*methods_)) options_.methods.push_back(parse_method(name, "--methods"));
    }
    if (tolerances_)
      std::tie(options_.tolerance_loose, options_.tolerance_tight) = scene::parse_range("--tolerances", *tolerances_);
    if (dt_) std::tie(options_.dt_large, options_.dt_small) = scene::parse_range("--dt", *dt_);
  } catch (const OptionError& e) {
    throw BadInput{std::string("command line: ") + e.what()};
  }
  if (repeat_) options_.repeat = *repeat_;
  if (per_decade_) options_.per_decade = *per_decade_;
  if (reference_tol_) options_.reference_tolerance = *reference_tol_;
  options_.out_dir = out_dir_ ? *out_dir_ : "out/bench/" + scene_stem(scene_.path);
  options_.plots = !no_plots_;
  options_.png = scene.output.png;
  options_.svg = scene.output.svg;
  try {
    options_.validate();
  } catch (const OptionError& e) {
    const std::string what = e.what();
    // Name the command-line option the field comes from.
    const std::string flag = what.rfind("methods", 0) == 0               ? "--methods"
                             : what.rfind("tolerances", 0) == 0          ? "--tolerances"
                             : what.rfind("per_decade", 0) == 0          ? "--per-decade"
                             : what.rfind("dt", 0) == 0                  ? "--dt"
                             : what.rfind("repeat", 0) == 0              ? "--repeat"
                             : what.rfind("reference_tolerance", 0) == 0 ? "--reference-tol"
                                                                         : "--out";
    throw BadInput{"command line: " + flag + what.substr(what.find(':'))};
  }
}

int BenchCommand::run() {
  const std::optional<scene::Scene> scene = scene_or_say([&] {
    scene::Scene s = scene_.load();
    apply(s);
    return s;
  });
  if (!scene) return kBadInput;
  if (!quiet_) options_.progress = &print_progress;
  return guarded("bench", [&] {
    const scene::BenchResult r = scene::bench(*scene, options_);
    if (!quiet_) std::cout << r.table();
    for (const std::string& w : r.warnings) std::cerr << "lagrangian: bench: warning: " << w << "\n";
    print_outputs(r.plot_note, r.files, quiet_);
    return kOk;
  });
}

}  // namespace lagrangian::cli
