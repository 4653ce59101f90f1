#pragma once
// One-dimensional bounded minimisation with NLopt's derivative-free BOBYQA,
// shared by the aiming and identification helpers.

#include <memory>
#include <string>
#include <utility>

#include <nlopt.h>

#include "lagrangian/errors.hpp"

namespace lagrangian::models::detail {

/// Minimises f on [lo, hi] from `start` to |Δx| ≤ xtol (at most `max_evaluations`
/// calls); returns (x, f(x)). Throws SimulationError when NLopt fails.
template <class F>
std::pair<double, double> minimise_1d(F& f, double lo, double hi, double start, double xtol,
                                      int max_evaluations = 500) {
  struct Ctx {
    F* f;
  } ctx{&f};
  std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(nlopt_create(NLOPT_LN_BOBYQA, 1), &nlopt_destroy);
  nlopt_set_min_objective(
      opt.get(), [](unsigned, const double* x, double*, void* data) { return (*static_cast<Ctx*>(data)->f)(x[0]); },
      &ctx);
  nlopt_set_lower_bounds1(opt.get(), lo);
  nlopt_set_upper_bounds1(opt.get(), hi);
  nlopt_set_xtol_abs1(opt.get(), xtol);
  nlopt_set_maxeval(opt.get(), max_evaluations);
  const double step = 0.25 * (hi - lo);
  nlopt_set_initial_step(opt.get(), &step);
  double x = start, fx = 0;
  const nlopt_result r = nlopt_optimize(opt.get(), &x, &fx);
  if (r < 0) throw SimulationError("NLopt BOBYQA failed (code " + std::to_string(static_cast<int>(r)) + ")", 0.0);
  return {x, fx};
}

}  // namespace lagrangian::models::detail
