// The driver's loop for the 15th-order Gauss–Radau stepper (method
// "gauss_radau15", integrate/detail/gauss_radau.hpp): adaptive steps, dense output
// from the step's own polynomial for samples and events.

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lagrangian/integrate/detail/gauss_radau.hpp"
#include "lagrangian/errors.hpp"
#include "loops.hpp"

namespace lagrangian::detail {

namespace {
/// True when the events logged from index `from` on are all watched events
/// (logged or stopping the run), and there is one at least.
bool only_watched(const std::vector<EventRecord>& events, std::size_t from) {
  if (events.size() <= from) return false;
  for (std::size_t k = from; k < events.size(); ++k)
    if (events[k].kind != EventKind::watched && events[k].kind != EventKind::stop) return false;
  return true;
}

/// The loop on the stepper for N coordinates (N = 0: any).
template <int N>
void gauss_radau_loop(Run& run, StateVector& x, double eps) {
  const SimulationOptions& opt = run.options();
  System& system = run.system();
  std::uint64_t& evaluations = run.report().rhs_evaluations;
  const auto f = [&](const double* xs, double* dxdt, double t) {
    system.rhs(xs, dxdt, t);
    ++evaluations;
  };
  const FirstOrderRhs rhs = function_ref<void(const double*, double*, double)>(f);
  GaussRadau15<N> stepper(run.size());
  stepper.start(x.data());
  const bool moves = run.has_events() || run.has_constraints();
  StateVector x_old = x;
  double t = opt.t0;
  double dt = opt.dt;
  while (!reached(t, opt.t_end) && !run.stopped()) {
    const bool clamped = t + dt > opt.t_end;
    const double h = clamped ? opt.t_end - t : dt;
    typename GaussRadau15<N>::Attempt a;
    try {
      a = stepper.attempt(rhs, t, h);
    } catch (const DynamicsError&) {
      // f failed at a node of a step too long for the iteration, whose
      // states strayed (a polar radius through 0): a shorter step, unless
      // the step is already at the end of its resolution.
      if (!(0.25 * h > 1e-15 * std::max(1.0, std::abs(t)))) throw;
      run.rejected(t, 0.25 * h);
      dt = 0.25 * h;
      continue;
    }
    const double next = GaussRadau15<N>::next_step(h, a, eps);
    if (!a.converged || !(next >= GaussRadau15<N>::kSafety * h)) {
      // The iteration did not reach round-off (the step is too long for
      // it), or the error measure asks for a far shorter step: again.
      const double shorter = a.converged ? next : 0.25 * h;
      run.rejected(t, shorter);
      dt = shorter;
      continue;
    }
    const double t_old = t;
    if (moves) x_old = x;
    stepper.accept(h);
    t = clamped ? opt.t_end : t + h;
    stepper.state(x.data());
    // The last accepted step: this one, or the shorter one to an event in it.
    const auto interpolate = [&](double to, double* out) { stepper.dense((to - t_old) / stepper.dense_step(), out); };
    if (moves) {
      const double t_end = t;
      const std::size_t logged = run.report().events.size();
      const bool event = run.handle_events(t_old, x_old.data(), t, x.data(), interpolator(interpolate));
      // A watched event inside the step (a stop, or one only logged) leaves
      // the state where the polynomial has it and the equations of motion
      // as they were: the step is taken again, to the event, for the
      // method's order there and the state's compensation (the polynomial
      // inside a step is less accurate than its end). An impact, a rest or a
      // lift-off changes the state or the equations, and restarts the stepper.
      const bool watched = event && t > t_old && t < t_end && only_watched(run.report().events, logged);
      if (watched) {
        stepper.rewind();
        const double h_event = t - t_old;
        if (stepper.attempt(rhs, t_old, h_event).converged) {
          stepper.accept(h_event);
          stepper.state(x.data());
        } else {
          // A shorter step converges where the longer one did; should it
          // not, the run goes on from the event's state on the polynomial.
          stepper.moved(x.data(), false);
        }
      }
      const bool projected = run.stabilize(x.data(), t);
      // A projection moves the state by a rounding's worth and keeps the polynomial.
      if ((event && !watched) || projected) stepper.moved(x.data(), event && !watched);
    }
    run.reset_rejections();
    run.accepted(t_old, t, x.data(), interpolate);
    dt = clamped ? std::max(dt, next) : next;
  }
}

}  // namespace

void run_gauss_radau15(Run& run, StateVector& x) {
  const SimulationOptions& opt = run.options();
  const double eps = std::max(opt.rtol, kGaussRadauSmallestTolerance);
  if (opt.rtol < kGaussRadauSmallestTolerance) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "gauss_radau15 ran at rtol %.0e, not %.3g: its error measure |b6|/|qdd| is round-off below that "
                  "(the run's error is round-off from about 1e-9 on)",
                  kGaussRadauSmallestTolerance, opt.rtol);
    run.report().warnings.emplace_back(text);
  }
  switch (run.size()) {
    case 1: return gauss_radau_loop<1>(run, x, eps);
    case 2: return gauss_radau_loop<2>(run, x, eps);
    case 3: return gauss_radau_loop<3>(run, x, eps);
    case 4: return gauss_radau_loop<4>(run, x, eps);
    case 5: return gauss_radau_loop<5>(run, x, eps);
    case 6: return gauss_radau_loop<6>(run, x, eps);
    case 7: return gauss_radau_loop<7>(run, x, eps);
    case 8: return gauss_radau_loop<8>(run, x, eps);
    default: return gauss_radau_loop<0>(run, x, eps);
  }
}

}  // namespace lagrangian::detail
