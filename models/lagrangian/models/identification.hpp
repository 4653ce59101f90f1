#pragma once
/// \file identification.hpp
/// Parameter identification from recorded motion with NLopt's
/// derivative-free BOBYQA: each objective value is a simulated run compared
/// with the record by least squares,
///   J(p) = Σ_k |x_sim(t_k; p) − x_k|²,  t_k = t0 + k Δ  (k = 0 … K−1),
/// and the fit reports the parameter and the root-mean-square residual
/// √(J/K) (m), which for a right model is the noise of the record.
///  - fit_restitution(): e of a ball bouncing on a floor, from heights;
///  - fit_drag(): the drag coefficient of a projectile, from positions.

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "lagrangian/errors.hpp"
#include "lagrangian/models/detail/minimise_1d.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/simulate.hpp"

namespace lagrangian::models {

/// A fitted parameter.
struct Fit {
  double value = 0;         ///< the parameter
  double rms_residual = 0;  ///< √(J/K) (m)
  int evaluations = 0;      ///< simulated runs
};

namespace detail {

inline void check_record(const char* who, double interval, const std::vector<std::vector<double>>& series) {
  if (!(interval > 0) || !std::isfinite(interval)) {
    std::ostringstream os;
    os << who << ": the record's interval must be positive and finite, got " << interval;
    throw ParameterError(os.str());
  }
  for (const auto& s : series) {
    if (s.size() < 2) throw ParameterError(std::string(who) + ": the record needs at least 2 samples");
    if (s.size() != series.front().size())
      throw ParameterError(std::string(who) + ": the recorded series differ in length");
    for (std::size_t k = 0; k < s.size(); ++k) {
      if (!std::isfinite(s[k])) {
        std::ostringstream os;
        os << who << ": recorded value " << k << " is " << s[k] << "; it must be finite";
        throw ParameterError(os.str());
      }
    }
  }
}

/// A projectile that flies on past the launch plane (a record may go below it).
template <Drag D>
struct ProjectileWithoutLanding : Projectile<D> {
  template <class S>
  Vec<S, 1> events(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return Vec<S, 1>(qd[1]);
  }
  std::array<EventSpec, 1> event_specs() const { return {EventSpec{"apex", Direction::falling}}; }
};

}  // namespace detail

/// The coefficient of restitution e ∈ [0, 1] of `ball` (its own e is
/// ignored) that best reproduces the recorded heights z_k of the ball's
/// centre (m) at t_k = k·interval from the initial state x0. Throws
/// ParameterError for an empty, ragged or non-finite record.
inline Fit fit_restitution(const BallAndPlane& ball, const State<3>& x0, double interval,
                           const std::vector<double>& heights) {
  detail::check_record("fit_restitution", interval, {heights});
  const std::size_t K = heights.size();
  SimulationOptions o;
  o.t_end = interval * static_cast<double>(K - 1);
  o.output_interval = interval;
  int evaluations = 0;
  auto cost = [&](double e) {
    ++evaluations;
    const BallAndPlane trial(ball.m, ball.R, e, ball.g, ball.n, ball.d);
    Recorder<3> rec;
    simulate(trial, x0, o, rec);
    double j = 0;
    for (std::size_t k = 0; k < K && k < rec.samples.size(); ++k) {
      const double r = rec.samples[k].q[2] - heights[k];
      j += r * r;
    }
    return j;
  };
  const auto [e, j] = detail::minimise_1d(cost, 0.0, 1.0, 0.5, 1e-9, 300);
  return {e, std::sqrt(j / static_cast<double>(K)), evaluations};
}

/// The drag coefficient (b in kg/s for Drag::linear, c in kg/m for
/// Drag::quadratic) in [0, max_coefficient] of `projectile` (its own is
/// ignored) that best reproduces the recorded positions (x_k, y_k) (m) at
/// t_k = k·interval from x0.
template <Drag D>
Fit fit_drag(const Projectile<D>& projectile, const State<2>& x0, double interval, const std::vector<double>& xs,
             const std::vector<double>& ys, double max_coefficient) {
  static_assert(D != Drag::none, "fit_drag needs a projectile with declared drag");
  detail::check_record("fit_drag", interval, {xs, ys});
  require_positive("fit_drag", "max_coefficient", max_coefficient);
  const std::size_t K = xs.size();
  SimulationOptions o;
  o.t_end = interval * static_cast<double>(K - 1);
  o.output_interval = interval;
  int evaluations = 0;
  auto cost = [&](double c) {
    ++evaluations;
    const detail::ProjectileWithoutLanding<D> trial{Projectile<D>(projectile.m, projectile.g, projectile.beta, c)};
    Recorder<2> rec;
    simulate(trial, x0, o, rec);
    double j = 0;
    for (std::size_t k = 0; k < K && k < rec.samples.size(); ++k) {
      const double rx = rec.samples[k].q[0] - xs[k], ry = rec.samples[k].q[1] - ys[k];
      j += rx * rx + ry * ry;
    }
    return j;
  };
  const auto [c, j] = detail::minimise_1d(cost, 0.0, max_coefficient, 0.5 * max_coefficient, 1e-12 * max_coefficient, 300);
  return {c, std::sqrt(j / static_cast<double>(K)), evaluations};
}

}  // namespace lagrangian::models
