#pragma once
/// \file sweep.hpp
/// Ensembles and parameter sweeps of a scene: many runs, one table.
///
/// A sweep takes a scene file and changes values in it before each run. Any
/// numeric key of the scene file can be varied, under the name it has in the
/// file (`model.parameters.e`, `bodies[0].velocity[2]`, `contacts.planes[0].restitution`,
/// `run.rtol`): the parsed TOML document is changed and read again with the
/// same reader, so a misspelt key is refused with the scene files' message
/// ("unknown key 'rtoll'; did you mean 'rtol'?"). Besides scene keys a sweep
/// may vary plain *variables* (a name without `.` or `[`) and set scene keys
/// from them with an expression (`--set 'model.qd[0]=20*cos(alpha*pi/180)'`).
///
/// Points:
///  - a grid: every `--vary key=start:stop:count[:log]` is a linear (or
///    logarithmic) grid of `count` values from start to stop inclusive; the
///    points are the Cartesian product, the first `--vary` varying slowest;
///  - Monte Carlo: `--monte-carlo N --seed S` with `--vary key=uniform:a:b`
///    or `key=normal:mu:sigma`; point i draws its values from a
///    std::mt19937_64 seeded with point_seed(S, i) (splitmix64 of S and i),
///    uniforms from the engine's 53 high bits, normals by Box–Muller
///    (two uniforms each), in the order of the `--vary` options. The values
///    of point i therefore depend on (S, i) alone — not on the thread or
///    rank that runs it, nor on the standard library.
///
/// Every point is an independent scene::run() without output files. The
/// results are gathered by point index, whatever order they finish in, into
/// `sweep.csv` (written through `sweep.csv.partial`): one row per point with
/// the varied values, the set values, the status (`ok` or `failed: <why>`:
/// a failed run does not stop the sweep) and the chosen output columns
/// (SweepOptions::outputs), doubles with 17 significant digits. Plots: a
/// curve per plotted column for a 1-D grid, a heat map for a 2-D grid.
///
/// Parallel: `threads` workers pull point indices from an atomic counter,
/// each parsing its own copy of the document; with `ranks` > 1 (MPI, see the
/// `lagrangian-mpi` program) rank r runs the points i with i mod ranks = r
/// and `gather` brings the results to rank 0, which alone writes files. The
/// CSV is the same byte for byte for any number of threads and ranks (the
/// `wall` column, off by default, excepted).

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "lagrangian/errors.hpp"

namespace lagrangian::scene {

/// One `--vary`: a scene key or a variable, and its values.
struct VarySpec {
  enum class Kind { linear, log, uniform, normal };
  std::string key;          ///< scene key ("model.parameters.e") or variable name ("alpha")
  Kind kind = Kind::linear;
  double a = 0, b = 0;      ///< grid: start, stop; uniform: low, high; normal: mean, standard deviation
  int count = 1;            ///< grid points (grids only), ≥ 1
  bool variable() const;    ///< a plain name (no '.' nor '['): not a scene key
  bool grid() const { return kind == Kind::linear || kind == Kind::log; }
  /// The grid's k-th value (k < count): linear a + k (b − a)/(count − 1), log
  /// a (b/a)^(k/(count − 1)); a alone when count = 1.
  double grid_value(int k) const;
};

/// Parses "key=start:stop:count", "key=start:stop:count:log",
/// "key=uniform:a:b" or "key=normal:mu:sigma". Throws OptionError
/// "--vary: …" naming the text. start > stop is allowed (a descending grid);
/// log grids need start and stop > 0; uniform needs a < b; normal sigma > 0.
VarySpec parse_vary(const std::string& text);

/// One `--set key=expression`: a scene key computed from the variables.
struct SetSpec {
  std::string key;
  std::string expression;
};
/// Parses "key=expression"; throws OptionError "--set: …".
SetSpec parse_set(const std::string& text);

/// One `--first-time name=expression`: the first time the expression of the
/// coordinates (names as in the trajectory: `theta1`, `theta1_dot`, `t`)
/// becomes positive, from the run's samples (linear interpolation between
/// the two samples around the crossing; resolution: run.output_interval).
struct FirstTimeSpec {
  std::string name;
  std::string expression;
};
/// Parses "name=expression"; throws OptionError "--first-time: …".
FirstTimeSpec parse_first_time(const std::string& text);

/// A compiled arithmetic expression: numbers, variables, + − * / ^, unary
/// minus, parentheses, pi, and the functions sin cos tan asin acos atan
/// sqrt exp log abs (one argument), atan2 min max pow (two arguments).
class Expression {
 public:
  /// Compiles `text` against the variable names (their order gives the
  /// slots evaluate() reads). Throws OptionError "<what>: …" naming the
  /// expression and the problem (unknown name, syntax).
  Expression(const std::string& text, const std::vector<std::string>& variables, const std::string& what);
  double evaluate(const double* values) const;
  /// True when the expression reads the variable in slot `k`.
  bool uses(std::size_t k) const;

 private:
  struct Op {
    int code;
    double value;
  };
  std::vector<Op> ops_;
};

/// What a sweep runs and writes.
struct SweepOptions {
  std::vector<VarySpec> vary;
  std::vector<SetSpec> set;
  std::vector<FirstTimeSpec> first_times;
  std::uint64_t monte_carlo = 0;  ///< number of Monte Carlo points; 0: a grid
  std::uint64_t seed = 1;         ///< Monte Carlo seed
  int threads = 0;                ///< worker threads; 0: std::thread::hardware_concurrency()
  /// Column groups after the varied and set values and the status:
  /// "final" (t_final, q_<coordinate>, qd_<coordinate>), "events"
  /// (n_, first_, last_ per event kind — impact, rest, release, stop — and
  /// per watched event name), "energy" (energy_drift_max, energy_drift_final:
  /// of the energy scale; energy_drift_relative_to_initial: |h − h0|/|h0| at
  /// the end; impact_energy_loss), "error" (reference_error_final: against the
  /// model's closed form, empty without one), "cost" (steps,
  /// rejected_steps, rhs_evaluations), "wall" (wall_time_s; varies run to
  /// run, so not a default), "chaos" (lyapunov_max, megno: see SweepRecord;
  /// a second run of each point with one tangent vector, about 16 times
  /// the cost of the first for the double pendulum, so not a default either).
  std::vector<std::string> outputs{"final", "events", "energy", "error", "cost"};
  std::vector<std::string> plot_columns;  ///< columns to plot; empty: a default choice (docs/sweeps.md)
  std::string out_dir = "out/sweep";
  bool plots = true;
  bool png = true, svg = false;
  bool progress = false;          ///< progress bar with ETA on stderr (a terminal only)
  int rank = 0, ranks = 1;        ///< this process's rank and the number of ranks (MPI)
  /// ranks > 1: called once by every rank with its serialized results;
  /// returns, on rank 0, every rank's text concatenated (anything elsewhere).
  std::function<std::string(const std::string&)> gather;
  /// When not null and set (by a SIGINT handler, say): no further run
  /// starts, the runs under way finish, the sweep removes its working files
  /// and throws SweepInterrupted; nothing that looks like a table is left.
  const std::atomic<bool>* cancel = nullptr;

  /// Throws OptionError naming the option and the value when invalid.
  void validate() const;
  /// Names of the output groups (for messages).
  static std::vector<std::string> output_groups();
  /// True when `group` is one of `outputs`.
  bool wants(const std::string& group) const;
};

/// A sweep stopped through SweepOptions::cancel before all its runs were
/// done; done_runs of total_runs had finished on this rank.
class SweepInterrupted : public Error {
 public:
  SweepInterrupted(std::uint64_t done, std::uint64_t total)
      : Error("sweep interrupted after " + std::to_string(done) + " of " + std::to_string(total) +
              " runs; no table written"),
        done_runs(done),
        total_runs(total) {}
  std::uint64_t done_runs, total_runs;
};

/// The outcome of one run.
struct SweepRecord {
  std::string status = "ok";     ///< "ok" or "failed: <why>"
  std::vector<double> values;    ///< varied values, then set values (the inputs of the point)
  std::vector<std::string> coordinates;
  std::vector<double> q, qd;     ///< final state
  double t_final = 0;
  double energy_drift_max = 0, energy_drift_final = 0, impact_energy_loss = 0;
  double energy_drift_relative_to_initial = 0;  ///< RunReport::energy_drift_relative_to_initial(); NaN when h0 = 0
  bool has_reference = false;
  double reference_error_final = 0;
  std::uint64_t steps = 0, rejected_steps = 0, rhs_evaluations = 0;
  double wall_time_s = 0;
  struct EventGroup {
    std::uint64_t count = 0;
    double first = 0, last = 0;
  };
  std::map<std::string, EventGroup> events;  ///< by kind (impact, rest, release, stop) or watched event name
  std::vector<double> first_times;           ///< one per FirstTimeSpec; NaN: never
  /// The "chaos" group (NaN when not asked): the largest Lyapunov exponent
  /// λ1 (1/s) and MEGNO's time mean ⟨Y⟩ (dimensionless) of the point's model
  /// from its initial state over [t0, t_end], one tangent vector integrated
  /// beside the state by scene::lyapunov() (analysis.hpp; docs/analysis.md).
  /// ⟨Y⟩ → 0 for an isochronous orbit, → 2 for a regular one, and grows as
  /// λ1 t / 2 on a chaotic one. Watched events do not stop this run.
  double lyapunov_max = std::numeric_limits<double>::quiet_NaN();
  double megno = std::numeric_limits<double>::quiet_NaN();
  bool ok() const { return status == "ok"; }
};

/// What sweep() did.
struct SweepResult {
  std::uint64_t points = 0, failed = 0;
  int threads = 1, ranks = 1;
  double wall_time_s = 0;               ///< the whole sweep, with writing the table and the plots (s)
  /// From the start to the last result gathered: loading, the runs and (MPI)
  /// the gather, without the table and the plots (s). Runs per second are
  /// points / run_time_s.
  double run_time_s = 0;
  std::vector<std::string> header;      ///< the CSV's column names, without the units its header adds (rank 0)
  std::vector<SweepRecord> records;     ///< by point index (rank 0; empty on other ranks)
  std::vector<std::string> files;       ///< files written (rank 0)
  std::string plot_note;                ///< why plots were skipped, if they were
  std::vector<std::string> warnings;    ///< sweep_warnings() of the options
};

/// What about a sweep's options deserves a warning though it is not an
/// error: a varied variable that no --set expression reads, so that every
/// point runs the same scene. Throws OptionError as the sweep would for an
/// expression that does not compile.
std::vector<std::string> sweep_warnings(const SweepOptions& options);

/// Runs the sweep of the scene file `scene_path` and (rank 0) writes
/// `<out_dir>/sweep.csv` and the plots. Throws SceneError / OptionError for
/// bad input (unreadable scene, unknown key, malformed option) before any
/// run; runs that fail are rows with their message, counted in
/// SweepResult::failed.
SweepResult sweep(const std::string& scene_path, const SweepOptions& options);

/// The seed of point i's engine: splitmix64 applied to seed + (i + 1)·φ64,
/// φ64 = 0x9E3779B97F4A7C15.
std::uint64_t point_seed(std::uint64_t seed, std::uint64_t i);

/// The values of point `index` of a sweep (varied keys in order).
std::vector<double> point_values(const SweepOptions& options, std::uint64_t index);

/// Number of points of the sweep (the grid's product, or monte_carlo).
std::uint64_t point_count(const SweepOptions& options);

}  // namespace lagrangian::scene
