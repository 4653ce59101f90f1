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
#include "lagrangian/integrate/simulate.hpp"

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

/// The common fit: a record of K samples at t_k = k·interval from x0;
/// `make_model(p)` builds the trial model for parameter p, `misfit2(sample,
/// k)` is the squared misfit of sample k; J(p) is minimised on [lo, hi].
template <int N, class MakeModel, class Misfit2>
Fit fit_record(const State<N>& x0, double interval, std::size_t K, const MakeModel& make_model,
               const Misfit2& misfit2, double lo, double hi, double start, double xtol) {
  SimulationOptions o;
  o.t_end = interval * static_cast<double>(K - 1);
  o.output_interval = interval;
  int evaluations = 0;
  auto cost = [&](double p) {
    ++evaluations;
    Recorder<N> rec;
    simulate(make_model(p), x0, o, rec);
    double j = 0;
    for (std::size_t k = 0; k < K && k < rec.samples.size(); ++k) j += misfit2(rec.samples[k], k);
    return j;
  };
  const auto [p, j] = minimise_1d(cost, lo, hi, start, xtol, 300);
  return {p, std::sqrt(j / static_cast<double>(K)), evaluations};
}

}  // namespace detail

/// The coefficient of restitution e ∈ [0, 1] of `ball` (its own e is
/// ignored) that best reproduces the recorded heights z_k of the ball's
/// centre (m) at t_k = k·interval from the initial state x0. Throws
/// ParameterError for an empty, ragged or non-finite record.
inline Fit fit_restitution(const BallAndPlane& ball, const State<3>& x0, double interval,
                           const std::vector<double>& heights) {
  detail::check_record("fit_restitution", interval, {heights});
  return detail::fit_record(
      x0, interval, heights.size(),
      [&](double e) { return BallAndPlane(ball.m, ball.R, e, ball.g, ball.n, ball.d); },
      [&](const Sample<3>& s, std::size_t k) {
        const double r = s.q[2] - heights[k];
        return r * r;
      },
      0.0, 1.0, 0.5, 1e-9);
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
  return detail::fit_record(
      x0, interval, xs.size(),
      [&](double c) {
        return detail::ProjectileWithoutLanding<D>{Projectile<D>(projectile.m, projectile.g, projectile.beta, c)};
      },
      [&](const Sample<2>& s, std::size_t k) {
        const double rx = s.q[0] - xs[k], ry = s.q[1] - ys[k];
        return rx * rx + ry * ry;
      },
      0.0, max_coefficient, 0.5 * max_coefficient, 1e-12 * max_coefficient);
}

}  // namespace lagrangian::models
