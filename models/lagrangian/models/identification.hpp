#pragma once
/// \file identification.hpp
/// Parameter identification from recorded motion: each objective value is a
/// simulated run compared with the record by least squares,
///   J(p) = Σ_k |x_sim(t_k; p) − x_k|²,  t_k = t0 + k Δ  (k = 0 … K−1),
/// and the fit reports the parameter and the root-mean-square residual
/// √(J/K) (m), which for a right model is the noise of the record.
///  - fit_restitution(): e of a ball bouncing on a floor, from heights;
///  - fit_drag(): the drag coefficient of a projectile, from positions;
/// each by NLopt's derivative-free BOBYQA or from the run's parameter
/// sensitivity s_k = ∂x_sim(t_k)/∂p (analysis/sensitivity.hpp, integrated
/// beside the state: J and its derivative from one run): Gauss–Newton,
/// p ← p − Σ r_k·s_k / Σ |s_k|² with r_k = x_sim(t_k) − x_k, or NLopt's
/// L-BFGS or SLSQP on the mean square J/K with d(J/K)/dp = 2 Σ_k r_k·s_k / K.

#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/analysis/sensitivity.hpp"
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
  int evaluations = 0;      ///< simulated runs (with the sensitivity beside the state when a method uses it)
};

/// How a fit searches (docs/analysis.md compares them).
enum class FitMethod {
  bobyqa,        ///< NLopt LN_BOBYQA: derivative-free, plain runs
  gauss_newton,  ///< Gauss–Newton with the residuals' derivatives from the parameter sensitivity
  lbfgs,         ///< NLopt LD_LBFGS with dJ/dp from the parameter sensitivity
  slsqp,         ///< NLopt LD_SLSQP with dJ/dp from the parameter sensitivity
};

/// What a fit does besides its record.
struct FitOptions {
  FitMethod method = FitMethod::bobyqa;
  /// Stop as soon as the RMS residual √(J/K) is at most this (m); 0 runs
  /// to the parameter's tolerance.
  double target_rms = 0;
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

/// SimulationError unless a run gave the record's K samples (a run that
/// stopped early would leave J short of terms).
inline void require_samples(const char* who, std::size_t got, std::size_t K, double t) {
  if (got < K)
    throw SimulationError(std::string(who) + ": the run gave " + std::to_string(got) + " samples for a record of " +
                              std::to_string(K),
                          t);
}

/// A projectile that flies on past the launch plane (a record may go below it).
template <Drag D, class P = double>
struct ProjectileWithoutLanding : Projectile<D, P> {
  /// The model with parameters of type Q (parameter sensitivities).
  template <class Q>
  using with_parameter_type = ProjectileWithoutLanding<D, Q>;
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
               const Misfit2& misfit2, double lo, double hi, double start, double xtol, double stop = -HUGE_VAL) {
  SimulationOptions o;
  o.t_end = interval * static_cast<double>(K - 1);
  o.output_interval = interval;
  int evaluations = 0;
  auto cost = [&](double p) {
    ++evaluations;
    Recorder<N> rec;
    simulate(make_model(p), x0, o, rec);
    require_samples("fit", rec.samples.size(), K, rec.samples.empty() ? 0.0 : rec.samples.back().t);
    double j = 0;
    for (std::size_t k = 0; k < K; ++k) j += misfit2(rec.samples[k], k);
    return j;
  };
  const auto [p, j] = minimise_1d(cost, lo, hi, start, xtol, 300, stop);
  return {p, std::sqrt(j / static_cast<double>(K)), evaluations};
}

/// The fit fed by the parameter's sensitivity: each run of make_model(p)
/// integrates s = ∂x/∂p beside the state (analysis/sensitivity.hpp) and
/// `add(x_k, s_k, k, j, g, h)` adds sample k's |r_k|², r_k·s_k and |s_k|²
/// (x_k the state (q, q̇), s_k its column) to J, g = ½ dJ/dp and h;
/// Gauss–Newton on (J, g, h), or NLopt's L-BFGS or SLSQP on the mean
/// square J/K with d(J/K)/dp = 2 g / K (on the sum's scale NLopt's L-BFGS
/// fails and SLSQP stops early: docs/analysis.md).
template <class M, class MakeModel, class Add>
Fit fit_record_by_sensitivity(const char* who, const State<coordinate_count_v<M>>& x0, double interval, std::size_t K,
                              const MakeModel& make_model, const std::string& parameter, const Add& add, double lo,
                              double hi, double start, double xtol, double stop, FitMethod method) {
  const double count = static_cast<double>(K);
  SensitivityOptions so;
  so.run.t_end = interval * (count - 1);
  so.run.output_interval = interval;
  so.initial_state = false;
  so.parameters = {parameter};
  int evaluations = 0;
  auto run = [&](double p, double& g, double& h) {
    ++evaluations;
    const SensitivityResult r = sensitivities(make_model(p), x0, so);
    require_samples(who, r.states.size(), K, r.times.empty() ? 0.0 : r.times.back());
    double j = 0;
    g = h = 0;
    for (std::size_t k = 0; k < K; ++k) add(r.states[k], r.sensitivities[k], k, j, g, h);
    return j;
  };
  if (method == FitMethod::gauss_newton) {
    const auto [p, j] = gauss_newton_1d(run, lo, hi, start, xtol, stop, 300);
    return {p, std::sqrt(j / count), evaluations};
  }
  if (method != FitMethod::lbfgs && method != FitMethod::slsqp)
    throw ParameterError(std::string(who) + ": method " + std::to_string(static_cast<int>(method)) +
                         " is not a FitMethod");
  auto mean_square = [&](double p, double& dj) {
    double g = 0, h = 0;
    const double j = run(p, g, h);
    dj = 2 * g / count;
    return j / count;
  };
  const auto [p, j] = minimise_1d_with_gradient(mean_square, method == FitMethod::lbfgs ? NLOPT_LD_LBFGS : NLOPT_LD_SLSQP,
                                                lo, hi, start, xtol, stop / count, 300);
  return {p, std::sqrt(j), evaluations};
}

/// The fit of one parameter p ∈ [lo, hi] (from `start`, to `xtol`) to
/// recorded coordinates: J(p) = Σ_k Σ_i (q_{c_i}(t_k; p) − y_i,k)², the
/// coordinates c_i = `coordinates[i]` of the runs of make(p) against the
/// series y_i = `*series[i]`, searched as `options` says (the sensitivity's
/// column of `parameter` feeding the methods that use one); each sample's
/// terms are summed before they join J.
template <class MakeModel>
Fit fit_coordinates(const char* who, const auto& x0, double interval, const std::vector<int>& coordinates,
                    const std::vector<const std::vector<double>*>& series, const MakeModel& make,
                    const std::string& parameter, double lo, double hi, double start, double xtol,
                    const FitOptions& options) {
  using M = std::decay_t<decltype(make(start))>;
  const std::size_t K = series.front()->size();
  const double stop =
      options.target_rms > 0 ? options.target_rms * options.target_rms * static_cast<double>(K) : -HUGE_VAL;
  const auto residual = [&](std::size_t i, double q, std::size_t k) { return q - (*series[i])[k]; };
  if (options.method == FitMethod::bobyqa) {
    return fit_record(
        x0, interval, K, make,
        [&](const auto& sample, std::size_t k) {
          double jk = 0;
          for (std::size_t i = 0; i < coordinates.size(); ++i) {
            const double r = residual(i, sample.q[coordinates[i]], k);
            jk += r * r;
          }
          return jk;
        },
        lo, hi, start, xtol, stop);
  }
  return fit_record_by_sensitivity<M>(
      who, x0, interval, K, make, parameter,
      [&](const Eigen::VectorXd& x, const Eigen::MatrixXd& s, std::size_t k, double& j, double& g, double& h) {
        double jk = 0, gk = 0, hk = 0;
        for (std::size_t i = 0; i < coordinates.size(); ++i) {
          const double r = residual(i, x[coordinates[i]], k), d = s(coordinates[i], 0);
          jk += r * r;
          gk += r * d;
          hk += d * d;
        }
        j += jk;
        g += gk;
        h += hk;
      },
      lo, hi, start, xtol, stop, options.method);
}

}  // namespace detail

/// The coefficient of restitution e ∈ [0, 1] of `ball` (its own e is
/// ignored) that best reproduces the recorded heights z_k of the ball's
/// centre (m) at t_k = k·interval from the initial state x0, searched as
/// `options` says (BOBYQA by default; the others with ∂z/∂e from the
/// parameter's column, which crosses the bounces and the rest a plain run
/// ends them with). Throws ParameterError for an empty, ragged or
/// non-finite record.
inline Fit fit_restitution(const BallAndPlane& ball, const State<3>& x0, double interval,
                           const std::vector<double>& heights, const FitOptions& options = {}) {
  detail::check_record("fit_restitution", interval, {heights});
  require_nonnegative("fit_restitution", "target_rms", options.target_rms);
  const auto make = [&](double e) { return BallAndPlane(ball.m, ball.R, e, ball.g, ball.normal(), ball.d); };
  return detail::fit_coordinates("fit_restitution", x0, interval, {2}, {&heights}, make, "e", 0.0, 1.0, 0.5, 1e-9,
                                 options);
}

/// The drag coefficient (b in kg/s for Drag::linear, c in kg/m for
/// Drag::quadratic) in [0, max_coefficient] of `projectile` (its own is
/// ignored) that best reproduces the recorded positions (x_k, y_k) (m) at
/// t_k = k·interval from x0, searched as `options` says (BOBYQA by default).
template <Drag D>
Fit fit_drag(const Projectile<D>& projectile, const State<2>& x0, double interval, const std::vector<double>& xs,
             const std::vector<double>& ys, double max_coefficient, const FitOptions& options = {}) {
  static_assert(D != Drag::none, "fit_drag needs a projectile with declared drag");
  detail::check_record("fit_drag", interval, {xs, ys});
  require_positive("fit_drag", "max_coefficient", max_coefficient);
  require_nonnegative("fit_drag", "target_rms", options.target_rms);
  const auto make = [&](double c) {
    return detail::ProjectileWithoutLanding<D>{Projectile<D>(projectile.m, projectile.g, projectile.beta, c)};
  };
  return detail::fit_coordinates("fit_drag", x0, interval, {0, 1}, {&xs, &ys}, make,
                                 std::string(Projectile<D>::description.parameters[3].name), 0.0, max_coefficient,
                                 0.5 * max_coefficient, 1e-12 * max_coefficient, options);
}

}  // namespace lagrangian::models
