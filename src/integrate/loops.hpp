#pragma once
// The stepper loops of the driver, one per stepper family; each runs from
// options.t0 with x (2n values) and leaves the end state in x.

#include <algorithm>

#include "run.hpp"

namespace lagrangian::detail {

/// The explicit Runge–Kutta methods (dopri5, rk4, cash_karp54, fehlberg78,
/// bulirsch_stoer; explicit_loops.hpp) on the Odeint state std::array<double,
/// 2n> for n ≤ kMaxFixedStateSize and StateVector above: a fixed-size state
/// lets Odeint's stage arithmetic run on registers and unrolled loops, which
/// saved 15 % of the instructions of a whole run of the double pendulum
/// against a std::vector state (docs/performance.md).
void run_explicit(Run& run, StateVector& x);
inline constexpr int kMaxFixedStateSize = 12;
/// The method on the Odeint state X, and on std::array<double, 2N> (x copied
/// in and out): defined in explicit_loops.hpp, compiled in explicit_*.cpp.
template <class X>
void run_explicit_on(Run& run, X& x);
template <int N>
void run_explicit_fixed(Run& run, StateVector& x);
/// Odeint's rosenbrock4 (rosenbrock_loop.cpp).
void run_rosenbrock4(Run& run, StateVector& x);
/// The fixed-step structure-preserving methods (fixed_grid_loops.cpp).
void run_symplectic(Run& run, StateVector& x);
void run_variational(Run& run, StateVector& x);

/// The state inside an accepted step for steppers without dense output:
/// Runge–Kutta–Fehlberg 7(8) from the step's start (t0, x0) to t, with its
/// error controlled to the run's rtol and atol (used only while locating an
/// event). A single uncontrolled step would do for short steps, but
/// Bulirsch–Stoer takes steps of a large fraction of an orbit, over which one
/// 7(8) step is far less accurate than the tolerance the run asked for (the
/// work-precision bench found this: Kepler with periapsis events lost up to
/// three orders of magnitude). Defined in explicit_loops.hpp.
template <class X>
struct SubStep {
  CountedRhs<X> rhs;
  const X& x0;
  double t0;
  double rtol, atol;
  void operator()(double t, double* out) const;
};

/// The loop for a controlled stepper without dense output: `try_step(x, t,
/// dt)` attempts one step (true: accepted, x and t advanced, dt the next
/// step; false: dt reduced), `restart()` is called after an event moved the
/// state. Steps are shortened to land on output times and on t_end; events
/// are located on a SubStep from the step's start.
template <class X, class TryStep, class Restart>
void run_controlled_loop(Run& run, X& x, TryStep&& try_step, Restart&& restart) {
  const SimulationOptions& opt = run.options();
  const bool events = run.has_events();
  double t = opt.t0;
  double dt = opt.dt;
  X x_prev = x;
  while (!reached(t, opt.t_end) && !run.stopped()) {
    const double limit = std::min(opt.t_end, run.next_output_time());
    const bool clamped = t + dt > limit;
    double dt_try = clamped ? limit - t : dt;
    const double t_old = t;
    if (events) x_prev = x;
    if (try_step(x, t, dt_try)) {
      if (clamped) t = limit;  // land exactly on the output time or t_end
      if (events) {
        const SubStep<X> sub{run.rhs<X>(), x_prev, t_old, opt.rtol, opt.atol};
        if (run.handle_events(t_old, x_prev.data(), t, x.data(), interpolator(sub))) restart();
      }
      run.stabilize(x.data(), t);
      run.reset_rejections();
      run.accepted(t_old, t, x.data(), [](double, double*) {});
      dt = clamped ? std::max(dt, dt_try) : dt_try;
    } else {
      run.rejected(t, dt_try);
      dt = dt_try;
    }
  }
}

/// Estimates ρ, the largest |eigenvalue| of ∂f/∂x at the end state x
/// (stiffness.cpp): sets report.stiffness_rho and warns when the final step
/// size h satisfies h ρ > 1.
void check_stiffness(const System& system, const StateVector& x, double t, double step, RunReport& report);

}  // namespace lagrangian::detail
