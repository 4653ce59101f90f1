// The stiffness diagnostic of a finished run.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <optional>
#include <sstream>
#include <string>

#include "lagrangian/integrate/detail/explicit_loops.hpp"
#include "loops.hpp"

namespace lagrangian::detail {

namespace {

/// ρ ≈ √(‖J²v‖/‖v‖) after 20 power iterations on J² (J² turns a pair of
/// oscillatory eigenvalues ±iω into the real −ω², so the iteration
/// settles); J v by central differences of f. None when f cannot be
/// evaluated near x.
std::optional<double> largest_rate(const System& system, const StateVector& x, double t) {
  const std::size_t size = x.size();
  StateVector v = x, w = x, xp = x, xm = x, fp = x, fm = x;
  for (std::size_t i = 0; i < size; ++i) v[i] = 1.0 + 0.1 * static_cast<double>(i % 7);
  double xnorm = 0;
  for (double c : x) xnorm = std::max(xnorm, std::abs(c));
  auto norm = [](const StateVector& a) {
    double s = 0;
    for (double c : a) s += c * c;
    return std::sqrt(s);
  };
  auto apply = [&](const StateVector& in, StateVector& out) {  // not counted as the run's work
    const double eps = 1e-6 * (1.0 + xnorm) / std::max(norm(in), 1e-300);
    for (std::size_t i = 0; i < size; ++i) {
      xp[i] = x[i] + eps * in[i];
      xm[i] = x[i] - eps * in[i];
    }
    system.rhs(xp.data(), fp.data(), t);
    system.rhs(xm.data(), fm.data(), t);
    for (std::size_t i = 0; i < size; ++i) out[i] = (fp[i] - fm[i]) / (2 * eps);
  };
  double rho2 = 0;
  try {
    for (int it = 0; it < 20; ++it) {
      const double nv = norm(v);
      if (!(nv > 0) || !std::isfinite(nv)) return std::nullopt;
      for (auto& c : v) c /= nv;
      apply(v, w);
      apply(w, v);
      rho2 = norm(v);
    }
  } catch (const std::exception&) {
    return std::nullopt;  // a diagnostic only: a state where f cannot be evaluated gives none
  }
  if (!std::isfinite(rho2)) return std::nullopt;
  return std::sqrt(rho2);
}

/// Accepted steps and evaluations of f of the controlled stepper
/// `Controlled` from (x, t) over [t, t + span] at (rtol, atol), on f alone
/// as the system has it after the run (its contacts as they ended; no
/// events, no constraint projection), starting with the step dt; capped
/// when `cap` steps do not reach the end; failed when f fails, the state
/// turns non-finite or the step underflows.
template <class Controlled>
ProbeCost steps_over(const System& system, StateVector x, double t, double span, double dt, double rtol, double atol,
                     std::uint64_t cap) {
  Controlled stepper = make_controlled<Controlled>(atol, rtol);
  ProbeCost cost;
  auto f = [&system, &cost](const StateVector& y, StateVector& dydt, double tt) {
    ++cost.evaluations;
    system.rhs(y.data(), dydt.data(), tt);
  };
  const double t_end = t + span;
  try {
    cost.steps = advance_controlled(stepper, f, x, t, t_end, dt, cap);
    if (cost.steps >= cap)
      cost.outcome = ProbeCost::Outcome::capped;
    else if (t >= t_end && state_finite(x))
      cost.outcome = ProbeCost::Outcome::reached;
  } catch (const std::exception&) {
    cost.outcome = ProbeCost::Outcome::failed;
  }
  return cost;
}

/// The growth exponent 1/(p+1) of the steps with 1/tol for the embedded
/// pairs (a step with local error h^(p+1) per unit tolerance, p the error
/// order of method_table()); none for Bulirsch–Stoer, which changes its
/// order with the tolerance.
std::optional<double> growth_exponent(Method method) {
  const int p = method_info(method).error_order;
  if (p == 0) return std::nullopt;
  return 1.0 / (p + 1);
}

ProbeCost steps_over(Method method, const System& system, const StateVector& x, double t, double span,
                     double dt, double rtol, double atol, std::uint64_t cap) {
  using V = StateVector;
  if (method == Method::dopri5)
    return steps_over<odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<V>>>(system, x, t, span, dt, rtol,
                                                                                      atol, cap);
  if (method == Method::cash_karp54)
    return steps_over<odeint::controlled_runge_kutta<odeint::runge_kutta_cash_karp54<V>>>(system, x, t, span, dt,
                                                                                          rtol, atol, cap);
  if (method == Method::fehlberg78)
    return steps_over<odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<V>>>(system, x, t, span, dt,
                                                                                         rtol, atol, cap);
  return {};
}

}  // namespace

/// The warning is considered when the step size h at the end satisfies
/// h ρ > 1 (an explicit Runge–Kutta method is stable only for h ρ below a
/// few units), and given only when two measurements on the run's first
/// stretch, min(100 h, t_end − t0) from the initial state, confirm it:
///
/// 1. Stability, not accuracy, set the steps: the same method at the run's
///    tolerances and at tolerances 100 times tighter. Steps set by accuracy
///    grow as 100^(1/(p+1)) for an embedded pair whose local error is
///    O(h^(p+1)) (2.5× for dopri5 and cash_karp54, 1.8× for fehlberg78);
///    steps set by stability do not grow. Fewer than 1.5 times as many
///    steps confirm it. The test starts from the initial state, not the
///    end: there the fast modes carry the run's own error, at the run's
///    tolerance, which tighter tolerances would have to resolve (the stiff
///    springs of stability_stiff.cpp: 1.25× from the start, 2.5× from the
///    end, 1.001× for the whole run). bulirsch_stoer raises its order rather
///    than shrinking its step at a tighter tolerance (1.0–1.16× whether
///    stiff or not), so dopri5 makes its test, as it does for
///    gauss_radau15. Where this test cannot run (rtol below 1e-12), the
///    warning says the steps "may" have been limited.
/// 2. The implicit method is cheaper: rosenbrock4, as the driver runs it
///    (its Jacobian by central differences, its steps landing on the run's
///    sample times), integrates the whole run again from the initial state
///    at the run's tolerances, on f alone, and must use fewer evaluations of
///    f (its Jacobians' included) than the run did. Steady motion passes
///    test 1 and fails this one: on a conical pendulum's circular orbit f is
///    constant along the solution, round-off alone excites the orbit's own
///    oscillation, and that holds dopri5's steps at h ρ ≈ 2 whatever the
///    tolerance, yet dopri5 needs 26 steps for 10 s and rosenbrock4,
///    stopping at every sample, a thousand. A stiff problem is one an
///    implicit method integrates for less work; only a measurement says so.
///    The probe stops once it has used as many evaluations as the run, so
///    it never costs more than the run's own evaluations (plus its LU
///    factorizations); it is made only for states of at most
///    kMaxImplicitProbe values, its Jacobian being dense.
void check_stiffness(const System& system, const StateVector& x, double t, double step, const StateVector& x0,
                     const SimulationOptions& options, RunReport& report) {
  const std::optional<double> rho = largest_rate(system, x, t);
  if (!rho) return;
  report.stiffness_rho = *rho;
  const double h_rho = step * *rho;
  if (!(h_rho > 1.0)) return;
  constexpr double kConfirm = 1.5;
  constexpr std::uint64_t kCap = 20000;
  constexpr double kTighter = 100;
  constexpr std::size_t kMaxImplicitProbe = 400;
  // Bulirsch–Stoer raises its order rather than shrinking its step at a
  // tighter tolerance, and gauss_radau15's steps are set by its last term,
  // not a tolerance per step: dopri5 makes the test for both.
  const bool stand_in = options.method == Method::bulirsch_stoer || options.method == Method::gauss_radau15;
  const Method probe = stand_in ? Method::dopri5 : options.method;
  const std::optional<double> exponent = growth_exponent(probe);
  if (!exponent) return;
  const double span = std::min(100 * step, options.t_end - options.t0);
  const ProbeCost same = steps_over(probe, system, x0, options.t0, span, step, options.rtol, options.atol, kCap);
  if (same.outcome == ProbeCost::Outcome::failed || same.steps == 0) return;  // nothing measured: no claim
  std::optional<double> growth;
  if (options.rtol / kTighter >= 1e-14) {
    const ProbeCost tight = steps_over(probe, system, x0, options.t0, span, step, options.rtol / kTighter,
                                       options.atol / kTighter, kCap);
    // A tight run stopped at the cap grew by at least the cap's ratio.
    if (tight.outcome != ProbeCost::Outcome::failed)
      growth = static_cast<double>(tight.steps) / static_cast<double>(same.steps);
  }
  if (growth && *growth >= kConfirm) return;  // accuracy set the steps: not stiff at this tolerance
  // Would the implicit method have been cheaper? Measured, not assumed.
  if (x0.size() > kMaxImplicitProbe) return;
  const std::uint64_t explicit_cost = report.rhs_evaluations;
  const ProbeCost implicit = rosenbrock4_probe(system, x0, options.t0, report.t_final, options.dt, options.rtol,
                                               options.atol, options.t0, options.output_interval, explicit_cost);
  if (implicit.outcome != ProbeCost::Outcome::reached || implicit.evaluations >= explicit_cost) return;
  std::ostringstream os;
  os.precision(3);
  os << "stiff problem: the " << report.steps << " steps (" << step << " s at the end) ";
  if (growth) {
    os << "were limited by stability, not accuracy: over the run's first " << span << " s, tolerances " << kTighter
       << " times tighter took " << to_string(probe);
    if (probe != options.method)
      os << " (standing in for " << to_string(options.method)
         << (options.method == Method::bulirsch_stoer ? ", which raises its order rather than shrinking its step)"
                                                : ", whose steps no tolerance per step sets)");
    os << " " << *growth << " times as many steps, where steps set by accuracy would take about "
       << std::pow(kTighter, *exponent) << " times as many (largest |eigenvalue| of df/dx about " << *rho
       << " 1/s, step x rho = " << h_rho << ")";
  } else {
    os << "may have been limited by stability rather than accuracy (largest |eigenvalue| of df/dx about " << *rho
       << " 1/s, step x rho = " << h_rho << "; tolerances 100 times tighter are below what the test resolves)";
  }
  os << "; the implicit rosenbrock4, run over the same interval at the same tolerances and sample times, took "
     << implicit.steps << " steps and " << implicit.evaluations << " evaluations of f (its Jacobians included) against "
     << to_string(options.method) << "'s " << report.steps << " steps and " << explicit_cost
     << ": it is not limited this way";
  report.warnings.push_back(os.str());
}

}  // namespace lagrangian::detail
