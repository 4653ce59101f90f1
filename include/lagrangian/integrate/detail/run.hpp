#pragma once
// The bookkeeping of one run, shared by every stepper loop of the driver:
// samples due, the limits (finite state, max_steps, step-size underflow),
// and the system's hooks behind one object.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "lagrangian/integrate/detail/roots.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/integrate/system.hpp"

namespace lagrangian::detail {

/// The state of the first-order system in the driver: 2n values.
using StateVector = std::vector<double>;

/// True when t has reached t_end up to rounding.
inline bool reached(double t, double t_end) {
  return t_end - t <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(t), std::abs(t_end));
}

/// f(x, t) of the system as Odeint calls it, counting evaluations. X is the
/// Odeint state: std::array<double, 2n> for the sizes the driver is compiled
/// for (explicit_loops.hpp), StateVector otherwise.
template <class X = StateVector>
struct CountedRhs {
  const System* system;
  std::uint64_t* evaluations;
  void operator()(const X& x, X& dxdt, double t) const {
    system->rhs(x.data(), dxdt.data(), t);
    ++*evaluations;
  }
};

class Run {
 public:
  Run(System& system, const SimulationOptions& options, RunReport& report);

  const SimulationOptions& options() const { return opt_; }
  RunReport& report() { return report_; }
  System& system() { return system_; }
  template <class X = StateVector>
  CountedRhs<X> rhs() const {
    return {&system_, &report_.rhs_evaluations};
  }
  /// n: the state has 2n values.
  int size() const { return size_; }
  bool has_events() const { return events_; }
  bool has_constraints() const { return constraints_; }

  /// Next time a sample is due (infinity when sampling every step or never).
  double next_output_time() const { return next_output_; }
  /// True once an event stopped the run.
  bool stopped() const { return events_ && system_.stopped(); }
  /// Constraint stabilisation after an accepted step; true when x changed.
  bool stabilize(double* x, double t, bool allow_projection = true) {
    return constraints_ && system_.stabilize(x, t, allow_projection);
  }
  /// Events in the step from (t_old, x_old) to (t, x); true when one was
  /// applied (t and x then moved to it).
  bool handle_events(double t_old, const double* x_old, double& t, double* x, const Interpolator& interp) {
    return events_ && system_.handle_events(t_old, x_old, t, x, interp);
  }
  void extra_rhs_evaluation() { system_.extra_rhs_evaluation(); }

  /// A sample at (t, x).
  void emit(double t, const double* x);

  /// Called after every accepted step ending at t with state x (2n values).
  /// `interpolate(t_out, buffer)` fills the state at an earlier time when the
  /// stepper has dense output; otherwise steps end on output times. One
  /// combined test per step (state finite, max_steps not reached, no sample
  /// due); all else, including the errors, is in accepted_slow().
  template <class Interp>
  void accepted(double t_old, double t, const double* x, const Interp& interpolate) {
    ++report_.steps;
    recent_steps_[report_.steps % 2] = t - t_old;
    last_t_ = t;
    // No sample is due while t + tol < next output time, with the tolerance
    // of accepted_slow(), tol = 1e-12 max(|t|, Δt_out) ≤ 1e-12 (|t| + Δt_out).
    const bool finite = all_finite(x);
    const bool within = report_.steps <= opt_.max_steps;
    const bool no_sample = no_sample_due(t);
    if (!(finite & within & no_sample)) [[unlikely]]
      accepted_slow(t_old, t, x, interpolator(interpolate));
  }

  /// True when no sample is due by a step ending at t (the test of accepted()).
  bool no_sample_due(double t) const { return sample_due_ > t + 1e-12 * std::abs(t) + sample_slack_; }
  /// Steps left before max_steps is exceeded.
  std::uint64_t steps_left() const { return opt_.max_steps > report_.steps ? opt_.max_steps - report_.steps : 0; }
  /// accepted() for `count` steps taken in a row, the last from t_old to t
  /// ending at x, after which no sample was due (no_sample_due()) and of
  /// which all but the last ended with a finite state.
  void accepted_in_a_row(std::uint64_t count, double t_old, double t, const double* x) {
    report_.steps += count - 1;
    accepted(t_old, t, x, [](double, double*) {});
  }

  /// A rejected step attempt at t with the reduced step dt; throws
  /// SimulationError on step-size underflow.
  void rejected(double t, double dt);
  void reset_rejections() { consecutive_rejections_ = 0; }
  /// The larger of the last two accepted step sizes (s): the step size at
  /// the end of the run even when the last step was cut short to end on t_end.
  double recent_step() const { return std::max(recent_steps_[0], recent_steps_[1]); }
  /// Time of the last accepted step's end (t0 before the first).
  double last_time() const { return last_t_; }

  /// The end of the run: the system's final monitors, and a sample of the
  /// end state x if not sampled yet.
  void finish(const double* x);

 private:
  void accepted_slow(double t_old, double t, const double* x, const Interpolator& interpolate);
  [[noreturn]] void throw_non_finite(double t_old, double t, const double* x) const;
  [[noreturn]] void throw_max_steps(double t) const;
  void update_next_output();
  bool all_finite(const double* x) const {
    bool finite = true;
    for (int i = 0; i < 2 * size_; ++i) finite = finite && std::isfinite(x[i]);
    return finite;
  }

  System& system_;
  const SimulationOptions& opt_;
  RunReport& report_;
  int size_;
  bool events_, constraints_;
  std::uint64_t consecutive_rejections_ = 0;
  std::array<double, 2> recent_steps_{};
  double last_emitted_ = std::numeric_limits<double>::quiet_NaN();
  double last_t_ = 0;
  std::uint64_t next_output_index_ = 1;
  double next_output_ = std::numeric_limits<double>::infinity();  ///< t0 + next_output_index_ · output_interval
  /// The time from which accepted() must look for due samples (−∞ when
  /// sampling every step, +∞ when sampling only the ends).
  double sample_due_ = std::numeric_limits<double>::infinity();
  double sample_slack_ = 0;  ///< 1e-12 Δt_out (s)
  StateVector buf_;
};

}  // namespace lagrangian::detail
