#pragma once
// The explicit Runge–Kutta loops of simulate(): dopri5 with dense output,
// rk4 on a fixed grid, and Odeint's controlled steppers without dense
// output (cash_karp54, fehlberg78, Bulirsch–Stoer).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <boost/numeric/odeint/stepper/bulirsch_stoer.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_cash_karp54.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include "lagrangian/detail/first_order_system.hpp"
#include "lagrangian/detail/run_state.hpp"
#include "lagrangian/report.hpp"

namespace lagrangian::detail {

/// True when t has reached t_end up to rounding.
inline bool reached(double t, double t_end) {
  return t_end - t <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(t), std::abs(t_end));
}

/// The explicit Runge–Kutta loops (dopri5, rk4, cash_karp54, fehlberg78,
/// Bulirsch–Stoer) run in a function of their own, which works on its own
/// copies of the state, the stepper and (LoopModel) the model: the compiler
/// then knows that no store in the loop can change the model's parameters or
/// the stepper's coefficients, and keeps them out of the loop, as it does for
/// a hand-written Odeint program. For models that supply q̈ themselves and
/// have no constraints or events, every call in that function is inlined
/// (flatten), the model's `accelerations` in every stage included, whatever
/// the compiler's budget for inlining in the translation unit has left; the
/// rarely taken paths (samples, errors) are marked noinline and stay calls.
/// The instructions per run against raw Odeint with the same hand-coded q̈
/// are in docs/performance.md.
template <class M>
inline constexpr bool flat_loop_v =
    has_explicit_accelerations_v<M> && !has_constraints_v<M> && unilateral_count_v<M> == 0 && event_count_v<M> == 0;

template <class Loop>
[[gnu::noinline]] void run_loop(const Loop& loop) {
  loop();
}

template <class Loop>
[[gnu::noinline, gnu::flatten]] void run_loop_flat(const Loop& loop) {
  loop();
}

template <class M, class Loop>
void run_out_of_line(const Loop& loop) {
  if constexpr (flat_loop_v<M>) {
    run_loop_flat(loop);
  } else {
    run_loop(loop);
  }
}

/// Odeint's controlled stepper `Controlled` with the run's tolerances.
/// (Its constructor copies a default-constructed stepper whose scratch arrays
/// are not initialised yet; g++ warns of that copy once it is inlined.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
template <class Controlled>
Controlled make_controlled(const SimulationOptions& opt) {
  if constexpr (requires { typename Controlled::error_checker_type; }) {
    return Controlled{typename Controlled::error_checker_type(opt.atol, opt.rtol)};
  } else {
    return Controlled(opt.atol, opt.rtol);  // Bulirsch–Stoer
  }
}
#pragma GCC diagnostic pop

/// Loop for an Odeint controlled stepper without dense output: steps are
/// shortened to land on output times and on t_end.
template <class Controlled, class M, class Observer, class X>
void run_controlled(FirstOrderSystem<M> sys, X& x_io, const SimulationOptions& opt, RunState<M, Observer>& rs) {
  namespace odeint = boost::numeric::odeint;
  constexpr bool events = RunState<M, Observer>::has_events_v;
  Controlled stepper = make_controlled<Controlled>(opt);
  X x = x_io;
  double t = opt.t0;
  double dt = opt.dt;
  const LoopModel<M> loop_model(sys);
  [[maybe_unused]] X x_prev = x;
  while (!reached(t, opt.t_end) && !rs.stopped()) {
    const double limit = std::min(opt.t_end, rs.next_output_time());
    const bool clamped = t + dt > limit;
    double dt_try = clamped ? limit - t : dt;
    const double t_old = t;
    if constexpr (events) x_prev = x;
    if (stepper.try_step(InlinedSystem<M>{sys}, x, t, dt_try) == odeint::success) {
      if (clamped) t = limit;  // land exactly on the output time or t_end
      if constexpr (events) {
        // No state is carried between steps except by Bulirsch–Stoer, which restarts.
        if (rs.handle_events(t_old, x_prev.data(), t, x.data(), SubStep<M, X>{sys, x_prev, t_old, opt.rtol, opt.atol})) {
          if constexpr (requires { stepper.reset(); }) stepper.reset();
        }
      }
      rs.stabilize(x.data(), t);
      rs.reset_rejections();
      rs.accepted(t_old, t, x.data(), [](double, double*) {});
      dt = clamped ? std::max(dt, dt_try) : dt_try;
    } else {
      rs.rejected(t, dt_try);
      dt = dt_try;
    }
  }
  x_io = x;
}

template <class M, class Observer, class X>
void run_dopri5(FirstOrderSystem<M> sys, X& x_io, const SimulationOptions& opt, RunState<M, Observer>& rs) {
  X x = x_io;
  namespace odeint = boost::numeric::odeint;
  using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<X>>;
  constexpr bool events = RunState<M, Observer>::has_events_v;
  Controlled stepper{typename Controlled::error_checker_type(opt.atol, opt.rtol)};
  const LoopModel<M> loop_model(sys);
  X dxdt = x;
  X x_old = x;
  X dxdt_old = x;
  X x_step = x;
  X dxdt_step = x;
  X buf = x;
  double t = opt.t0;
  double dt = opt.dt;
  // Samples between steps and event location need the step's start.
  const bool dense = opt.output_interval > 0 || events;
  sys(x, dxdt, t);
  while (!reached(t, opt.t_end) && !rs.stopped()) {
    const bool clamped = t + dt > opt.t_end;
    double dt_try = clamped ? opt.t_end - t : dt;
    if (dense) {
      x_old = x;
      dxdt_old = dxdt;
    }
    const double t_old = t;
    if (stepper.try_step(sys, x, dxdt, t, dt_try) == odeint::success) {
      if (clamped) t = opt.t_end;
      rs.reset_rejections();
      const double t_new = t;
      const X* x_new = &x;
      const X* deriv_new = &dxdt;
      auto interpolate = [&](double to, double* out) {
        stepper.stepper().calc_state(to, buf, x_old, dxdt_old, t_old, *x_new, *deriv_new, t_new);
        std::copy(buf.begin(), buf.end(), out);
      };
      if constexpr (has_constraints_v<M> || events) {
        if (dense) {
          // The step's own end point, for its dense output after x moves.
          x_step = x;
          dxdt_step = dxdt;
          x_new = &x_step;
          deriv_new = &dxdt_step;
        }
        bool changed = rs.handle_events(t_old, x_old.data(), t, x.data(), interpolate);
        changed = rs.stabilize(x.data(), t) || changed;
        if (changed) {
          sys(x, dxdt, t);  // FSAL: the moved state needs its own derivative
          rs.extra_rhs_evaluation();
        }
      }
      rs.accepted(t_old, t, x.data(), interpolate);
      dt = clamped ? std::max(dt, dt_try) : dt_try;
    } else {
      rs.rejected(t, dt_try);
      dt = dt_try;
    }
  }
  x_io = x;
}

template <class M, class Observer, class X>
void run_rk4(FirstOrderSystem<M> sys, X& x_io, const SimulationOptions& opt, RunState<M, Observer>& rs) {
  X x = x_io;
  namespace odeint = boost::numeric::odeint;
  constexpr bool events = RunState<M, Observer>::has_events_v;
  odeint::runge_kutta4<X> stepper;
  const LoopModel<M> loop_model(sys);
  // Fixed steps of opt.dt; the k-th step ends at t0 + k dt (no accumulated
  // rounding); a step is shortened only to land on an output time or t_end.
  std::uint64_t k = 0;
  double t = opt.t0;
  [[maybe_unused]] X x_prev = x;
  while (!reached(t, opt.t_end) && !rs.stopped()) {
    const double t_grid = opt.t0 + static_cast<double>(k + 1) * opt.dt;
    const double t_next = std::min({t_grid, opt.t_end, rs.next_output_time()});
    const double t_old = t;
    if constexpr (events) x_prev = x;
    stepper.do_step(InlinedSystem<M>{sys}, x, t, t_next - t);
    t = t_next;
    if constexpr (events) rs.handle_events(t_old, x_prev.data(), t, x.data(), SubStep<M, X>{sys, x_prev, t_old, opt.rtol, opt.atol});
    if (t >= t_grid) ++k;  // a step cut at an event leaves the grid point ahead
    rs.stabilize(x.data(), t);
    rs.accepted(t_old, t, x.data(), [](double, double*) {});
  }
  x_io = x;
}

}  // namespace lagrangian::detail
