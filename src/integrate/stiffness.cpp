// The stiffness diagnostic of a finished run.

#include <algorithm>
#include <cmath>
#include <exception>
#include <sstream>

#include "loops.hpp"

namespace lagrangian::detail {

/// ρ ≈ √(‖J²v‖/‖v‖) after 20 power iterations on J² (J² turns a pair of
/// oscillatory eigenvalues ±iω into the real −ω², so the iteration
/// settles); J v by central differences of f. The warning is given when the
/// step size h at the end satisfies h ρ > 1 (steps limited by stability: an
/// explicit Runge–Kutta method is stable only for h ρ below a few units).
void check_stiffness(const System& system, const StateVector& x, double t, double step, RunReport& report) {
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
      if (!(nv > 0) || !std::isfinite(nv)) return;
      for (auto& c : v) c /= nv;
      apply(v, w);
      apply(w, v);
      rho2 = norm(v);
    }
  } catch (const std::exception&) {
    return;  // a diagnostic only: a state where f cannot be evaluated gives none
  }
  if (!std::isfinite(rho2)) return;
  report.stiffness_rho = std::sqrt(rho2);
  if (step * report.stiffness_rho > 1.0) {
    std::ostringstream os;
    os.precision(3);
    os << "stiff problem: the " << report.steps << " steps (" << step << " s at the end) may have been limited by "
       << "stability rather than accuracy (largest |eigenvalue| of df/dx about " << report.stiffness_rho
       << " 1/s, step x rho = " << step * report.stiffness_rho
       << "); if a tighter rtol leaves the step count nearly unchanged, they were, and an implicit method "
       << "(rosenbrock4) is not limited this way";
    report.warnings.push_back(os.str());
  }
}

}  // namespace lagrangian::detail
