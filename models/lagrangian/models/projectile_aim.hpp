#pragma once
/// \file projectile_aim.hpp
/// Aiming a projectile with NLopt, every objective value a simulated flight
/// (so drag and inclined planes need no closed form):
///  - best_elevation(): the elevation of greatest range along the plane;
///  - elevations_to_hit(): the two elevations that pass through a target.

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "lagrangian/errors.hpp"
#include "lagrangian/models/detail/minimise_1d.hpp"
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/integrate/simulate.hpp"

namespace lagrangian::models {

/// Result of an aiming search.
struct Aim {
  double alpha = 0;     ///< elevation (rad)
  double value = 0;     ///< range along the plane (m) for best_elevation; miss (m) for elevations_to_hit
  int evaluations = 0;  ///< simulated flights
};

namespace detail {

/// A projectile whose only event stops the run where x reaches x_target.
template <Drag D>
struct ProjectileToX : Projectile<D> {
  double x_target = 0;
  template <class S>
  Vec<S, 1> events(const Vec<S, 2>& q, const Vec<S, 2>&, const S&) const {
    return Vec<S, 1>(q[0] - x_target);
  }
  std::array<EventSpec, 1> event_specs() const { return {EventSpec{"target_x", Direction::rising, EventAction::stop}}; }
};

}  // namespace detail

/// The elevation α ∈ (β, π/2) that maximises the simulated range along the
/// plane, R = x_landing / cos β, by NLopt BOBYQA over [β + 0.01, π/2 − 0.01]
/// from `start` (rad; by default a third of the way up that bracket, which
/// knows nothing of the answer). Without drag it is π/4 + β/2 (Projectile::best_elevation());
/// with drag it is lower.
template <Drag D>
Aim best_elevation(const Projectile<D>& p, double u, SimulationOptions options = {},
                   double start = std::numeric_limits<double>::quiet_NaN()) {
  options.output_interval = -1;
  options.t_end = 1e3 * u / p.g + 1.0;  // long enough for any flight; the landing event stops it
  int evaluations = 0;
  auto negative_range = [&](double alpha) {
    ++evaluations;
    Recorder<2> rec;
    const RunReport r = simulate(p, p.launch(u, alpha), options, rec);
    if (r.stopped_by != "landing") throw SimulationError("the projectile did not land by t_end", r.t_final);
    return -rec.samples.back().q[0] / std::cos(p.beta);
  };
  // The bracket stops 0.01 rad short of the plane and the vertical: a
  // flight a micro-radian above the plane lasts microseconds, rises and
  // lands inside one step and is never seen to land.
  const double lo = p.beta + 1e-2, hi = Projectile<D>::kHalfPi - 1e-2;
  if (std::isnan(start)) start = lo + (hi - lo) / 3.0;
  if (!(start >= lo && start <= hi))
    lagrangian::detail::parameter_failure("best_elevation", "start", "inside [beta + 0.01, pi/2 - 0.01] rad", start);
  const auto [alpha, f] = detail::minimise_1d(negative_range, lo, hi, start, 1e-12);
  return {alpha, -f, evaluations};
}

/// The two elevations (low and high) whose simulated flights pass through
/// the target (x_t, y_t) (m, x_t > 0): the roots of the miss y(x_t) − y_t,
/// found by NLopt BOBYQA on the miss² either side of the elevation of
/// greatest reach toward the target, π/4 + atan2(y_t, x_t)/2. Throws
/// ParameterError naming the target and the closest miss when it is out of
/// reach (a miss above `tolerance` m remains).
template <Drag D>
std::pair<Aim, Aim> elevations_to_hit(const Projectile<D>& p, double u, double x_target, double y_target,
                                      double tolerance = 1e-9, SimulationOptions options = {}) {
  require_positive("elevations_to_hit", "x_target", x_target);
  require_finite("elevations_to_hit", "y_target", y_target);
  detail::ProjectileToX<D> model{p};
  model.x_target = x_target;
  options.output_interval = -1;
  options.t_end = 1e3 * u / p.g + 1.0;
  int evaluations = 0;
  auto miss = [&](double alpha) {
    ++evaluations;
    Recorder<2> rec;
    simulate(model, p.launch(u, alpha), options, rec);
    const auto& end = rec.samples.back();
    // Not reaching x_target counts as passing below it by how far it fell short.
    return end.q[0] >= x_target ? end.q[1] - y_target : -(x_target - end.q[0]) - std::abs(end.q[1] - y_target);
  };
  auto miss2 = [&](double alpha) {
    const double m = miss(alpha);
    return m * m;
  };
  const double split = 0.7853981633974483 + 0.5 * std::atan2(y_target, x_target);
  const double lo = std::max(p.beta, std::atan2(y_target, x_target)) + 1e-9, hi = Projectile<D>::kHalfPi - 1e-9;
  std::pair<Aim, Aim> out;
  const auto low = detail::minimise_1d(miss2, lo, split, 0.5 * (lo + split), 1e-12);
  const auto high = detail::minimise_1d(miss2, split, hi, 0.5 * (split + hi), 1e-12);
  out.first = {low.first, std::sqrt(low.second), evaluations};
  out.second = {high.first, std::sqrt(high.second), evaluations};
  const double worst = std::max(out.first.value, out.second.value);
  if (!(worst <= tolerance)) {
    std::ostringstream os;
    os.precision(6);
    os << "elevations_to_hit: the target (" << x_target << ", " << y_target << ") m is out of reach at u = " << u
       << " m/s: the closest flight misses it by " << std::min(out.first.value, out.second.value) << " m";
    throw ParameterError(os.str());
  }
  return out;
}

}  // namespace lagrangian::models
