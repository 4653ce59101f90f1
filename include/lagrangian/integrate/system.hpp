#pragma once
/// \file system.hpp
/// The system the integration driver (integrate.hpp) runs: a first-order
/// system ẋ = f(x, t) with x = [q; q̇] (2n values: n generalized
/// coordinates in their own units — m, rad — then their rates, m/s, rad/s),
/// and optional hooks for what a run may need besides f: constraint
/// stabilisation, events (contacts, watched event functions, impacts), the
/// monitors reported at samples, and a stepper of the system's own.
///
/// The driver is compiled once, in the library; a system is reached through
/// this interface, one indirect call per right-hand side. A Model becomes a
/// System through the adapter of simulate() (integrate/detail/model_system.hpp), the
/// only per-model part of a run. Hooks a system does not override cost a
/// run nothing: the driver asks has_constraints() and has_events() once.

#include <vector>

#include "lagrangian/integrate/detail/roots.hpp"

namespace lagrangian {

namespace detail {
class Run;
}  // namespace detail

/// The state inside the step just taken: interpolant(t, x_out) writes the 2n
/// values of x at a time t between the step's ends (the stepper's dense
/// output, or a controlled sub-step from the step's start).
using StepInterpolant = detail::Interpolator;

/// A first-order system for integrate(). Only coordinate_count(), rhs() and
/// sample() are required.
class System {
 public:
  virtual ~System() = default;

  /// n, the number of generalized coordinates; the state x has 2n values.
  virtual int coordinate_count() const = 0;

  /// ẋ = f(x, t): writes 2n values into dxdt. Called from every stage of
  /// every step; it must not allocate. Throws DynamicsError when f cannot
  /// be evaluated (a singular mass matrix), which stops the run.
  virtual void rhs(const double* x, double* dxdt, double t) const = 0;

  /// Sets up the run's monitors at (t0, x) before the first step; may
  /// change x (impacts at t0). The first sample follows.
  virtual void start(double* x, double t0) = 0;

  /// A sample at (t, x): the monitors (energy, momenta, constraint
  /// residuals, ...) and the observer.
  virtual void sample(double t, const double* x) = 0;

  /// The end of the run at (t, x), after the last accepted step; when
  /// `sample_end` the end state has not been sampled yet and is sampled now.
  virtual void finish(double t, const double* x, bool sample_end) = 0;

  /// True when the system has constraints: stabilize() is then called after
  /// every accepted step.
  virtual bool has_constraints() const { return false; }
  /// Constraint stabilisation and residual monitoring after an accepted step
  /// ending at (t, x); projection only when `allow_projection`. Returns true
  /// when x changed.
  virtual bool stabilize(double* x, double t, bool allow_projection) {
    (void)x, (void)t, (void)allow_projection;
    return false;
  }
  /// Counts a right-hand side re-evaluated because stabilize() or an event
  /// moved the state (first-same-as-last steppers).
  virtual void extra_rhs_evaluation() {}

  /// True when the system has contacts or watched events: handle_events()
  /// is then called after every accepted step.
  virtual bool has_events() const { return false; }
  /// Events in the step just taken from (t_old, x_old) to (t, x), located
  /// on `interpolant`. When one is applied the step end moves to it (t and x
  /// are overwritten) and true is returned: the stepper restarts there.
  virtual bool handle_events(double t_old, const double* x_old, double& t, double* x,
                             const StepInterpolant& interpolant) {
    (void)t_old, (void)x_old, (void)t, (void)x, (void)interpolant;
    return false;
  }
  /// True once an event asked the run to stop.
  virtual bool stopped() const { return false; }

  /// The explicit Runge–Kutta methods (dopri5, rk4, cash_karp54,
  /// fehlberg78, bulirsch_stoer) compiled for this system's type with its
  /// right-hand side inlined into the stepper's stages: the driver's own
  /// loops (integrate/detail/explicit_loops.hpp), not a copy; a model's adapter does
  /// this for models wrapped by lagrangian::inlined() (inlined.hpp). Runs
  /// `run` from x (2n values) to its end and returns true; the default
  /// returns false and the driver runs the loops compiled once in the
  /// library, which reach rhs() through the vtable. Worth it only when f is
  /// cheap (a hand-coded q̈), where the indirect call and the lost inlining
  /// are a tenth of a run (docs/performance.md).
  virtual bool integrate_inlined(detail::Run& run, std::vector<double>& x) {
    (void)run, (void)x;
    return false;
  }

  /// The system's own fixed-step method, for options.method ==
  /// "variational": advances x (2n values) from t by h. The default throws
  /// OptionError (the system has none).
  virtual void variational_step(double t, double h, double* x);
};

namespace detail {
/// Stops a run whose energy (J) came out infinite or NaN at a sample at t
/// while the state x (2n values) is finite: the values overflow double
/// precision. Throws SimulationError naming the time, energy and state.
[[noreturn]] void throw_non_finite_energy(double t, double energy, const double* x, int n);
}  // namespace detail

}  // namespace lagrangian
