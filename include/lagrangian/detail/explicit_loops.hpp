#pragma once
// The explicit Runge–Kutta loops of the driver: dopri5 with dense output,
// rk4 on a fixed grid, and Odeint's controlled steppers without dense
// output (cash_karp54, fehlberg78, Bulirsch–Stoer), as templates on the
// Odeint state X; compiled for each state type in explicit_*.cpp.

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>

#include <boost/numeric/odeint/stepper/bulirsch_stoer.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4_classic.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_cash_karp54.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include "lagrangian/errors.hpp"
#include "loops.hpp"

namespace lagrangian::detail {

namespace odeint = boost::numeric::odeint;

// Odeint's controlled stepper `Controlled` with the run's tolerances. (Its
// constructor copies a default-constructed stepper whose scratch arrays are
// not initialised yet; g++ warns of that copy once it is inlined.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
template <class Controlled>
Controlled make_controlled(double atol, double rtol) {
  if constexpr (requires { typename Controlled::error_checker_type; }) {
    return Controlled{typename Controlled::error_checker_type(atol, rtol)};
  } else {
    return Controlled(atol, rtol);  // Bulirsch–Stoer
  }
}
#pragma GCC diagnostic pop

template <class X>
void SubStep<X>::operator()(double t, double* out) const {
  if (t == t0) {
    std::copy(x0.begin(), x0.end(), out);
    return;
  }
  using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<X>>;
  Controlled stepper = make_controlled<Controlled>(atol, rtol);
  X x = x0;
  double tc = t0, dt = t - t0;
  while (tc < t) {
    const bool last = tc + dt >= t;
    double dt_try = last ? t - tc : dt;
    if (stepper.try_step(rhs, x, tc, dt_try) == odeint::success) {
      if (last) tc = t;
      dt = dt_try;
    } else {
      dt = dt_try;
      if (!(dt > 0) || tc + dt == tc) break;  // underflow: keep what we have
    }
  }
  std::copy(x.begin(), x.end(), out);
}

namespace explicit_loops {



// Odeint's controlled stepper without dense output in the common loop.
// No state is carried between steps except by Bulirsch–Stoer, which
// restarts after an event.
template <class Controlled, class X>
void run_controlled(Run& run, X& x) {
  const CountedRhs<X> rhs = run.rhs<X>();
  Controlled stepper = make_controlled<Controlled>(run.options().atol, run.options().rtol);
  run_controlled_loop(
      run, x, [&](X& xs, double& t, double& dt) { return stepper.try_step(rhs, xs, t, dt) == odeint::success; },
      [&] {
        if constexpr (requires { stepper.reset(); }) stepper.reset();
      });
}

template <class X>
void run_dopri5(Run& run, X& x) {
  const SimulationOptions& opt = run.options();
  const CountedRhs<X> rhs = run.rhs<X>();
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
  while (!reached(t, opt.t_end) && !run.stopped()) {
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

template <class X>
void run_rk4(Run& run, X& x) {
  const SimulationOptions& opt = run.options();
  const CountedRhs<X> rhs = run.rhs<X>();
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
  while (!reached(t, opt.t_end) && !run.stopped()) {
    const double t_grid = opt.t0 + static_cast<double>(k + 1) * opt.dt;
    const double t_next = std::min(t_grid, opt.t_end);
    const double t_old = t;
    if (keep_start) x_prev = x;
    stepper.do_step(rhs, x, t, t_next - t);
    t = t_next;
    const SubStep<X> sub{rhs, x_prev, t_old, opt.rtol, opt.atol};
    if (events) run.handle_events(t_old, x_prev.data(), t, x.data(), interpolator(sub));
    if (t >= t_grid) ++k;  // a step cut at an event leaves the grid point ahead
    run.stabilize(x.data(), t);
    run.accepted(t_old, t, x.data(), sub);
  }
}

}  // namespace explicit_loops

/// The explicit method options.method on the Odeint state X.
template <class X>
void run_explicit_on(Run& run, X& x) {
  namespace loops = explicit_loops;
  const std::string& m = run.options().method;
  if (m == "dopri5") {
    loops::run_dopri5(run, x);
  } else if (m == "rk4") {
    loops::run_rk4(run, x);
  } else if (m == "cash_karp54") {
    loops::run_controlled<odeint::controlled_runge_kutta<odeint::runge_kutta_cash_karp54<X>>>(run, x);
  } else if (m == "fehlberg78") {
    loops::run_controlled<odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<X>>>(run, x);
  } else if (m == "bulirsch_stoer") {
    loops::run_controlled<odeint::bulirsch_stoer<X>>(run, x);
  } else {
    throw OptionError("not an explicit Runge-Kutta method: '" + m + "'");
  }
}

/// run_explicit_on for the fixed state of 2N values, copying x in and out.
template <int N>
void run_explicit_fixed(Run& run, StateVector& x) {
  std::array<double, 2 * N> xa;
  std::copy(x.begin(), x.end(), xa.begin());
  run_explicit_on(run, xa);
  std::copy(xa.begin(), xa.end(), x.begin());
}

}  // namespace lagrangian::detail
