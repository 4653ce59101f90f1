#pragma once
/// \file report.hpp
/// Options of a run and the report of what it cost and how accurate it was.

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "lagrangian/integrate/method.hpp"

namespace lagrangian {

/// How constraint drift is controlled during a run of a constrained model.
enum class Stabilization {
  none,        ///< the index-1 equations as they are; the residual drifts with time
  baumgarte,   ///< C q̈ = −γ − 2ω ġ − ω² g (holonomic rows), −γ − ω φ (Pfaffian rows)
  projection,  ///< after every accepted step: q by Gauss–Newton onto g = 0, q̇ by M-weighted projection
};

/// Name of a stabilization ("none", "baumgarte", "projection").
const char* to_string(Stabilization s);

/// What a run should do. Times in s.
struct RunReport;
/// The sanity monitors, run by every engine at the end of every run: sets
/// report.drift_bound = max(1e-2, 100 rtol) and judges each monitor that
/// applies to the run (report.monitors) by a dimensionless figure:
///   energy               max |h − h0| / energy_scale (report.conservative only;
///                        impacts' changes taken out);
///   momentum p_<q_i>     max |p_i − p_i(t0)| · max |q̇_i| / energy_scale, for each
///                        cyclic coordinate (the energy the error amounts to);
///   linear momentum      max drift of the conserved components of P / momentum_scale;
///   angular momentum     the same for L / angular_momentum_scale;
///   constraint residual  max ‖g(q, t)‖∞ / (1 + coordinate_scale) (constrained models);
///   closed-form error    max ‖q − q_ref‖∞ / (1 + coordinate_scale) (models with reference()).
/// A figure beyond the bound sets report.drift_exceeded and a warning naming
/// the monitor, its figure, the bound and what to do. No run at that
/// tolerance can excuse such a drift: a local error of rtol per step
/// accumulates to 100 rtol only after about 100 error-maximal steps in one
/// direction, and 1 % of the energy marks a trajectory no longer worth
/// reading at any tolerance.
void check_drift(RunReport& report, double rtol);

/// The smallest relative tolerance a run accepts: about 5 units of
/// double-precision rounding (ε = 2.2e-16). An adaptive step cannot hold its
/// error below the rounding of the state itself, so a smaller rtol only
/// shrinks the steps until max_steps or step-size underflow stops the run.
inline constexpr double min_rtol = 1e-15;

struct SimulationOptions {
  Method method = Method::dopri5;  ///< the stepper (method.hpp)
  double t0 = 0.0;                ///< start time (s)
  double t_end = 10.0;            ///< end time (s), > t0
  double dt = 1e-3;               ///< fixed step for rk4; first trial step for adaptive steppers (s)
  double rtol = 1e-10;            ///< relative tolerance per step (adaptive steppers), in [min_rtol, 1)
  double atol = 1e-12;            ///< absolute tolerance per step (adaptive steppers)
  std::uint64_t max_steps = 50'000'000;  ///< a run needing more accepted steps fails
  /// Time between samples sent to the observer (s). 0: every accepted step.
  /// Negative: only the initial and final states.
  double output_interval = 0.0;

  // Constrained models only (ignored otherwise).
  Stabilization stabilization = Stabilization::projection;  ///< drift control
  double baumgarte_omega = 10.0;        ///< Baumgarte rate ω (1/s), critically damped
  double projection_tolerance = 1e-12;  ///< ‖g‖∞ after projection, relative to 1 + ‖q‖∞

  // The variational integrator only (method "variational").
  /// Discrete Lagrangian: "midpoint" or "trapezoidal" (see discrete.hpp).
  std::string discrete_rule = "midpoint";
  /// Newton's method stops when ‖Δq‖∞ ≤ newton_tolerance · (1 + ‖q‖∞).
  double newton_tolerance = 1e-12;
  /// A step whose Newton solve needs more iterations fails (SimulationError).
  int newton_max_iterations = 50;

  /// Point r₀ (m) about which the angular momentum of a particle system is
  /// reported (models that declare particles()).
  std::array<double, 3> angular_momentum_point{0.0, 0.0, 0.0};

  // Contacts (unilateral constraints with restitution) only.
  /// Zeno rule: an impact whose approach speed is at most this fraction of
  /// the largest approach speed met so far on the same contact, or that comes
  /// within `zeno_min_interval` of the previous impact there, ends the
  /// bouncing when the forces press the contact shut (d²φ/dt² < 0 in free
  /// motion): it is resolved with e = 0 and the contact becomes a resting
  /// contact (active unilateral constraint). In [0, 1).
  double zeno_speed_ratio = 1e-6;
  /// Shortest time between two impacts on one contact before they count as
  /// an accumulation (s), relative to max(1 s, |t|).
  double zeno_min_interval = 1e-10;
  /// Approach speeds at or below this (units of dφ/dt, m/s for a distance
  /// gap) are touches, not impacts: no impulse; the contact becomes resting
  /// if the motion presses into it and is ignored if it curves away.
  double contact_touch_speed = 1e-9;

  /// Throws OptionError naming the first invalid field and its value.
  void validate() const;
};

/// Drift of one generalized momentum conjugate to a cyclic coordinate.
struct MomentumDrift {
  std::string coordinate;   ///< name of the cyclic coordinate
  double initial = 0;       ///< p at t0
  double max_abs_drift = 0;  ///< max |p(t) − p(t0)| over the samples
  double final_abs_drift = 0;  ///< |p(t_end) − p(t0)|
  double rate_max = 0;         ///< max |q̇| of the coordinate over the samples (its units per s)
};

/// One sanity monitor's verdict (RunReport::monitors, check_drift).
struct MonitorVerdict {
  std::string name;     ///< "energy", "momentum p_<coordinate>", "linear momentum", "angular momentum",
                        ///< "constraint residual", "closed-form error"
  double figure = 0;    ///< its largest drift or error over the run, dimensionless (see check_drift)
  bool exceeded = false;  ///< figure > RunReport::drift_bound
};

/// Constraint residuals and the cost of keeping them small.
struct ConstraintReport {
  std::vector<std::string> names;        ///< holonomic then Pfaffian constraints
  std::string stabilization;             ///< none, baumgarte or projection
  double baumgarte_omega = 0;            ///< ω used (1/s), 0 unless baumgarte
  double max_position_residual = 0;      ///< max ‖g(q, t)‖∞ over accepted steps and samples (holonomic)
  double max_velocity_residual = 0;      ///< max ‖C q̇ + c‖∞ over accepted steps and samples
  double final_position_residual = 0;    ///< ‖g‖∞ at t_end
  double final_velocity_residual = 0;    ///< ‖C q̇ + c‖∞ at t_end
  std::uint64_t projections = 0;         ///< projections carried out
  std::uint64_t projection_iterations = 0;  ///< Gauss–Newton iterations in them
  std::uint64_t extra_rhs_evaluations = 0;  ///< right-hand sides re-evaluated after projections
  double stabilization_time_s = 0;       ///< wall time spent projecting (s)
  int initial_rank = 0;                  ///< rank of the constraint Jacobian at t0
  int min_rank = 0;                      ///< smallest rank met at the samples
  /// Smallest σ_r/σ_1 over accepted steps and samples, σ the singular values of the
  /// bilateral constraint Jacobian and r its rank at t0: near 0 when the
  /// run passed close to a singular configuration (1 when unconstrained).
  double min_conditioning = 1;
  double min_conditioning_time = 0;      ///< when min_conditioning was met (s)
  std::vector<std::string> warnings;     ///< rank drops (singular configurations) with their times
};

/// Kinds of logged events.
enum class EventKind {
  impact,   ///< a contact closed with approach speed: Newton's law of restitution applied
  rest,     ///< a contact became a resting contact (Zeno accumulation, plastic impact or a slow touch)
  release,  ///< a resting contact lifted off (its force would have pulled)
  watched,  ///< a watched event function crossed zero
  stop,     ///< a watched event with action stop ended the run
};

/// Name of an event kind ("impact", "rest", "release", "event", "stop").
const char* to_string(EventKind k);

/// One entry of a run's event log (see RunReport::write_events_csv).
struct EventRecord {
  double t = 0;              ///< time (s), located to event_time_tolerance
  EventKind kind = EventKind::impact;
  std::string name;          ///< the contact or event function (for contacts between bodies, their names)
  double impulse = 0;        ///< Λ along +∇φ (N·s for a distance gap); 0 for releases and watched events
  double approach_speed = 0;     ///< −dφ/dt before (m/s for a distance gap); 0 unless impact or rest
  double separation_speed = 0;   ///< dφ/dt after
  double kinetic_energy_before = 0;  ///< T just before (J); ½ q̇ᵀMq̇ when the model gives L directly
  double kinetic_energy_after = 0;   ///< T just after (J), likewise
  /// A rest that the Zeno rule began: the time the bounces it cut off would
  /// have taken (s, an estimate: detail::zeno_cutoff), to which the rest's
  /// time is known. NaN for other events.
  double zeno_cutoff = std::numeric_limits<double>::quiet_NaN();
};

/// What a run did, what it cost and how accurate it was.
struct RunReport {
  std::string model;             ///< model name
  std::vector<std::string> coordinates;  ///< coordinate names
  std::string method;            ///< stepper name
  bool adaptive = true;          ///< adaptive step size control
  double rtol = 0, atol = 0, dt = 0;
  double t0 = 0, t_end = 0;

  std::uint64_t steps = 0;            ///< accepted steps
  std::uint64_t rejected_steps = 0;   ///< steps rejected by the error control
  std::uint64_t rhs_evaluations = 0;  ///< evaluations of q̈ (including those for Jacobians); variational: of L on AD numbers
  std::uint64_t newton_iterations = 0;  ///< Newton iterations of implicit steps (variational)
  std::uint64_t samples = 0;          ///< samples sent to the observer
  double wall_time_s = 0;             ///< wall-clock time of the integration (s)

  /// True when no generalized force or dissipation is declared and ∂L/∂t = 0
  /// at the sampled states: the energy function h is then a constant of the
  /// motion and its drift measures the integration error.
  bool conservative = false;
  /// The sanity monitor (check_drift): the relative drift of a conserved
  /// energy that a run at its tolerance can excuse, max(1e-2, 100 rtol), and
  /// whether the run went beyond it. When it did, `warnings` says so in words,
  /// and the `lagrangian` command exits with code 3 unless --allow-drift.
  double drift_bound = 0;
  bool drift_exceeded = false;
  /// Every monitor that applies to the run, with its figure (check_drift).
  std::vector<MonitorVerdict> monitors;
  /// The largest ‖q‖∞ over the samples (units of q): the scale of the
  /// constraint-residual and closed-form monitors.
  double coordinate_scale = 0;
  /// Scale for the sanity monitor's energy drift (J): the largest of |h| and
  /// |T| + |V| over the run's samples (t0 included), or 1 J when all are
  /// zero. The particle scenes use |E| and |T| + |V|; the hard-sphere engine
  /// T0. The figures users quote are relative to the initial energy
  /// (energy_drift_relative_to_initial()); these, relative to the scale,
  /// stay defined where h0 = 0 (a pendulum let go from the horizontal).
  double energy_scale = 1;
  double energy_initial = 0;        ///< h(t0) = p·q̇ − L (J)
  double energy_final = 0;          ///< h(t_end) (J)
  double energy_drift_max = 0;      ///< max |h − h0| / energy_scale over the samples
  double energy_drift_final = 0;    ///< |h(t_end) − h0| / energy_scale
  bool has_total_energy = false;    ///< the model gives T and V separately
  double total_energy_initial = 0;  ///< T + V at t0 (J)
  double total_energy_final = 0;    ///< T + V at t_end (J)
  double total_energy_drift_max = 0;    ///< max |E − E0| / energy_scale
  double total_energy_drift_final = 0;  ///< |E(t_end) − E0| / energy_scale
  /// T + V equalled h at every sample (to 1e-9 of the energy scale): T is
  /// quadratic in q̇ and the constraints do not move, so T + V is conserved
  /// exactly when h is. False for a bead on a rotating hoop, whose h is
  /// conserved while the motor feeds T + V.
  bool total_energy_is_h = false;

  /// The energy figures relative to the initial energy, what celestial
  /// mechanics quotes as |ΔE/E0| (dimensionless): |h − h0| / |h0| at t_end
  /// and its largest value over the samples; the same for T + V. Impacts'
  /// losses are taken out as in energy_drift_* (h0 moves by each impact's
  /// change). NaN when the initial energy is 0, where only the scale-relative
  /// figure is defined.
  double energy_drift_relative_to_initial() const;
  double energy_drift_relative_to_initial_max() const;
  double total_energy_drift_relative_to_initial() const;
  double total_energy_drift_relative_to_initial_max() const;
  std::vector<MomentumDrift> conserved_momenta;  ///< cyclic coordinates and their momenta
  /// Particle systems (models that declare particles() or mass_points(),
  /// particle scenes):
  /// total linear momentum P = Σ m v (kg·m/s) and angular momentum
  /// L = Σ m (r − r₀) × v (kg·m²/s) about
  /// SimulationOptions::angular_momentum_point, at t0, and the largest and
  /// final drift of their conserved components, |P(t) − P(t0)| and
  /// |L(t) − L(t0)| over those components only. Which components the
  /// system's symmetries conserve is judged at the start of the run from its
  /// own forces and contacts (Noether; integrate/detail/momentum_symmetry.hpp): a
  /// component is conserved when no external force has a part along it (a
  /// moment about it, for L) and no impact with a fixed surface pushes along
  /// it (turns about it). For each component left out the reason says why.
  bool has_particles = false;
  std::array<bool, 3> linear_momentum_conserved{}, angular_momentum_conserved{};
  std::array<std::string, 3> linear_momentum_reason, angular_momentum_reason;
  /// Models with a closed form (reference()): the largest and the final
  /// error max_i |q_i(t) − q_i,ref(t)| over the samples (units of q), the
  /// true error of the run.
  bool has_reference = false;
  double reference_error_max = 0, reference_error_final = 0;
  std::array<double, 3> linear_momentum_initial{};
  std::array<double, 3> angular_momentum_initial{};
  double linear_momentum_drift_max = 0, linear_momentum_drift_final = 0;
  double angular_momentum_drift_max = 0, angular_momentum_drift_final = 0;
  /// Σ m |v| (kg·m/s) and Σ m |r − r₀| |v| (kg·m²/s) at t0 (or, when zero
  /// there, at the first sample where they are not): the scales of the
  /// momentum monitors.
  double momentum_scale = 0, angular_momentum_scale = 0;
  bool constrained = false;                      ///< the model declares constraints
  ConstraintReport constraints;                  ///< filled when constrained

  /// Every event in time order: impacts, rests, releases, watched events.
  std::vector<EventRecord> events;
  std::uint64_t impacts = 0;        ///< events of kind impact
  /// Events that happened but are not in `events`: the event-driven engine
  /// keeps the first HardSphereOptions::max_recorded_events (a scene's
  /// output.max_events). Nonzero: the log is truncated, and the summary,
  /// report.json and events.csv say so.
  std::uint64_t unlogged_events = 0;
  double impact_energy_loss = 0;    ///< sum of T_before − T_after over impacts and rests (J)
  /// Normal impulse each fixed wall received over the run (N·s), by wall name
  /// ("wall:x_max", a plane's name): every impact counted, logged or not
  /// (event-driven engine; empty otherwise). Over the run's duration and a
  /// wall's area it is the mean pressure on that wall.
  std::map<std::string, double> wall_impulses;
  /// The same in kWallImpulseBlocks equal stretches of [t0, t_end], in order
  /// (their sum is wall_impulses): the fluctuation of the pressure from one
  /// stretch to the next gives its standard error.
  std::map<std::string, std::vector<double>> wall_impulse_blocks;
  static constexpr int kWallImpulseBlocks = 10;
  /// Time at which a watched event with action stop ended the run (s); NaN
  /// when the run reached t_end.
  double stopped_at = std::numeric_limits<double>::quiet_NaN();
  std::string stopped_by;           ///< name of that event; empty when none
  double t_final = 0;               ///< time the run ended (t_end, or stopped_at) (s)
  /// Explicit adaptive steppers: the largest |eigenvalue| ρ of ∂f/∂x at the
  /// end of the run (1/s), estimated by power iteration on (∂f/∂x)² with
  /// finite differences of f; 0 when not estimated. When the step size at
  /// the end times ρ exceeds 1, the run's first stretch at tolerances 100
  /// times tighter takes under 1.5 times as many steps (the steps were
  /// limited by stability, not accuracy; the test made with dopri5 for
  /// bulirsch_stoer; "may" where it cannot be made), and rosenbrock4, run
  /// again over the whole run at the same tolerances and sample times, used
  /// fewer evaluations of f than the run (a stiff problem), `warnings` says
  /// so with both counts. Without that measurement there is no warning:
  /// rosenbrock4 is never recommended where it was measured slower.
  double stiffness_rho = 0;
  /// Run-level warnings (e.g. an explicit stepper on a stiff problem).
  std::vector<std::string> warnings;

  /// The report as a JSON object (numbers with 17 significant digits; NaN as null).
  std::string to_json() const;
  /// A few human-readable lines for a terminal.
  std::string summary() const;
  /// Writes to_json() to `path` (through `<path>.partial`, renamed when
  /// complete); throws OptionError naming the path when it cannot.
  void write_json(const std::string& path) const;
  /// Writes the event log as CSV with the header
  ///   t [s],kind,bodies,impulse,approach_speed,separation_speed,ke_before [J],ke_after [J]
  /// where `bodies` is the contact's name (the bodies it joins, e.g. s1-s2) or
  /// the watched event's name. `gap_unit` is the unit of the contacts' gaps φ
  /// ("m" when every gap is a distance): given, the impulse and the speeds
  /// carry theirs ("impulse [N*s]", "approach_speed [m/s]"); empty, they
  /// carry none. Written through `<path>.partial`, renamed when complete;
  /// throws OptionError naming the path when it cannot.
  void write_events_csv(const std::string& path, const std::string& gap_unit = "") const;
};

}  // namespace lagrangian
