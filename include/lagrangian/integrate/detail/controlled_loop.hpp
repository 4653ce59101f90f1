#pragma once
// The driver's loop for controlled steppers without dense output, and the
// sub-step it locates events on.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "lagrangian/integrate/detail/run.hpp"

namespace lagrangian::detail {

/// True when every value of the state x is finite (no branch per value).
template <class X>
bool state_finite(const X& x) {
  bool finite = true;
  for (const double v : x) finite &= std::isfinite(v);
  return finite;
}

/// True for a right-hand side the compiler can inline into the stepper's
/// stages (inlined.hpp), false for the library's, which calls through the
/// System's vtable. Only an inlined one gains from quiet_steps(): with the
/// bookkeeping out of the loop the compiler keeps q̈'s invariants out of the
/// stages; through the vtable there is nothing to keep, and the library's
/// loops measured up to 2 % slower with them (docs/performance.md).
template <class Rhs, class X>
inline constexpr bool inlined_rhs_v = !std::is_same_v<Rhs, CountedRhs<X>>;

/// What quiet_steps() did: how many steps it accepted, and whether one was
/// rejected.
struct QuietSteps {
  std::uint64_t accepted = 0;
  double t_old = 0;  ///< start of the last accepted step
  bool rejected = false;
};

/// Adaptive steps in a row that need no hook and end short of `limit` and
/// of the next sample, taken in a function of their own with only a
/// finiteness test each: with the bookkeeping kept out and every call
/// inlined (flatten), the compiler keeps the right-hand side's loop
/// invariants out of the stages. try_step(x, t, dt) as in
/// run_controlled_loop. A rejection or a non-finite state ends the steps.
template <class X, class TryStep>
[[gnu::flatten]] QuietSteps quiet_steps(const Run& run, X& x, double& t, double& dt, double limit, TryStep& try_step) {
  QuietSteps q;
  q.t_old = t;
  const std::uint64_t cap = run.steps_left();
  while (q.accepted < cap && t + dt < limit && run.no_sample_due(t + dt)) {
    const double t_start = t;
    double dt_try = dt;
    if (!try_step(x, t, dt_try)) {
      q.rejected = true;
      dt = dt_try;
      break;
    }
    q.t_old = t_start;
    dt = dt_try;
    ++q.accepted;
    if (!state_finite(x)) break;
  }
  return q;
}

/// quiet_steps() and their bookkeeping; true when any step was attempted.
template <class X, class TryStep>
bool run_quiet_steps(Run& run, X& x, double& t, double& dt, double limit, TryStep& try_step) {
  const QuietSteps q = quiet_steps(run, x, t, dt, limit, try_step);
  if (q.accepted > 0) {
    run.reset_rejections();
    run.accepted_in_a_row(q.accepted, q.t_old, t, x.data());
  }
  if (q.rejected) run.rejected(t, dt);
  return q.accepted > 0 || q.rejected;
}

/// The state inside an accepted step for steppers without dense output:
/// Runge–Kutta–Fehlberg 7(8) from the step's start (t0, x0) to t, with its
/// error controlled to the run's rtol and atol (used only while locating an
/// event). A single uncontrolled step would do for short steps, but
/// Bulirsch–Stoer takes steps of a large fraction of an orbit, over which one
/// 7(8) step is far less accurate than the tolerance the run asked for (the
/// work-precision bench found this: Kepler with periapsis events lost up to
/// three orders of magnitude). Rhs is f(x, t) as Odeint calls it. Defined in
/// explicit_loops.hpp.
template <class X, class Rhs = CountedRhs<X>>
struct SubStep {
  Rhs rhs;
  const X& x0;
  double t0;
  double rtol, atol;
  void operator()(double t, double* out) const;
};

/// The loop for a controlled stepper without dense output: `try_step(x, t,
/// dt)` attempts one step (true: accepted, x and t advanced, dt the next
/// step; false: dt reduced), `restart()` is called after an event moved the
/// state. Steps are shortened to land on output times and on t_end; events
/// are located on a SubStep of `rhs` from the step's start.
template <class X, class Rhs, class TryStep, class Restart>
void run_controlled_loop(Run& run, X& x, const Rhs& rhs, TryStep try_step, Restart&& restart) {
  const SimulationOptions& opt = run.options();
  const bool events = run.has_events();
  double t = opt.t0;
  double dt = opt.dt;
  X x_prev = x;
  // Steps that need no hook (no events, no constraints): quiet_steps().
  const bool quiet = !events && !run.has_constraints();
  while (!reached(t, opt.t_end) && !run.stopped()) {
    if constexpr (inlined_rhs_v<Rhs, X>) {
      if (quiet && run_quiet_steps(run, x, t, dt, std::min(opt.t_end, run.next_output_time()), try_step)) continue;
    }
    const double limit = std::min(opt.t_end, run.next_output_time());
    const bool clamped = t + dt > limit;
    double dt_try = clamped ? limit - t : dt;
    const double t_old = t;
    if (events) x_prev = x;
    if (try_step(x, t, dt_try)) {
      if (clamped) t = limit;  // land exactly on the output time or t_end
      if (events) {
        const SubStep<X, Rhs> sub{rhs, x_prev, t_old, opt.rtol, opt.atol};
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

}  // namespace lagrangian::detail
