// Work-precision benches of a scene: runs per stepper and tolerance, their
// error against a closed form or a reference run, the medians of their wall
// times, and the table, JSON and diagrams (see include/lagrangian/scene/bench.hpp).

#include "lagrangian/scene/bench.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

#include "lagrangian/integrate/detail/gauss_radau.hpp"
#include "lagrangian/detail/text_output.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/scene/plots.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/scene/run.hpp"
#include "bench_output.hpp"

namespace lagrangian::scene {
namespace {

namespace fs = std::filesystem;
using detail::bench::fmt;
using detail::bench::load_average;
using detail::bench::read_first_line_with;
using detail::bench::machine_description;
using detail::bench::remove_outputs;
using detail::bench::csv_text;
using detail::bench::json_text;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
/// The reference run's stepper where there is neither a closed form nor a
/// shipped reference: the most accurate the project has (docs/accuracy.md,
/// "Gauss–Radau to round-off"), at its tightest tolerance.
constexpr Method kReferenceMethod = Method::gauss_radau15;
const std::string kReferenceName{to_string(kReferenceMethod)};
constexpr double kReferenceTightest = lagrangian::detail::kGaussRadauSmallestTolerance;

/// bench/reference/double_pendulum.txt: the chaotic double pendulum of
/// bench/scenes/double_pendulum_chaotic.toml (m1 = m2 = l1 = l2 = 1,
/// g = 9.81, θ1 = θ2 = 2 rad at rest from t = 0) at t = 5 s and 20 s,
/// computed in mpmath at 60 and 70 digits (the two agree to 1e-37), rounded
/// to double here. tests/test_bench.cpp checks these against the file.
struct ShippedReference {
  double t_end;
  std::array<double, 2> q, qd;
};
constexpr std::array<ShippedReference, 2> kDoublePendulumReference{
    ShippedReference{5.0,
                     {-1.410706688941584255089104615020398236118, -4.041716878877189687566077358790925909559},
                     {-1.984147306034064825616346511085029318764, -5.429525625408064226171414122363918190494}},
    ShippedReference{20.0,
                     {0.1331110409533288179392626946627098523853, -30.15572941228644871906116174598442574834},
                     {3.892915415262310090929197793596436874494, 4.799273316583681084173939753666041202325}}};
/// loose, …, tight: `per_decade` values per decade, each rounded to three
/// significant digits (1e-3, 3.16e-4, 1e-4 … for two per decade).
std::vector<double> grid(double loose, double tight, int per_decade) {
  const double decades = std::log10(loose / tight);
  const int count = std::max(0, static_cast<int>(std::lround(decades * per_decade)));
  std::vector<double> out;
  for (int k = 0; k <= count; ++k) {
    const double v = count == 0 ? loose : loose * std::pow(tight / loose, static_cast<double>(k) / count);
    out.push_back(std::stod(fmt(v, "%.3g")));
  }
  return out;
}

/// The shipped reference of the scene, when the scene is exactly the one it
/// was computed for: the built-in double_pendulum with every parameter at
/// m1 = m2 = l1 = l2 = 1, g = 9.81 (defaults and overrides alike), q(0) =
/// (2, 2) rad, q̇(0) = 0, t0 = 0, t_end 5 s or 20 s, nothing else in the
/// scene. Anything else (another parameter, a body, an effect) gets nullptr.
const ShippedReference* shipped_reference(const Scene& s) {
  if (!s.model || s.model->name != "double_pendulum" || !s.bodies.empty() || s.gas || !s.declared().empty())
    return nullptr;
  if (s.model->q != std::vector<double>{2.0, 2.0} || s.model->qd != std::vector<double>{0.0, 0.0}) return nullptr;
  if (s.run.t0 != 0.0) return nullptr;
  const ModelInfo* info = find_model("double_pendulum");
  if (!info) return nullptr;
  const std::map<std::string, double> want{{"m1", 1.0}, {"m2", 1.0}, {"l1", 1.0}, {"l2", 1.0}, {"g", 9.81}};
  if (info->parameters.size() != want.size()) return nullptr;
  for (const ParameterInfo& p : info->parameters) {
    const auto given = s.model->parameters.find(p.name);
    const double value = given != s.model->parameters.end() ? given->second : p.default_value;
    const auto w = want.find(p.name);
    if (w == want.end() || value != w->second) return nullptr;
  }
  for (const auto& [name, value] : s.model->parameters)
    if (!want.count(name)) return nullptr;
  for (const ShippedReference& r : kDoublePendulumReference)
    if (s.run.t_end == r.t_end) return &r;
  return nullptr;
}

/// Half an ulp of the largest |x_i|: the rounding of a value good to many
/// more digits than a double holds.
double half_ulp_max(const std::array<double, 2>& x) {
  double e = 0;
  for (double v : x) e = std::max(e, 0.5 * (std::nextafter(std::abs(v), kInf) - std::abs(v)));
  return e;
}

/// The scene set up for one bench run: method, tolerances, step, samples at
/// the ends only, no outputs, the ODE engine for particle scenes.
Scene configured(const Scene& scene, Method method, double rtol, double atol, double dt) {
  Scene s = scene;
  s.run.method = method;
  s.run.rtol = rtol;
  s.run.atol = atol;
  s.run.dt = dt;
  s.run.output_interval = s.run.t_end - s.run.t0;
  if (!s.model) s.run.engine = "ode";
  s.output.plots = false;
  s.output.trajectory = false;
  return s;
}

RunResult run_quiet(const Scene& s) {
  RunControls controls;
  controls.write_outputs = false;
  controls.progress = false;
  return run(s, controls);
}

double state_difference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.empty()) return kNaN;
  double e = 0;
  for (std::size_t i = 0; i < a.size(); ++i) e = std::max(e, std::abs(a[i] - b[i]));
  return e;
}

double momentum_drift(const RunReport& r) {
  double d = kNaN;
  for (const MomentumDrift& m : r.conserved_momenta) d = std::isnan(d) ? m.max_abs_drift : std::max(d, m.max_abs_drift);
  // The drifts of the components of P and L the system conserves (none
  // when it conserves none).
  auto any = [](const std::array<bool, 3>& f) { return f[0] || f[1] || f[2]; };
  if (r.has_particles && any(r.linear_momentum_conserved))
    d = std::isnan(d) ? r.linear_momentum_drift_max : std::max(d, r.linear_momentum_drift_max);
  if (r.has_particles && any(r.angular_momentum_conserved))
    d = std::isnan(d) ? r.angular_momentum_drift_max : std::max(d, r.angular_momentum_drift_max);
  return d;
}

}  // namespace

std::pair<double, double> parse_range(const std::string& option, const std::string& text) {
  const auto colon = text.find(':');
  auto fail = [&](const std::string& why) -> std::pair<double, double> {
    throw OptionError(option + ": " + why + ", got '" + text + "'");
  };
  if (colon == std::string::npos) return fail("expected LOOSE:TIGHT, e.g. 1e-3:1e-13");
  auto parse = [&](const std::string& part) {
    std::size_t used = 0;
    double v = kNaN;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (part.empty() || used != part.size()) fail("'" + part + "' is not a number");
    if (!std::isfinite(v) || !(v > 0)) fail("both ends must be positive finite numbers");
    return v;
  };
  const double a = parse(text.substr(0, colon)), b = parse(text.substr(colon + 1));
  if (!(a > b)) return fail("the first value must be the larger (loosest first)");
  return {a, b};
}

void BenchOptions::validate() const {
  if (methods.empty()) throw OptionError("methods: none given");
  for (const Method m : methods) {
    if (static_cast<std::size_t>(m) >= method_table().size())
      throw OptionError("methods: " + std::to_string(static_cast<int>(m)) + " is not a Method");
    if (std::count(methods.begin(), methods.end(), m) > 1)
      throw OptionError("methods: '" + std::string(to_string(m)) + "' given twice");
  }
  if (!(tolerance_tight >= min_rtol) || !(tolerance_loose > tolerance_tight) || !(tolerance_loose < 1) ||
      !std::isfinite(tolerance_loose))
    throw OptionError("tolerances: need 1 > loose > tight >= 1e-15, got " + fmt(tolerance_loose) + ":" +
                      fmt(tolerance_tight));
  if (per_decade < 1 || per_decade > 10) throw OptionError("per_decade: must be in [1, 10], got " + std::to_string(per_decade));
  if (dt_large != 0 || dt_small != 0)
    if (!(dt_small > 0) || !(dt_large > dt_small) || !std::isfinite(dt_large))
      throw OptionError("dt: need large > small > 0, got " + fmt(dt_large) + ":" + fmt(dt_small));
  if (repeat < 1 || repeat > 1000) throw OptionError("repeat: must be in [1, 1000], got " + std::to_string(repeat));
  if (!(reference_tolerance >= 1e-16) || !(reference_tolerance < 1e-6))
    throw OptionError("reference_tolerance: must be in [1e-16, 1e-6), got " + fmt(reference_tolerance));
  if (out_dir.empty()) throw OptionError("out_dir: empty");
}

std::string BenchResult::table() const {
  std::ostringstream os;
  os << "scene " << scene << " — engine " << engine << "\n"
     << "error: " << error_measure << "\n";
  if (!reference.empty()) os << "reference: " << reference << "\n";
  char line[256];
  std::snprintf(line, sizeof line, "%-15s %9s %9s %12s %12s %10s %12s %10s %10s %10s\n", "method", "rtol", "dt",
                "error", "time (ms)", "steps", "RHS", "E drift", "p drift", "residual");
  os << line;
  for (const BenchPoint& p : points) {
    if (!p.ok()) {
      std::snprintf(line, sizeof line, "%-15s %9s %9s  %s\n", p.method.c_str(),
                    p.adaptive ? fmt(p.rtol, "%.3g").c_str() : "-", p.adaptive ? "-" : fmt(p.dt, "%.3g").c_str(),
                    p.status.c_str());
      os << line;
      continue;
    }
    auto opt = [](double v) { return std::isfinite(v) ? fmt(v, "%.2e") : std::string("-"); };
    std::snprintf(line, sizeof line, "%-15s %9s %9s %12s %12s %10llu %12llu %10s %10s %10s%s\n", p.method.c_str(),
                  p.adaptive ? fmt(p.rtol, "%.3g").c_str() : "-", p.adaptive ? "-" : fmt(p.dt, "%.3g").c_str(),
                  fmt(p.error, "%.3e").c_str(), fmt(1e3 * p.wall_time_s, "%.4g").c_str(),
                  static_cast<unsigned long long>(p.steps), static_cast<unsigned long long>(p.rhs_evaluations),
                  opt(p.energy_drift).c_str(), opt(p.momentum_drift).c_str(), opt(p.constraint_residual).c_str(),
                  p.is_reference ? "  (the reference run: its estimated error)"
                  : p.resolved   ? ""
                                 : "  (below the reference's accuracy)");
    os << line;
  }
  os << "time: median of the repeats; machine: " << machine << "\n";
  return os.str();
}

namespace {

/// Progress lines and warnings of one bench.
struct BenchLog {
  const BenchOptions& options;
  BenchResult& result;
  void say(const std::string& line) const {
    if (options.progress) options.progress(line);
  }
  void warn(const std::string& line) const { result.warnings.push_back(line); }
};

/// The reference, the most accurate the project has: the model's closed
/// form; else the shipped multiple-precision reference when the scene is
/// exactly the one it was computed for; else gauss_radau15 at its tightest
/// tolerance (rtol = atol = max(reference_tolerance, 1e-11); retried 10×
/// looser, up to 1e-9, if it fails), whose error is estimated by a second
/// gauss_radau15 run at 10× its tolerance. Fills the result's reference
/// fields; returns the tolerance of the reference runs.
double find_reference(const Scene& scene, const BenchOptions& options, BenchResult& result, const BenchLog& log) {
  double tol = std::max(options.reference_tolerance, kReferenceTightest);
  if (options.reference_tolerance < kReferenceTightest * (1 - 1e-9))
    log.warn("reference tolerance " + fmt(options.reference_tolerance, "%.3g") + " is below " + kReferenceName +
             "'s tightest tolerance " + fmt(kReferenceTightest, "%.0e") + " (its error measure |b6|/|q''| is round-off "
             "there): a reference run uses " + fmt(kReferenceTightest, "%.0e"));
  // The closed form, if any, comes with the report of any run: one cheap run
  // tells (its result is the reference state only in the third case).
  RunResult reference;
  for (;;) {
    try {
      reference = run_quiet(configured(scene, kReferenceMethod, tol, tol, scene.run.dt));
      break;
    } catch (const SimulationError&) {
      if (tol * 10 > 1e-9 * (1 + 1e-9)) throw;
      tol *= 10;
    }
  }
  result.closed_form = reference.report.has_reference;
  const ShippedReference* shipped = result.closed_form ? nullptr : shipped_reference(scene);
  const std::string units = scene.model ? "the model's coordinates" : "m, positions";
  if (result.closed_form) {
    result.reference_kind = "closed_form";
    result.error_measure =
        "max_i |q_i(t_end) - q_i(t_end) of the closed form| (true error, units of q: " +
        std::string(scene.model ? "the model's coordinates" : "m") + ")";
  } else if (shipped) {
    result.reference_kind = "shipped";
    result.reference_q.assign(shipped->q.begin(), shipped->q.end());
    result.reference_qd.assign(shipped->qd.begin(), shipped->qd.end());
    // The 60- and 70-digit runs agree to 1e-37: the reference's error as a
    // double is its rounding.
    result.reference_accuracy = half_ulp_max(shipped->q);
    result.reference_time_s = kNaN;
    result.error_measure = "max_i |q_i(t_end) - q_i,ref(t_end)| against the shipped reference (units of q: " +
                           units + ")";
    result.reference = "bench/reference/double_pendulum.txt at t = " + fmt(shipped->t_end, "%g") +
                       " s (Gragg-Bulirsch-Stoer in mpmath at 60 and 70 digits, which agree to 1e-37); its error "
                       "as doubles is their rounding, at most " +
                       fmt(result.reference_accuracy, "%.1e");
    log.say("reference: " + result.reference);
  } else {
    result.reference_kind = "run";
    result.reference_method = kReferenceName;
    result.reference_tolerance = tol;
    log.say("reference: " + kReferenceName + " at rtol = atol = " + fmt(tol, "%.0e"));
    result.reference_time_s = reference.report.wall_time_s;
    result.reference_q = reference.q_final;
    result.reference_qd = reference.qd_final;
    const RunResult check = run_quiet(configured(scene, kReferenceMethod, 10 * tol, 10 * tol, scene.run.dt));
    result.reference_accuracy = state_difference(reference.q_final, check.q_final);
    if (!std::isfinite(result.reference_accuracy))
      throw SimulationError("bench: the reference runs ended in states of different sizes", scene.run.t_end);
    result.error_measure = "max_i |q_i(t_end) - q_i,ref(t_end)| against a reference run (units of q: " + units + ")";
    result.reference = kReferenceName + " at rtol = atol = " + fmt(tol, "%.0e") + " (" +
                       std::to_string(reference.report.steps) + " steps; the tightest it runs at); its error is "
                       "estimated as " + fmt(result.reference_accuracy, "%.1e") +
                       " = max_i |q_i - q_i,ref| of a second " + kReferenceName + " run at " + fmt(10 * tol, "%.0e") +
                       " (at these tolerances both are round-off, so this is the size of the reference's error, "
                       "not a bound)";
  }
  return tol;
}

/// One configuration of the bench: a stepper at a tolerance (adaptive) or a
/// step size (fixed step).
struct Config {
  Method method;
  double rtol, atol, dt;
};

/// Every configuration: each adaptive stepper at every tolerance of the
/// grid, each fixed-step one at every step size.
std::vector<Config> configurations(const Scene& scene, const BenchOptions& options, const BenchLog& log) {
  const double span = scene.run.t_end - scene.run.t0;
  std::vector<Config> configs;
  const std::vector<double> tols = grid(options.tolerance_loose, options.tolerance_tight, options.per_decade);
  const double dt_large = options.dt_large > 0 ? options.dt_large : span / 100;
  const double dt_small = options.dt_small > 0 ? options.dt_small : span / 1e5;
  const std::vector<double> dts = grid(dt_large, dt_small, options.per_decade);
  for (const Method m : options.methods) {
    if (method_info(m).adaptive) {
      // gauss_radau15 runs tolerances below its smallest at that one (its
      // error measure is round-off there): those points would repeat it, so
      // they are dropped, and the user is told which.
      const double smallest = lagrangian::detail::kGaussRadauSmallestTolerance;
      std::string dropped;
      for (double t : tols) {
        if (m != Method::gauss_radau15 || t >= smallest * (1 - 1e-9)) configs.push_back({m, t, t, scene.run.dt});
        else dropped += (dropped.empty() ? "" : ", ") + fmt(t, "%.3g");
      }
      if (!dropped.empty())
        log.warn(std::string(to_string(m)) + ": tolerances " + dropped + " dropped: below " + fmt(smallest, "%.0e") +
                 " its error measure |b6|/|q''| is round-off and it runs at " + fmt(smallest, "%.0e") +
                 ", so those rows would repeat the " + fmt(smallest, "%.0e") + " row");
    } else {
      for (double h : dts) configs.push_back({m, 0, 0, h});
    }
  }
  return configs;
}

/// The measures of the first run of a configuration (runs are
/// deterministic): steps, evaluations, the error against the reference and
/// the drifts.
void measure(const RunResult& r, const BenchResult& result, BenchPoint& p) {
  const RunReport& rep = r.report;
  p.steps = rep.steps;
  p.rejected_steps = rep.rejected_steps;
  p.rhs_evaluations = rep.rhs_evaluations;
  p.t_final = rep.t_final;
  p.error = result.closed_form ? rep.reference_error_final : state_difference(r.q_final, result.reference_q);
  // The reference run itself (deterministic: the same state): its error is
  // the reference's estimate, not a measurement.
  if (p.is_reference) p.error = result.reference_accuracy;
  p.energy_drift = rep.conservative ? rep.energy_drift_max : kNaN;
  p.momentum_drift = momentum_drift(rep);
  p.constraint_residual = rep.constrained ? rep.constraints.max_position_residual : kNaN;
  p.resolved = result.closed_form || (!p.is_reference && p.error > 2 * result.reference_accuracy);
  if (!std::isfinite(p.error)) throw SimulationError("the error is not finite", rep.t_final);
}

/// Runs every configuration `repeat` times and fills result.points: passes
/// over all configurations (rather than the repeats of one configuration
/// back to back), so that a burst of load from other programs falls on many
/// configurations a little instead of on a few entirely; the median time per
/// configuration is kept. The first pass also measures the accuracy.
/// Returns how many configurations succeeded.
int time_configurations(const Scene& scene, const std::vector<Config>& configs, const BenchOptions& options,
                        BenchResult& result, const BenchLog& log) {
  std::vector<BenchPoint> points(configs.size());
  std::vector<std::vector<double>> times(configs.size());
  std::vector<Scene> scenes;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const Config& c = configs[i];
    BenchPoint& p = points[i];
    p.method = to_string(c.method);
    p.adaptive = method_info(c.method).adaptive;
    p.rtol = c.rtol;
    p.atol = c.atol;
    p.dt = c.dt;
    p.is_reference = result.reference_kind == "run" && p.method == result.reference_method &&
                     c.rtol == result.reference_tolerance && c.atol == result.reference_tolerance &&
                     c.dt == scene.run.dt;
    scenes.push_back(configured(scene, c.method, p.adaptive ? c.rtol : scene.run.rtol,
                                p.adaptive ? c.atol : scene.run.atol, c.dt));
  }
  for (int pass = 0; pass < options.repeat; ++pass) {
    for (std::size_t i = 0; i < configs.size(); ++i) {
      BenchPoint& p = points[i];
      if (!p.ok()) continue;
      try {
        const RunResult r = run_quiet(scenes[i]);
        times[i].push_back(r.report.wall_time_s);
        if (pass == 0) measure(r, result, p);
      } catch (const SimulationError& e) {
        p.status = std::string("failed: ") + e.what();
      }
      if (pass == 0)
        log.say(p.method + (p.adaptive ? " rtol " + fmt(p.rtol, "%.3g") : " dt " + fmt(p.dt, "%.3g")) + ": " +
                (p.ok() ? "error " + fmt(p.error, "%.2e") + ", " + fmt(1e3 * times[i].back(), "%.4g") + " ms"
                        : p.status));
    }
    if (pass > 0) log.say("timing pass " + std::to_string(pass + 1) + " of " + std::to_string(options.repeat) + " done");
  }
  int succeeded = 0;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    BenchPoint& p = points[i];
    std::vector<double>& t = times[i];
    p.repeats = static_cast<int>(t.size());
    if (p.ok()) {
      std::sort(t.begin(), t.end());
      const std::size_t n = t.size();
      p.wall_time_s = n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
      p.wall_time_min_s = t.front();
      p.wall_time_max_s = t.back();
      ++succeeded;
    }
    result.points.push_back(std::move(p));
  }
  return succeeded;
}

/// The work-precision diagrams of the result (reference runs at `tol`).
void plot_bench(const Scene& scene, const BenchOptions& options, double tol, BenchResult& result) {
  WorkPrecisionPlotSpec plot;
  plot.title = scene.name;
  plot.error_label = result.closed_form ? "error against the closed form at t_end"
                                        : "error against the reference run at t_end";
  plot.note = (result.closed_form ? std::string("error: max_i |q_i - q_i,exact| at t = ")
                                  : std::string("error: max_i |q_i - q_i,ref| at t = ")) +
              fmt(scene.run.t_end, "%.6g") + " s" +
              (result.reference_kind == "run"
                   ? "; reference: " + kReferenceName + " at " + fmt(tol, "%.0e")
                   : result.reference_kind == "shipped" ? "; reference: bench/reference/double_pendulum.txt (mpmath)"
                                                        : "") +
              "; time: median of " + std::to_string(options.repeat) + "; " +
              read_first_line_with("/proc/cpuinfo", "model name");
  plot.reference_accuracy = result.reference_accuracy;
  plot.out_dir = options.out_dir;
  plot.png = options.png;
  plot.svg = options.svg;
  for (const Method m : options.methods) {
    WorkPrecisionSeries sr;
    sr.name = to_string(m);
    for (const BenchPoint& p : result.points) {
      if (p.method != sr.name || !p.ok()) continue;
      sr.wall_time_s.push_back(p.wall_time_s);
      sr.rhs_evaluations.push_back(static_cast<double>(p.rhs_evaluations));
      sr.error.push_back(p.error);
      sr.energy_drift.push_back(p.energy_drift);
    }
    plot.series.push_back(std::move(sr));
  }
  collect_plots([&] { return make_work_precision_plots(plot); }, result.files, result.plot_note);
}

}  // namespace

BenchResult bench(const Scene& input, const BenchOptions& options) {
  options.validate();
  input.validate();
  Scene scene = input;
  scene.expand_gas();
  const std::string load_before = load_average();

  BenchResult result;
  result.scene = scene.name;
  result.engine = scene.model ? "model" : "ode";
  const fs::path dir = options.out_dir;
  {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
      throw OptionError("out: cannot create directory '" + options.out_dir + "'" + (ec ? ": " + ec.message() : ""));
  }
  remove_outputs(dir);

  const BenchLog log{options, result};
  const double tol = find_reference(scene, options, result, log);
  const int succeeded = time_configurations(scene, configurations(scene, options, log), options, result, log);
  result.machine = machine_description(load_before);
  if (succeeded == 0) throw SimulationError("bench: every run failed (see the messages above)", scene.run.t0);

  // Outputs: the table, the JSON, then the diagrams.
  try {
    const std::string csv = (dir / "work_precision.csv").string();
    lagrangian::detail::write_text_file(csv, csv_text(scene, result), "work-precision table");
    result.files.push_back(csv);
    const std::string json = (dir / "bench.json").string();
    lagrangian::detail::write_text_file(json, json_text(scene, options, result), "bench report");
    result.files.push_back(json);
  } catch (...) {
    remove_outputs(dir);
    throw;
  }
  if (options.plots) plot_bench(scene, options, tol, result);
  return result;
}

}  // namespace lagrangian::scene
