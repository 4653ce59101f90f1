#pragma once
// One-dimensional bounded minimisation, shared by the aiming and
// identification helpers: NLopt's derivative-free BOBYQA, a gradient-based
// NLopt algorithm (L-BFGS, SLSQP) when the derivative is known, or
// Gauss–Newton for least squares whose residuals' derivatives are known.

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include <nlopt.h>

#include "lagrangian/errors.hpp"

namespace lagrangian::models::detail {

/// NLopt's `algorithm` on the objective (f, data) over [lo, hi] from
/// `start`, to |Δx| ≤ xtol or an objective ≤ stop (at most
/// `max_evaluations` calls); returns (x, f(x)). Throws SimulationError when
/// NLopt fails.
inline std::pair<double, double> nlopt_minimise_1d(nlopt_algorithm algorithm, nlopt_func f, void* data, double lo,
                                                   double hi, double start, double xtol, double stop,
                                                   int max_evaluations) {
  std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(nlopt_create(algorithm, 1), &nlopt_destroy);
  nlopt_set_min_objective(opt.get(), f, data);
  nlopt_set_lower_bounds1(opt.get(), lo);
  nlopt_set_upper_bounds1(opt.get(), hi);
  nlopt_set_xtol_abs1(opt.get(), xtol);
  nlopt_set_stopval(opt.get(), stop);
  nlopt_set_maxeval(opt.get(), max_evaluations);
  const double step = 0.25 * (hi - lo);
  nlopt_set_initial_step(opt.get(), &step);
  double x = start, fx = 0;
  const nlopt_result r = nlopt_optimize(opt.get(), &x, &fx);
  if (r < 0)
    throw SimulationError(std::string("NLopt ") + nlopt_algorithm_name(algorithm) + " failed (code " +
                              std::to_string(static_cast<int>(r)) + ")",
                          0.0);
  return {x, fx};
}

/// Minimises f on [lo, hi] from `start` with BOBYQA to |Δx| ≤ xtol or
/// f ≤ stop (at most `max_evaluations` calls); returns (x, f(x)).
template <class F>
std::pair<double, double> minimise_1d(F& f, double lo, double hi, double start, double xtol,
                                      int max_evaluations = 500, double stop = -HUGE_VAL) {
  return nlopt_minimise_1d(
      NLOPT_LN_BOBYQA, [](unsigned, const double* x, double*, void* data) { return (*static_cast<F*>(data))(x[0]); },
      &f, lo, hi, start, xtol, stop, max_evaluations);
}

/// Minimises f on [lo, hi] from `start` with the gradient-based `algorithm`
/// (NLOPT_LD_LBFGS, NLOPT_LD_SLSQP): fg(x, dfdx) returns f(x) and sets dfdx
/// = f′(x). Stops at |Δx| ≤ xtol or f ≤ stop; returns (x, f(x)).
template <class FG>
std::pair<double, double> minimise_1d_with_gradient(FG& fg, nlopt_algorithm algorithm, double lo, double hi,
                                                    double start, double xtol, double stop,
                                                    int max_evaluations = 500) {
  return nlopt_minimise_1d(
      algorithm,
      [](unsigned, const double* x, double* grad, void* data) {
        double dfdx = 0;
        const double value = (*static_cast<FG*>(data))(x[0], dfdx);
        if (grad != nullptr) grad[0] = dfdx;
        return value;
      },
      &fg, lo, hi, start, xtol, stop, max_evaluations);
}

/// Gauss–Newton for least squares in one variable on [lo, hi]:
/// run(x, g, h) returns J(x) = Σ_k r_k² and sets g = Σ_k r_k r_k′ (½ J′) and
/// h = Σ_k r_k′² (Gauss–Newton's ½ J″). The step x ← x − g/h, kept in
/// [lo, hi], is halved until J falls. Stops when a step moves x by at most
/// xtol, when J ≤ stop, or after `max_evaluations` runs; returns (x, J(x)).
template <class Run>
std::pair<double, double> gauss_newton_1d(Run& run, double lo, double hi, double start, double xtol, double stop,
                                          int max_evaluations = 500) {
  double x = std::clamp(start, lo, hi), g = 0, h = 0;
  double j = run(x, g, h);
  int evaluations = 1;
  while (j > stop && evaluations < max_evaluations && h > 0) {
    // (A step past a bound is cut to it, so halving it moves x.)
    double step = std::clamp(x - g / h, lo, hi) - x, xn = x, jn = j, gn = 0, hn = 0;
    for (;;) {
      xn = x + step;
      if (std::abs(xn - x) <= xtol) return {x, j};
      jn = run(xn, gn, hn);
      ++evaluations;
      if (jn < j || evaluations >= max_evaluations) break;
      step *= 0.5;
    }
    if (!(jn < j)) break;
    x = xn;
    j = jn;
    g = gn;
    h = hn;
  }
  return {x, j};
}

}  // namespace lagrangian::models::detail
