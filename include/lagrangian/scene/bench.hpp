#pragma once
/// \file bench.hpp
/// What accuracy costs in time: work-precision data for a scene.
///
/// bench() runs a scene once per (stepper, tolerance) — fixed-step steppers
/// once per step size — measures its error, times it in `repeat` passes over
/// all configurations and keeps the median (interleaved passes spread a burst
/// of load from other programs over many configurations), and writes the
/// table and the diagrams:
///
///  - `work_precision.csv`: comment lines starting with `#` (the scene, the
///    error measure, the reference, the machine), then the header
///    `method,adaptive,rtol,atol,dt,status,error,wall_time_s,wall_time_min_s,wall_time_max_s,repeats,`
///    `steps,rejected_steps,rhs_evaluations,energy_drift,momentum_drift,constraint_residual,t_final,resolved`
///    and one row per run (see BenchPoint for the columns);
///  - `bench.json`: the same as JSON, with the settings and the reference
///    run's final state (`reference_q`, `reference_qd`);
///  - `work_precision_time`, `work_precision_rhs` and, for conservative
///    systems, `work_precision_energy` (.png and .svg, log–log, one line per
///    stepper) and the gnuplot script `bench.gp` (make_work_precision_plots()).
///
/// **The error** of a run is measured at the end of the run, on the
/// generalized coordinates (built-in models) or on the positions (particle
/// scenes): e = max_i |q_i(t_end) − q_i,ref(t_end)| in the units of q. The
/// reference q_ref is the most accurate the project can make:
///  - the model's closed form when it has one (`reference()`: projectile,
///    projectile with linear drag, Kepler, two bodies, harmonic oscillator,
///    simple pendulum at any amplitude) — the true error;
///  - the shipped multiple-precision reference
///    (bench/reference/double_pendulum.txt, mpmath at 60 and 70 digits) when
///    the scene is exactly the one it was computed for: the built-in
///    double_pendulum with m1 = m2 = l1 = l2 = 1, g = 9.81, q(0) = (2, 2),
///    q̇(0) = 0, t0 = 0, t_end 5 or 20 s and nothing else; its error is its
///    rounding to double (half an ulp);
///  - otherwise a reference run of the same scene with gauss_radau15 at
///    rtol = atol = max(`reference_tolerance`, 1e-11) — its tightest: below
///    1e-11 it runs at 1e-11 — whose error is estimated by comparing it with
///    a second gauss_radau15 run at 10× that tolerance (both are round-off
///    there, so the difference is the size of the reference's error, not a
///    bound). The bench row that repeats the reference run
///    (`is_reference`) gets that estimate as its error.
/// Runs whose error is below twice the reference's estimate are marked
/// unresolved (`resolved` = 0). Warnings (tolerances gauss_radau15 drops
/// because they lie below 1e-11, a `reference_tolerance` it cannot run at)
/// are in BenchResult::warnings, the CSV's `# warning:` lines and bench.json's
/// "warnings".
/// Alongside: the relative energy drift max |E − E₀| / E scale of
/// conservative systems, the largest drift of the conserved momenta (cyclic
/// coordinates; the total linear and angular momentum of particle scenes
/// with internal forces only) and the largest constraint residual ‖g‖∞.
///
/// Each run samples only its start and its end, so the time measured is the
/// integration's (RunReport::wall_time_s). Runs that fail (a non-finite
/// state, a step-size underflow, max_steps) are rows with status `failed: …`
/// and are not drawn; the bench fails only when no run succeeds or the
/// reference fails.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "lagrangian/scene/scene.hpp"

namespace lagrangian::scene {

/// What bench() runs and writes.
struct BenchOptions {
  /// Steppers (method.hpp); adaptive ones run at every tolerance
  /// (gauss_radau15 down to 1e-11, below which it runs at 1e-11),
  /// fixed-step ones (rk4) at every step size.
  std::vector<Method> methods{Method::dopri5,         Method::cash_karp54,   Method::fehlberg78,
                              Method::bulirsch_stoer, Method::gauss_radau15, Method::rk4};
  double tolerance_loose = 1e-3;   ///< loosest rtol (= atol), in (tolerance_tight, 1)
  double tolerance_tight = 1e-13;  ///< tightest rtol (= atol), ≥ 1e-15
  int per_decade = 1;              ///< tolerances (and step sizes) per decade, ≥ 1
  /// Step sizes of fixed-step steppers (s), largest first; 0: from
  /// (t_end − t0)/100 down to (t_end − t0)/10⁵.
  double dt_large = 0, dt_small = 0;
  int repeat = 3;                  ///< timed runs per configuration (median kept), ≥ 1
  /// rtol = atol of the gauss_radau15 reference run (neither closed form nor
  /// shipped reference); below 1e-11 it runs at 1e-11, with a warning.
  double reference_tolerance = 1e-11;
  std::string out_dir = "out/bench";  ///< where the CSV, JSON, script and diagrams go
  bool plots = true;               ///< draw the diagrams (gnuplot; skipped with a note without it)
  bool png = true, svg = true;
  /// Called after each configuration with a line for the user (progress); may be empty.
  void (*progress)(const std::string& line) = nullptr;

  /// Throws OptionError naming the field and the value when invalid.
  void validate() const;
};

/// One configuration's runs.
struct BenchPoint {
  std::string method;          ///< the stepper's name
  bool adaptive = true;
  double rtol = 0, atol = 0;   ///< adaptive steppers
  double dt = 0;               ///< fixed-step steppers: the step (s); adaptive: the first trial step
  std::string status = "ok";   ///< "ok" or "failed: <why>"
  double error = 0;            ///< the error measure at t_final (units of q), see bench.hpp
  double wall_time_s = 0;      ///< median over the repeats (s)
  double wall_time_min_s = 0, wall_time_max_s = 0;
  int repeats = 0;
  std::uint64_t steps = 0, rejected_steps = 0, rhs_evaluations = 0;
  double energy_drift = 0;     ///< max |E − E₀| / E scale; NaN when the system is not conservative
  double momentum_drift = 0;   ///< largest drift of a conserved momentum (SI units); NaN when none is conserved
  double constraint_residual = 0;  ///< max ‖g‖∞ over the run; NaN without constraints
  double t_final = 0;          ///< time the run ended (s)
  bool resolved = true;        ///< error above twice the reference's accuracy (always true with a closed form)
  bool is_reference = false;   ///< this run is the reference run (its error is the reference's estimate)
  bool ok() const { return status == "ok"; }
};

/// What bench() did.
struct BenchResult {
  std::string scene;
  std::string engine;          ///< "model" or "ode"
  bool closed_form = false;    ///< the error is against the model's closed form
  std::string error_measure;   ///< one sentence: what the error is
  /// "closed_form", "shipped" (bench/reference/double_pendulum.txt) or "run"
  std::string reference_kind;
  std::string reference;       ///< how the reference was made and its error estimate (empty with a closed form)
  std::string reference_method;     ///< the reference run's stepper ("run" only)
  double reference_tolerance = 0;   ///< its rtol = atol ("run" only)
  /// Things the user asked for that were not done as asked (dropped
  /// tolerances, a reference tolerance below 1e-11): also in the CSV and JSON;
  /// `lagrangian bench` prints them on stderr.
  std::vector<std::string> warnings;
  double reference_accuracy = 0;  ///< estimated error of the reference (0 with a closed form)
  double reference_time_s = 0;    ///< wall time of the reference run (s); NaN for the shipped reference
  /// The reference run's final state (empty with a closed form): q and q̇ at
  /// t_end, so that other programs can measure their error the same way.
  std::vector<double> reference_q, reference_qd;
  std::string machine;         ///< CPU, cores, compiler, load average, date (UTC)
  std::vector<BenchPoint> points;
  std::vector<std::string> files;  ///< files written
  std::string plot_note;       ///< why the diagrams were skipped, if they were
  /// The table as text (what `lagrangian bench` prints).
  std::string table() const;
};

/// Runs the work-precision bench of `scene` (validated first) and writes the
/// files listed in this header's documentation into options.out_dir
/// (through partial files; on failure nothing that looks complete is left).
/// Throws SceneError / OptionError for invalid input and SimulationError
/// when the reference run or every run fails.
BenchResult bench(const Scene& scene, const BenchOptions& options);

/// Parses a range "A:B" of positive numbers with A > B (loosest first) for
/// the option named `option`; throws OptionError "<option>: …" naming the
/// value otherwise.
std::pair<double, double> parse_range(const std::string& option, const std::string& text);

}  // namespace lagrangian::scene
