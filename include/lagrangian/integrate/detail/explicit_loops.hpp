#pragma once
// The explicit Runge–Kutta loops of the driver: dopri5 with dense output,
// rk4 on a fixed grid, and Odeint's controlled steppers without dense
// output (cash_karp54, fehlberg78, Bulirsch–Stoer), as templates on the
// Odeint state X and on the right-hand side Rhs. The library compiles them
// once per state size with f reached through the System's vtable
// (CountedRhs; src/integrate/explicit_*.cpp); a system may compile them with
// its own f inlined (DirectRhs, System::integrate_inlined).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include <boost/numeric/odeint/stepper/bulirsch_stoer.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4_classic.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_cash_karp54.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/detail/controlled_loop.hpp"
#include "lagrangian/integrate/detail/run.hpp"

namespace lagrangian::detail {

namespace odeint = boost::numeric::odeint;

/// Odeint's controlled stepper `Controlled` with the run's tolerances. Its
/// constructor copies the stepper it is given, by default a temporary whose
/// scratch arrays are indeterminate, which g++ reports as a use of
/// uninitialised values wherever the copy is inlined (user programs
/// included); the prototype here has static storage, so it is zeroed.
template <class Controlled>
Controlled make_controlled(double atol, double rtol) {
  if constexpr (requires { typename Controlled::error_checker_type; }) {
    static const typename Controlled::stepper_type prototype{};
    return Controlled(typename Controlled::error_checker_type(atol, rtol), typename Controlled::step_adjuster_type(),
                      prototype);
  } else {
    return Controlled(atol, rtol);  // Bulirsch–Stoer
  }
}

/// Advances (x, t) to t_end with the controlled stepper's accepted steps,
/// the first tried with dt, the last shortened to land on t_end; returns how
/// many were accepted. Stops short of t_end when the step underflows or
/// after `cap` accepted steps.
template <class Controlled, class Rhs, class X>
std::uint64_t advance_controlled(Controlled& stepper, const Rhs& rhs, X& x, double& t, double t_end, double dt,
                                 std::uint64_t cap) {
  std::uint64_t steps = 0;
  while (t < t_end && steps < cap) {
    const bool last = t + dt >= t_end;
    double dt_try = last ? t_end - t : dt;
    if (stepper.try_step(rhs, x, t, dt_try) == odeint::success) {
      ++steps;
      if (last) t = t_end;
    }
    dt = dt_try;
    if (t < t_end && (!(dt > 0) || t + dt == t)) break;  // underflow
  }
  return steps;
}

template <class X, class Rhs>
void SubStep<X, Rhs>::operator()(double t, double* out) const {
  if (t == t0) {
    std::copy(x0.begin(), x0.end(), out);
    return;
  }
  using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<X>>;
  Controlled stepper = make_controlled<Controlled>(atol, rtol);
  X x = x0;
  double tc = t0;
  // An underflow keeps what was reached.
  advance_controlled(stepper, rhs, x, tc, t, t - t0, std::numeric_limits<std::uint64_t>::max());
  std::copy(x.begin(), x.end(), out);
}

namespace explicit_loops {



// Odeint's controlled stepper without dense output in the common loop.
// No state is carried between steps except by Bulirsch–Stoer, which
// restarts after an event.
template <class Controlled, class X, class Rhs>
void controlled_body(Run& run, X& x, const Rhs rhs) {
  Controlled stepper = make_controlled<Controlled>(run.options().atol, run.options().rtol);
  run_controlled_loop(
      run, x, rhs, [&](X& xs, double& t, double& dt) { return stepper.try_step(rhs, xs, t, dt) == odeint::success; },
      [&] {
        if constexpr (requires { stepper.reset(); }) stepper.reset();
      });
}

// Through the vtable (CountedRhs) each f(x, t) of a stage is a call. Left
// as functions of their own, Odeint's stage sums reload their operands after
// each call and test the arrays for overlap before each vectorised sum;
// flattened into the loop, the arrays are the loop's own and known apart
// (measured in docs/performance.md). With f inlined (DirectRhs) flattening
// would copy f into every stage and is not done.
template <class Controlled, class X, class Rhs>
[[gnu::flatten]] void controlled_flat(Run& run, X& x, const Rhs rhs) {
  controlled_body<Controlled>(run, x, rhs);
}
template <class Controlled, class X, class Rhs>
void run_controlled(Run& run, X& x, const Rhs rhs) {
  if constexpr (inlined_rhs_v<Rhs, X>) {
    controlled_body<Controlled>(run, x, rhs);
  } else {
    controlled_flat<Controlled>(run, x, rhs);
  }
}

template <class X, class Rhs>
void dopri5_body(Run& run, X& x, const Rhs rhs) {
  const SimulationOptions& opt = run.options();
  using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<X>>;
  Controlled stepper{typename Controlled::error_checker_type(opt.atol, opt.rtol)};
  const bool events = run.has_events();
  const bool moves = events || run.has_constraints();  // the state may move after a step
  X dxdt = x, x_old = x, dxdt_old = x, x_step = x, dxdt_step = x, buf = x;
  double t = opt.t0;
  double dt = opt.dt;
  // Samples between steps and event location need the step's start.
  const bool dense = opt.output_interval > 0 || events;
  rhs(x, dxdt, t);
  auto fsal_step = [&](X& xs, double& ts, double& dts) {
    return stepper.try_step(rhs, xs, dxdt, ts, dts) == odeint::success;
  };
  const bool quiet = !moves;  // no hook after a step: quiet_steps()
  while (!reached(t, opt.t_end) && !run.stopped()) {
    if constexpr (inlined_rhs_v<Rhs, X>) {
      if (quiet && run_quiet_steps(run, x, t, dt, opt.t_end, fsal_step)) continue;
    }
    const bool clamped = t + dt > opt.t_end;
    double dt_try = clamped ? opt.t_end - t : dt;
    if (dense) {
      x_old = x;
      dxdt_old = dxdt;
    }
    const double t_old = t;
    if (stepper.try_step(rhs, x, dxdt, t, dt_try) == odeint::success) {
      if (clamped) t = opt.t_end;
      run.reset_rejections();
      const double t_new = t;
      const X* x_new = &x;
      const X* deriv_new = &dxdt;
      auto interpolate = [&](double to, double* out) {
        stepper.stepper().calc_state(to, buf, x_old, dxdt_old, t_old, *x_new, *deriv_new, t_new);
        std::copy(buf.begin(), buf.end(), out);
      };
      if (moves) {
        if (dense) {
          // The step's own end point, for its dense output after x moves.
          x_step = x;
          dxdt_step = dxdt;
          x_new = &x_step;
          deriv_new = &dxdt_step;
        }
        bool changed = run.handle_events(t_old, x_old.data(), t, x.data(), interpolator(interpolate));
        changed = run.stabilize(x.data(), t) || changed;
        if (changed) {
          rhs(x, dxdt, t);  // FSAL: the moved state needs its own derivative
          run.extra_rhs_evaluation();
        }
      }
      run.accepted(t_old, t, x.data(), interpolate);
      dt = clamped ? std::max(dt, dt_try) : dt_try;
    } else {
      run.rejected(t, dt_try);
      dt = dt_try;
    }
  }
}

// Flattened through the vtable only, as controlled_flat.
template <class X, class Rhs>
[[gnu::flatten]] void dopri5_flat(Run& run, X& x, const Rhs rhs) {
  dopri5_body(run, x, rhs);
}
template <class X, class Rhs>
void run_dopri5(Run& run, X& x, const Rhs rhs) {
  if constexpr (inlined_rhs_v<Rhs, X>) {
    dopri5_body(run, x, rhs);
  } else {
    dopri5_flat(run, x, rhs);
  }
}

/// rk4's quiet_steps(): whole grid steps t0 + k dt (k advanced) that end
/// short of t_end and of the next sample; returns how many, t_old the start
/// of the last one.
template <class Stepper, class Rhs, class X>
[[gnu::flatten]] std::uint64_t quiet_grid_steps(const Run& run, Stepper& stepper, const Rhs& rhs, X& x, double& t,
                                                std::uint64_t& k, double& t_old) {
  const SimulationOptions& opt = run.options();
  const std::uint64_t cap = run.steps_left();
  std::uint64_t m = 0;
  while (m < cap) {
    const double t_grid = opt.t0 + static_cast<double>(k + 1) * opt.dt;
    if (!(t_grid < opt.t_end) || !run.no_sample_due(t_grid)) break;
    t_old = t;
    stepper.do_step(rhs, x, t, t_grid - t);
    t = t_grid;
    ++k;
    ++m;
    if (!state_finite(x)) break;
  }
  return m;
}

template <class X, class Rhs>
void run_rk4(Run& run, X& x, const Rhs rhs) {
  const SimulationOptions& opt = run.options();
  odeint::runge_kutta4_classic<X> stepper;
  const bool events = run.has_events();
  // Samples between grid points and event location start from the step's
  // beginning (SubStep): rk4 has no dense output of its own.
  const bool keep_start = events || opt.output_interval > 0;
  // Fixed steps of opt.dt: the k-th step ends at t0 + k dt (no accumulated
  // rounding). The step asked for is the step taken: only t_end, or an
  // event inside the step, ends one early; output times never do.
  std::uint64_t k = 0;
  double t = opt.t0;
  X x_prev = x;
  // Steps that need no hook (no events, no constraints): quiet_grid_steps().
  const bool quiet = !events && !run.has_constraints();
  while (!reached(t, opt.t_end) && !run.stopped()) {
    if constexpr (inlined_rhs_v<Rhs, X>) {
      if (quiet) {
        double t_old = t;
        const std::uint64_t m = quiet_grid_steps(run, stepper, rhs, x, t, k, t_old);
        if (m > 0) {
          run.accepted_in_a_row(m, t_old, t, x.data());
          continue;
        }
      }
    }
    const double t_grid = opt.t0 + static_cast<double>(k + 1) * opt.dt;
    const double t_next = std::min(t_grid, opt.t_end);
    const double t_old = t;
    if (keep_start) x_prev = x;
    stepper.do_step(rhs, x, t, t_next - t);
    t = t_next;
    const SubStep<X, Rhs> sub{rhs, x_prev, t_old, opt.rtol, opt.atol};
    if (events) run.handle_events(t_old, x_prev.data(), t, x.data(), interpolator(sub));
    if (t >= t_grid) ++k;  // a step cut at an event leaves the grid point ahead
    run.stabilize(x.data(), t);
    run.accepted(t_old, t, x.data(), sub);
  }
}

}  // namespace explicit_loops

/// The explicit method options.method on the Odeint state X, with the
/// system's f(x, t) called as `rhs(x, dxdt, t)`.
template <class X, class Rhs>
void run_explicit_on(Run& run, X& x, const Rhs& rhs) {
  namespace loops = explicit_loops;
  switch (const Method m = run.options().method) {
    case Method::dopri5: loops::run_dopri5(run, x, rhs); break;
    case Method::rk4: loops::run_rk4(run, x, rhs); break;
    case Method::cash_karp54:
      loops::run_controlled<odeint::controlled_runge_kutta<odeint::runge_kutta_cash_karp54<X>>>(run, x, rhs);
      break;
    case Method::fehlberg78:
      loops::run_controlled<odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<X>>>(run, x, rhs);
      break;
    case Method::bulirsch_stoer: loops::run_controlled<odeint::bulirsch_stoer<X>>(run, x, rhs); break;
    default: throw OptionError("not an explicit Runge-Kutta method: '" + std::string(to_string(m)) + "'");
  }
}

/// f(x, t) of the system S called directly, S::rhs rather than through the
/// vtable, so that it is inlined into the stepper's stages; counts
/// evaluations as CountedRhs does.
template <class S, class X>
struct DirectRhs {
  const S* system;
  std::uint64_t* evaluations;
  void operator()(const X& x, X& dxdt, double t) const {
    system->S::rhs(x.data(), dxdt.data(), t);
    ++*evaluations;
  }
};

/// run_explicit_on for the fixed state of 2N values (x, 2N values, copied
/// in and out), with f(x, t) called as `rhs`.
template <int N, class Rhs>
void run_explicit_array(Run& run, StateVector& x, const Rhs& rhs) {
  std::array<double, 2 * N> xa;
  std::copy(x.begin(), x.end(), xa.begin());
  run_explicit_on(run, xa, rhs);
  std::copy(xa.begin(), xa.end(), x.begin());
}

/// run_explicit for the fixed state of 2N values, f through the vtable.
template <int N>
void run_explicit_fixed(Run& run, StateVector& x) {
  run_explicit_array<N>(run, x, run.rhs<std::array<double, 2 * N>>());
}

}  // namespace lagrangian::detail
