#pragma once
// RunState: the bookkeeping of one simulate() run shared by all stepper
// loops (samples, drift monitors, limits); its constraint and event members
// are defined in run_constraints.hpp and run_events.hpp.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "lagrangian/constraints.hpp"
#include "lagrangian/detail/first_order_system.hpp"
#include "lagrangian/detail/observer_ref.hpp"
#include "lagrangian/detail/roots.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/impact.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/properties.hpp"
#include "lagrangian/report.hpp"

namespace lagrangian::detail {

/// Bookkeeping shared by all stepper loops: samples, drift monitors, limits.
template <class M, class Observer = ObserverRef<M::dof>>
class RunState {
 public:
  static constexpr int n = M::dof;
  /// The model declares contacts or watched events (the event code is compiled only then).
  static constexpr bool has_events_v = unilateral_count_v<M> > 0 || event_count_v<M> > 0;

  RunState(const M& model, const SimulationOptions& opt, Observer& obs, RunReport& report)
      : model_(model),
        opt_(opt),
        obs_(obs),
        report_(report),
        size_(model_size(model)),
        buf_(make_buffer<n>(size_)) {}

  /// Sets up the monitors and emits the first sample. Contacts that touch
  /// and approach at t0 are resolved first (impacts at t0); the state the
  /// run continues from is returned.
  State<n> start(State<n> x0) {
    Columns columns{coordinate_names(model_), {}, has_kinetic_potential_v<M>};
    if constexpr (has_constraints_v<M>) start_constraints(x0, columns);
    if constexpr (event_count_v<M> > 0) specs_ = event_specs(model_);
    if constexpr (has_particles_v<M>) {
      int k = 0;
      for (const Particle& part : model_.particles()) {
        if (!(part.mass > 0) || !std::isfinite(part.mass))
          throw ParameterError(model_name(model_) + ": particle " + std::to_string(k) + " has mass " +
                               std::to_string(part.mass) + "; it must be positive and finite");
        for (int i : part.axes)
          if (i < -1 || i >= size_)
            throw ParameterError(model_name(model_) + ": particle " + std::to_string(k) + " names coordinate " +
                                 std::to_string(i) + ", outside [0, " + std::to_string(size_) + ")");
        ++k;
      }
    }
    if constexpr (has_events_v) event_buf_.assign(static_cast<std::size_t>(2 * size_), 0.0);
    const std::vector<int> cyclic = cyclic_coordinates(model_, x0, opt_.t0);
    cyclic_.assign(cyclic.begin(), cyclic.end());
    Vec<double, n> p(size_);
    h0_ = energy_and_momenta(model_, x0.q, x0.qd, opt_.t0, p);  // after any impact at t0
    pending_shifts_.clear();
    double scale = std::abs(h0_);
    if constexpr (has_kinetic_potential_v<M>) {
      const double t0 = model_.kinetic(x0.q, x0.qd, opt_.t0);
      const double v0 = model_.potential(x0.q, opt_.t0);
      e0_ = t0 + v0;
      scale = std::max(scale, std::abs(t0) + std::abs(v0));
      report_.has_total_energy = true;
      report_.total_energy_initial = e0_;
    }
    report_.energy_scale = scale > 0 && std::isfinite(scale) ? scale : 1.0;
    report_.energy_initial = h0_;
    for (int i : cyclic_) report_.conserved_momenta.push_back({columns.coordinates[static_cast<std::size_t>(i)], p[i], 0, 0});
    if (obs_.begin) obs_.begin(obs_.object, columns);
    next_output_index_ = 1;
    update_next_output();
    last_t_ = opt_.t0;
    emit(opt_.t0, x0.q.data(), x0.qd.data());
    return x0;
  }

  /// Next time a sample is due (infinity when sampling every step or never).
  double next_output_time() const { return next_output_; }

  /// Called after every accepted step ending at t with state x (2n values).
  /// `interpolate(t_out, buffer)` fills the state at an earlier time when the
  /// stepper has dense output; otherwise steps end on output times.
  ///
  /// Inlined into the stepper loops: one combined test per step (state
  /// finite, max_steps not reached, no sample due); all else, including the
  /// errors, is in accepted_slow().
  template <class Interp>
  [[gnu::always_inline]] inline void accepted(double t_old, double t, const double* x, Interp&& interpolate) {
    ++report_.steps;
    recent_steps_[report_.steps % 2] = t - t_old;
    last_t_ = t;
    // No sample is due while t + tol < next output time, with the tolerance
    // of accepted_slow(), tol = 1e-12 max(|t|, Δt_out) ≤ 1e-12 (|t| + Δt_out).
    const bool finite = all_finite(x);
    const bool within = report_.steps <= opt_.max_steps;
    const bool no_sample = sample_due_ > t + 1e-12 * std::abs(t) + sample_slack_;
    if (!(finite & within & no_sample)) [[unlikely]]
      accepted_slow(t_old, t, x, interpolate);
  }

  /// Constrained models: projection (when chosen) and residual monitoring
  /// after an accepted step ending at t with state x; true when x changed.
  bool stabilize(double* x, double t, bool allow_projection = true);
  /// Tracks σ_r/σ_1 of the bilateral constraint Jacobian (r = rank at t0)
  /// at accepted steps and samples, and warns once when it falls below
  /// 1e-3: a singular configuration is near (the multipliers grow without
  /// bound there, and the motion may switch assembly branches).
  template <class CS>
  void monitor_conditioning(CS cs, double t);
  void extra_rhs_evaluation() {
    if constexpr (has_constraints_v<M>) ++report_.constraints.extra_rhs_evaluations;
  }
  void attach(ConstraintContext<M>* ctx) { ctx_ = ctx; }
  ActiveSet active() const { return ctx_ ? ctx_->active : all_active; }

  /// Events in the step just taken from (t_old, x_old) to (t, x): lift-off
  /// of resting contacts (their multiplier turns negative), contacts closing
  /// (the gap φ falls through zero, or dips below zero and back inside the
  /// step), and watched event functions crossing zero in their direction.
  /// Each crossing is located with Boost.Math's TOMS 748 on the step's
  /// continuous extension `interp` (dopri5's dense output, or a Fehlberg 7(8)
  /// sub-step from the step's start), the bracket narrowed to
  /// event_time_tolerance · max(1 s, |t|). The earliest event is applied:
  /// the step end moves to it (t and x are overwritten) and true is
  /// returned, so the caller restarts its stepper there; later events in
  /// the step are found by the following steps, so events are handled in
  /// time order. Truly simultaneous contacts are resolved together by
  /// resolve_contacts().
  template <class Interp>
  bool handle_events(double t_old, const double* x_old, double& t, double* x, const Interp& interp) {
    if constexpr (!has_events_v) {
      (void)t_old, (void)x_old, (void)t, (void)x, (void)interp;
      return false;
    } else {
      return handle_events_erased(t_old, x_old, t, x, interpolator(interp));  // one instantiation per model
    }
  }
  // Instantiated only for models with events (called from handle_events).
  bool handle_events_erased(double t_old, const double* x_old, double& t, double* x, Interpolator interp);

  /// True once a watched event with action stop has fired (a compile-time
  /// false without events, so the loops carry no extra branch).
  bool stopped() const {
    if constexpr (has_events_v) {
      return stopped_;
    } else {
      return false;
    }
  }

  /// Resolves every contact that is touching (|φ| within the touch
  /// tolerance) and approaching faster than contact_touch_speed at (x, t),
  /// one pair at a time: the one approaching fastest first, by Newton's law
  /// of restitution (apply_impact), until none approaches (the sequential
  /// rule for simultaneous impacts; each step conserves momentum, and kinetic
  /// energy when e = 1). Zeno accumulations are resolved plastically (see
  /// SimulationOptions::zeno_speed_ratio). Afterwards the contacts that took
  /// part (and `trigger`) are resting (active) when they do not separate,
  /// and active contacts that separate are released.
  void resolve_contacts(double* x, double t, int trigger);

  void rejected(double t, double dt) {
    ++report_.rejected_steps;
    if (++consecutive_rejections_ > 1000 || !(dt > 1e-15 * std::max(1.0, std::abs(t)))) {
      std::ostringstream os;
      os.precision(17);
      os << "step size underflow at t = " << t << " (dt = " << dt << " after " << consecutive_rejections_
         << " rejected steps); the problem may be stiff (try method rosenbrock4) or singular";
      throw SimulationError(os.str(), t);
    }
  }
  void reset_rejections() { consecutive_rejections_ = 0; }
  /// The larger of the last two accepted step sizes (s): the step size at
  /// the end of the run even when the last step was cut short to end on t_end.
  double recent_step() const { return std::max(recent_steps_[0], recent_steps_[1]); }

  /// Final bookkeeping: sample the end state if not done yet.
  /// x: the state at the end of the last accepted step (2n values).
  void finish(const double* x) {
    report_.t_final = last_t_;
    if constexpr (has_events_v) apply_pending_shifts(last_t_);
    if (opt_.output_interval != 0 && last_emitted_ != last_t_) emit(last_t_, x, x + size_);
    report_.energy_drift_final = std::abs(h_last_ - h0_) / report_.energy_scale;
    if (report_.has_total_energy) report_.total_energy_drift_final = std::abs(e_last_ - e0_) / report_.energy_scale;
    report_.energy_final = h_last_;
  }

 private:
  void emit(double t, const double* q, const double* qd) {
    if constexpr (has_events_v) apply_pending_shifts(t);
    Sample<n> s;
    s.t = t;
    s.q.resize(size_);
    s.qd.resize(size_);
    for (int i = 0; i < size_; ++i) {
      s.q[i] = q[i];
      s.qd[i] = qd[i];
    }
    Vec<double, n> p(size_);
    s.energy = energy_and_momenta(model_, s.q, s.qd, t, p);
    h_last_ = s.energy;
    report_.energy_drift_max = std::max(report_.energy_drift_max, std::abs(s.energy - h0_) / report_.energy_scale);
    if constexpr (has_kinetic_potential_v<M>) {
      s.total_energy = model_.kinetic(s.q, s.qd, t) + model_.potential(s.q, t);
      e_last_ = s.total_energy;
      report_.total_energy_drift_max =
          std::max(report_.total_energy_drift_max, std::abs(s.total_energy - e0_) / report_.energy_scale);
    }
    if constexpr (has_constraints_v<M>) sample_constraints(s);
    if constexpr (has_particles_v<M>) sample_particles(s);
    if constexpr (has_reference_v<M>) {
      if (s.t == opt_.t0) {
        reference_initial_.q = s.q;
        reference_initial_.qd = s.qd;
      }
      const State<n> ref = model_.reference(reference_initial_, s.t - opt_.t0);
      report_.has_reference = true;
      report_.reference_error_final = (s.q - ref.q).template lpNorm<Eigen::Infinity>();
      report_.reference_error_max = std::max(report_.reference_error_max, report_.reference_error_final);
    }
    for (std::size_t k = 0; k < cyclic_.size(); ++k) {
      MomentumDrift& d = report_.conserved_momenta[k];
      d.final_abs_drift = std::abs(p[cyclic_[k]] - d.initial);
      d.max_abs_drift = std::max(d.max_abs_drift, d.final_abs_drift);
    }
    obs_(s);
    ++report_.samples;
    last_emitted_ = t;
  }

  /// P = Σ m v and L = Σ m (r − r₀) × v of a particle system at a sample.
  void sample_particles(const Sample<n>& s) {
    std::array<double, 3> P{}, L{};
    const auto& r0 = opt_.angular_momentum_point;
    for (const Particle& part : model_.particles()) {
      std::array<double, 3> r{}, v{};
      for (int a = 0; a < 3; ++a) {
        const int i = part.axes[static_cast<std::size_t>(a)];
        if (i >= 0) {
          r[static_cast<std::size_t>(a)] = s.q[i] - r0[static_cast<std::size_t>(a)];
          v[static_cast<std::size_t>(a)] = s.qd[i];
        } else {
          r[static_cast<std::size_t>(a)] = -r0[static_cast<std::size_t>(a)];
        }
      }
      for (int a = 0; a < 3; ++a) P[static_cast<std::size_t>(a)] += part.mass * v[static_cast<std::size_t>(a)];
      L[0] += part.mass * (r[1] * v[2] - r[2] * v[1]);
      L[1] += part.mass * (r[2] * v[0] - r[0] * v[2]);
      L[2] += part.mass * (r[0] * v[1] - r[1] * v[0]);
    }
    if (!report_.has_particles) {
      report_.has_particles = true;
      report_.linear_momentum_initial = P;
      report_.angular_momentum_initial = L;
    }
    auto dist = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
      return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
    };
    report_.linear_momentum_drift_final = dist(P, report_.linear_momentum_initial);
    report_.angular_momentum_drift_final = dist(L, report_.angular_momentum_initial);
    report_.linear_momentum_drift_max = std::max(report_.linear_momentum_drift_max, report_.linear_momentum_drift_final);
    report_.angular_momentum_drift_max =
        std::max(report_.angular_momentum_drift_max, report_.angular_momentum_drift_final);
  }

  void start_constraints(State<n>& x0, Columns& columns);
  void sample_constraints(Sample<n>& s);


  /// Gaps within this of zero count as touching: 1e-9 (1 + ‖q‖∞).
  double contact_touch_tolerance(const double* x) const {
    double qmax = 0;
    for (int i = 0; i < size_; ++i) qmax = std::max(qmax, std::abs(x[i]));
    return 1e-9 * (1.0 + qmax);
  }
  template <class G>
  void gaps_at(const double* x, double t, G& g, G& r) const {
    Vec<double, n> q, qd;
    split_state(x, q, qd);
    contact_gaps(model_, q, qd, t, g, r);
  }
  Vec<double, event_count_v<M>> watched_at(const double* x, double t) const {
    if constexpr (event_count_v<M> > 0) {
      Vec<double, n> q, qd;
      split_state(x, q, qd);
      return model_.events(q, qd, t);
    } else {
      (void)x, (void)t;
      return {};
    }
  }
  std::string contact_name(int j) const {
    return report_.constraints.names[static_cast<std::size_t>(holonomic_count_v<M> + j)];
  }
  /// d²φ_j/dt² = G_j q̈ + γ_j with q̈ from the current active set (contact j
  /// itself inactive): negative when the forces press the contact shut.
  double gap_acceleration(const Vec<double, n>& q, const Vec<double, n>& qd, double t, int j);

  /// An event without an impulse: logs it with the kinetic energy at x.
  void log_simple(EventKind kind, const std::string& name, double t, const double* x) {
    EventRecord rec;
    rec.t = t;
    rec.kind = kind;
    rec.name = name;
    Vec<double, n> q, qd;
    split_state(x, q, qd);
    if constexpr (!has_kinetic_potential_v<M>) evaluate(model_, ws_, q, qd, t);  // M for ½ q̇ᵀMq̇
    rec.kinetic_energy_before = rec.kinetic_energy_after = detail::kinetic_for_log(model_, ws_, q, qd, t);
    report_.events.push_back(rec);
  }
  /// After an impact: the energy references move by the energy the impact
  /// took, so the drift monitors keep measuring integration error only.
  void shift_reference_energy(const Vec<double, n>& q, const Vec<double, n>& qd, double t, double h_before,
                              double kinetic_change) {
    // Applied by emit() from the event time on: samples interpolated
    // before the event still compare with the old references.
    pending_shifts_.push_back({t, energy_function(model_, q, qd, t) - h_before, kinetic_change});
  }
  void apply_pending_shifts(double t) {
    std::size_t k = 0;
    for (; k < pending_shifts_.size() && pending_shifts_[k][0] <= t; ++k) {
      h0_ += pending_shifts_[k][1];
      e0_ += pending_shifts_[k][2];  // an impulse leaves V unchanged: ΔE = ΔT
    }
    pending_shifts_.erase(pending_shifts_.begin(), pending_shifts_.begin() + static_cast<std::ptrdiff_t>(k));
  }

  const M& model_;
  const SimulationOptions& opt_;
  Observer& obs_;
  RunReport& report_;
  Workspace<n> ws_{model_size(model_)};
  std::array<double, unilateral_count_v<M>> restitution_{};
  std::array<double, unilateral_count_v<M>> approach_max_{};
  std::array<double, unilateral_count_v<M>> last_impact_{};
  std::vector<EventSpec> specs_;
  std::vector<double> event_buf_;
  bool stopped_ = false;
  std::vector<std::array<double, 3>> pending_shifts_;
  [[no_unique_address]] std::conditional_t<has_reference_v<M>, State<n>, None> reference_initial_{};  ///< (time, Δh, ΔE) of impacts not yet sampled past
  double last_event_time_ = std::numeric_limits<double>::quiet_NaN();
  int events_without_progress_ = 0;
  ConstraintContext<M>* ctx_ = nullptr;
  [[no_unique_address]] std::conditional_t<has_constraints_v<M>, ConstraintWorkspace<n, constraint_count_v<M>>, None>
      cw_{};
  std::vector<int> cyclic_;
  double h0_ = 0, e0_ = 0, h_last_ = 0, e_last_ = 0;
  std::uint64_t next_output_index_ = 1;
  double next_output_ = std::numeric_limits<double>::infinity();  ///< t0 + next_output_index_ · output_interval
  /// sample_due_: the time from which accepted() must look for due samples
  /// (−∞ when sampling every step, +∞ when sampling only the ends).
  double sample_due_ = std::numeric_limits<double>::infinity();
  double sample_slack_ = 0;  ///< 1e-12 Δt_out (s)
  void update_next_output() {
    constexpr double inf = std::numeric_limits<double>::infinity();
    const double dt_out = opt_.output_interval;
    next_output_ = dt_out > 0 ? opt_.t0 + static_cast<double>(next_output_index_) * dt_out : inf;
    sample_due_ = dt_out > 0 ? next_output_ : dt_out == 0 ? -inf : inf;
    sample_slack_ = dt_out > 0 ? 1e-12 * dt_out : 0.0;
  }
  template <class Interp>
  [[gnu::noinline]] void accepted_slow(double t_old, double t, const double* x, Interp& interpolate) {
    if (!all_finite(x)) throw_non_finite(t_old, t, x);
    if (report_.steps > opt_.max_steps) throw_max_steps(t);
    if (opt_.output_interval == 0) {
      emit(t, x, x + size_);
    } else if (opt_.output_interval > 0) {
      const double tol = 1e-12 * std::max(std::abs(t), opt_.output_interval);
      for (double to = next_output_time(); to <= t + tol && to <= opt_.t_end + tol; to = next_output_time()) {
        ++next_output_index_;
        update_next_output();
        if (std::abs(to - t) <= tol) {
          emit(t, x, x + size_);
        } else {
          interpolate(to, buf_.data());
          emit(to, buf_.data(), buf_.data() + size_);
        }
      }
    }
  }
  [[noreturn, gnu::cold, gnu::noinline]] void throw_non_finite(double t_old, double t, const double* x) const {
    std::ostringstream os;
    os.precision(17);
    os << "non-finite state after the step from t = " << t_old << " to t = " << t << ": x = [";
    for (int k = 0; k < 2 * size_; ++k) os << (k ? ", " : "") << x[k];
    os << "] (q then qd); the run was stopped";
    throw SimulationError(os.str(), t);
  }
  [[noreturn, gnu::cold, gnu::noinline]] void throw_max_steps(double t) const {
    std::ostringstream os;
    os << "max_steps = " << opt_.max_steps << " reached at t = " << t << " before t_end = " << opt_.t_end;
    throw SimulationError(os.str(), t);
  }
  /// All 2n state values finite (the loop's length is known at compile time
  /// for fixed-size models).
  bool all_finite(const double* x) const {
    const int count = n == Dynamic ? 2 * size_ : 2 * n;
    bool finite = true;
    for (int i = 0; i < count; ++i) finite = finite && std::isfinite(x[i]);
    return finite;
  }
  std::uint64_t consecutive_rejections_ = 0;
  std::array<double, 2> recent_steps_{};
  std::vector<double> singular_values_;
  bool warned_conditioning_ = false;
  double last_emitted_ = std::numeric_limits<double>::quiet_NaN();
  double last_t_ = 0;
  int size_;
  StateBuffer<n> buf_;
};

}  // namespace lagrangian::detail

#include "lagrangian/detail/run_constraints.hpp"  // IWYU pragma: export
#include "lagrangian/detail/run_events.hpp"  // IWYU pragma: export
