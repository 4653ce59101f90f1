// The stiffness diagnostic of a finished run.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <optional>
#include <sstream>
#include <string>

#include "lagrangian/detail/explicit_loops.hpp"
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

/// Accepted steps of the controlled stepper `Controlled` from (x, t) over
/// [t, t + span] at (rtol, atol), on f alone as the system has it after the
/// run (its contacts as they ended; no events, no constraint projection),
/// starting with the step dt; `cap` when that many do not
/// reach the end; none when f fails, the state turns non-finite or the step
/// underflows.
template <class Controlled>
std::optional<std::uint64_t> steps_over(const System& system, StateVector x, double t, double span, double dt,
                                        double rtol, double atol, std::uint64_t cap) {
  Controlled stepper = make_controlled<Controlled>(atol, rtol);
  auto f = [&system](const StateVector& y, StateVector& dydt, double tt) { system.rhs(y.data(), dydt.data(), tt); };
  const double t_end = t + span;
  try {
    const std::uint64_t steps = advance_controlled(stepper, f, x, t, t_end, dt, cap);
    if (steps < cap && (t < t_end || !state_finite(x))) return std::nullopt;
    return steps;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

/// The growth exponent 1/(p+1) of the steps with 1/tol for the embedded
/// pairs (a step with local error h^(p+1) per unit tolerance); none for
/// Bulirsch–Stoer, which changes its order with the tolerance.
std::optional<double> growth_exponent(const std::string& method) {
  if (method == "dopri5" || method == "cash_karp54") return 1.0 / 5.0;
  if (method == "fehlberg78") return 1.0 / 8.0;
  return std::nullopt;
}

std::optional<std::uint64_t> steps_over(const std::string& method, const System& system, const StateVector& x,
                                        double t, double span, double dt, double rtol, double atol,
                                        std::uint64_t cap) {
  using V = StateVector;
  if (method == "dopri5")
    return steps_over<odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<V>>>(system, x, t, span, dt, rtol,
                                                                                      atol, cap);
  if (method == "cash_karp54")
    return steps_over<odeint::controlled_runge_kutta<odeint::runge_kutta_cash_karp54<V>>>(system, x, t, span, dt,
                                                                                          rtol, atol, cap);
  if (method == "fehlberg78")
    return steps_over<odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<V>>>(system, x, t, span, dt,
                                                                                         rtol, atol, cap);
  return std::nullopt;
}

}  // namespace

/// The warning is considered when the step size h at the end satisfies
/// h ρ > 1 (an explicit Runge–Kutta method is stable only for h ρ below a
/// few units), and given when a test confirms that stability, not accuracy,
/// set the steps: the same method integrates the run's first stretch,
/// min(100 h, t_end − t0) from the initial state, at the run's tolerances and
/// at tolerances 100 times tighter. Steps set by accuracy grow as
/// 100^(1/(p+1)) for an embedded pair whose local error is O(h^(p+1)) (2.5×
/// for dopri5 and cash_karp54, 1.8× for fehlberg78); steps set by stability
/// do not grow. Fewer than 1.5 times as many steps confirm stiffness. The
/// test starts from the initial state, not the end: there the fast modes
/// carry the run's own error, at the run's tolerance, which tighter
/// tolerances would have to resolve (the stiff springs of
/// stability_stiff.cpp: 1.25× from the start, 2.5× from the end, 1.001× for
/// the whole run). bulirsch_stoer raises its order rather than shrinking
/// its step at a tighter tolerance (1.0–1.16× whether stiff or not), so
/// dopri5 makes its test, as it does for gauss_radau15. Where the test cannot run (rtol below 1e-12, f
/// failing), the warning is given and says the steps may have been limited.
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
  // Bulirsch–Stoer raises its order rather than shrinking its step at a
  // tighter tolerance, and gauss_radau15's steps are set by its last term,
  // not a tolerance per step: dopri5 makes the test for both.
  const bool stand_in = options.method == "bulirsch_stoer" || options.method == "gauss_radau15";
  const std::string probe = stand_in ? "dopri5" : options.method;
  const std::optional<double> exponent = growth_exponent(probe);
  const double span = std::min(100 * step, options.t_end - options.t0);
  std::optional<double> growth;
  if (exponent && options.rtol / kTighter >= 1e-14) {
    const auto same = steps_over(probe, system, x0, options.t0, span, step, options.rtol, options.atol, kCap);
    const auto tight = steps_over(probe, system, x0, options.t0, span, step, options.rtol / kTighter,
                                  options.atol / kTighter, kCap);
    // A tight run stopped at the cap grew by at least the cap's ratio.
    if (same && tight && *same > 0) growth = static_cast<double>(*tight) / static_cast<double>(*same);
  }
  if (growth && *growth >= kConfirm) return;  // accuracy set the steps: not stiff at this tolerance
  std::ostringstream os;
  os.precision(3);
  os << "stiff problem: the " << report.steps << " steps (" << step << " s at the end) ";
  if (growth) {
    os << "were limited by stability, not accuracy: over the run's first " << span << " s, tolerances " << kTighter
       << " times tighter took " << probe;
    if (probe != options.method)
      os << " (standing in for " << options.method
         << (options.method == "bulirsch_stoer" ? ", which raises its order rather than shrinking its step)"
                                                : ", whose steps no tolerance per step sets)");
    os << " " << *growth << " times as many steps, where steps set by accuracy would take about "
       << std::pow(kTighter, *exponent) << " times as many (largest |eigenvalue| of df/dx about " << *rho
       << " 1/s, step x rho = " << h_rho << "); an implicit method (rosenbrock4) is not limited this way";
  } else {
    os << "may have been limited by stability rather than accuracy (largest |eigenvalue| of df/dx about " << *rho
       << " 1/s, step x rho = " << h_rho
       << "); if a tighter rtol leaves the step count nearly unchanged, they were, and an implicit method "
       << "(rosenbrock4) is not limited this way";
  }
  report.warnings.push_back(os.str());
}

}  // namespace lagrangian::detail
