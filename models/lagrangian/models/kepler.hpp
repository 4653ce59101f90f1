#pragma once
/// \file kepler.hpp
/// Kepler orbits in closed form (course notes 1.6): the relative motion of
/// a gravitational pair, r̈ = −GM r/|r|³, from a state at t = 0 to any time,
/// for ellipses by the eccentric anomaly and for every conic by the
/// universal variable; and the elliptic orbit from its elements. SI units.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "lagrangian/errors.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::models {

/// The eccentric anomaly E with E − e sin E = M (Kepler's equation) for
/// e ∈ [0, 1): Newton's method from E₀ = M (e < 0.8) or π, M reduced to
/// [0, 2π), to 4 ulp of 2π or 50 iterations.
inline double solve_kepler(double mean_anomaly, double e) {
  const double two_pi = 2.0 * std::acos(-1.0);
  double m = std::fmod(mean_anomaly, two_pi);
  if (m < 0) m += two_pi;
  double E = e < 0.8 ? m : std::acos(-1.0);
  for (int it = 0; it < 50; ++it) {
    const double step = (E - e * std::sin(E) - m) / (1.0 - e * std::cos(E));
    E -= step;
    if (std::abs(step) <= 4 * std::numeric_limits<double>::epsilon() * two_pi) break;
  }
  return E;
}

/// The relative position and velocity (m, m/s) at time t of a bound Kepler
/// orbit that has r0, v0 at t = 0, gravitational parameter GM (m³/s²): the
/// orbital elements from the state (h = r × v, eccentricity vector
/// e = v × h / GM − r̂, a = 1/(2/r − v²/GM)), Kepler's equation for E(t), and
/// back along the periapsis direction p̂ and q̂ = ĥ × p̂. Throws
/// ParameterError for an unbound (a ≤ 0) or radial (h = 0) orbit;
/// kepler_propagate() takes every orbit.
inline std::pair<Eigen::Vector3d, Eigen::Vector3d> elliptic_kepler_propagate(double gm, const Eigen::Vector3d& r0,
                                                                             const Eigen::Vector3d& v0, double t) {
  const double r = r0.norm(), v2 = v0.squaredNorm();
  const double a = 1.0 / (2.0 / r - v2 / gm);
  const Eigen::Vector3d h = r0.cross(v0);
  if (!(a > 0) || !std::isfinite(a))
    throw ParameterError("elliptic_kepler_propagate: the orbit is not bound (v^2 >= 2 GM / r); no elliptic closed form");
  if (!(h.norm() > 1e-14 * r * std::sqrt(v2)))
    throw ParameterError("elliptic_kepler_propagate: the orbit is radial (r x v = 0); no elliptic closed form");
  const Eigen::Vector3d e_vec = v0.cross(h) / gm - r0 / r;
  double e = e_vec.norm();
  const Eigen::Vector3d h_hat = h.normalized();
  Eigen::Vector3d p_hat = e > 1e-12 ? Eigen::Vector3d(e_vec / e) : Eigen::Vector3d(r0 / r);
  if (e <= 1e-12) e = 0.0;
  const Eigen::Vector3d q_hat = h_hat.cross(p_hat);
  const double n = std::sqrt(gm / (a * a * a)), b = std::sqrt(1.0 - e * e);
  // E at t = 0 from r0 in the perifocal frame: x = a (cos E − e), y = a b sin E.
  const double E0 = std::atan2(r0.dot(q_hat) / (a * b), r0.dot(p_hat) / a + e);
  const double E = solve_kepler(E0 - e * std::sin(E0) + n * t, e);
  const double c = std::cos(E), sn = std::sin(E), d = 1.0 - e * c;
  return {a * (c - e) * p_hat + a * b * sn * q_hat, (-a * n * sn / d) * p_hat + (a * n * b * c / d) * q_hat};
}

namespace detail {

/// Stumpff's functions of z = α χ² (dimensionless):
///   C(z) = (1 − cos √z)/z,  S(z) = (√z − sin √z)/√z³   (z > 0),
///   C(z) = (cosh √−z − 1)/(−z),  S(z) = (sinh √−z − √−z)/√(−z)³   (z < 0),
/// both the series C = Σ (−z)ᵏ/(2k + 2)!, S = Σ (−z)ᵏ/(2k + 3)! (C(0) = 1/2,
/// S(0) = 1/6). The series is summed for |z| < 1, where the closed forms
/// cancel; elsewhere 1 − cos x is written 2 sin²(x/2) (and cosh alike).
struct Stumpff {
  double C, S;
};
inline Stumpff stumpff(double z) {
  if (std::abs(z) < 1.0) {
    double c = 0, s = 0, term_c = 0.5, term_s = 1.0 / 6.0;
    for (int k = 0; k < 16; ++k) {
      c += term_c;
      s += term_s;
      term_c *= -z / ((2.0 * k + 3) * (2.0 * k + 4));
      term_s *= -z / ((2.0 * k + 4) * (2.0 * k + 5));
    }
    return {c, s};
  }
  if (z > 0) {
    const double x = std::sqrt(z), h = std::sin(0.5 * x);
    return {2.0 * h * h / z, (x - std::sin(x)) / (z * x)};
  }
  const double x = std::sqrt(-z), h = std::sinh(0.5 * x);
  return {2.0 * h * h / -z, (std::sinh(x) - x) / (-z * x)};
}

}  // namespace detail

/// The relative position and velocity (m, m/s) at time t (s, either sign)
/// of any Kepler orbit, elliptic, parabolic or hyperbolic, that has r0, v0
/// at t = 0 under the gravitational parameter GM (m³/s²), by the universal
/// variable χ (m^½) (Battin 1999, *An Introduction to the Mathematics and
/// Methods of Astrodynamics*, ch. 4; Curtis, *Orbital Mechanics for
/// Engineering Students*, §3.7). With α = 2/r₀ − v₀²/GM (1/m, = 1/a) and
/// σ₀ = r₀·v₀/√GM, χ solves
///   √GM t = σ₀ χ² C(z) + (1 − α r₀) χ³ S(z) + r₀ χ,   z = α χ²,
/// found by the Laguerre–Conway iteration (Conway 1986, Celest. Mech. 39,
/// 199), which converges from a rough start for every conic; then with the
/// Lagrange coefficients
///   f = 1 − χ² C / r₀,  g = t − χ³ S / √GM = (σ₀ χ² C + r₀ χ (1 − z S))/√GM,
///   r = f r₀ + g v₀,
///   ḟ = √GM χ (z S − 1) / (r r₀),  ġ = 1 − χ² C / r,  v = ḟ r₀ + ġ v₀.
/// Accuracy: the state to ~1e-12 relative near the centre (tests/test_kepler.cpp:
/// against the hyperbolic anomaly and Barker's equation), and energy and
/// angular momentum to 1e-12 at any distance; a state far out on a
/// hyperbola (r ≫ r₀) carries an error that grows with r (propagating
/// 1e4 s out at 5 times escape speed and back misses the start by 5e-7).
/// Throws ParameterError for a radial orbit (r₀ × v₀ = 0: it meets the
/// centre) and for a state or time that is not finite.
inline std::pair<Eigen::Vector3d, Eigen::Vector3d> universal_kepler_propagate(double gm, const Eigen::Vector3d& r0,
                                                                              const Eigen::Vector3d& v0, double t) {
  const double r0n = r0.norm(), v2 = v0.squaredNorm();
  if (!(std::isfinite(gm) && gm > 0 && std::isfinite(r0n) && r0n > 0 && std::isfinite(v2) && std::isfinite(t)))
    throw ParameterError("universal_kepler_propagate: GM must be positive and r0, v0 and t finite with r0 != 0");
  if (!(r0.cross(v0).norm() > 1e-14 * r0n * std::sqrt(v2)))
    throw ParameterError("universal_kepler_propagate: the orbit is radial (r x v = 0) and meets the centre");
  if (t == 0) return {r0, v0};
  const double sqrt_gm = std::sqrt(gm), alpha = 2.0 / r0n - v2 / gm, sigma0 = r0.dot(v0) / sqrt_gm;
  const double b = 1.0 - alpha * r0n;
  // Starting guesses after Vallado (Fundamentals of Astrodynamics, algorithm 8):
  // ellipse √GM α t; hyperbola from the asymptotic form; otherwise √GM t / r₀.
  double chi = sqrt_gm * t / r0n;
  if (alpha > 1e-12 / r0n) {
    chi = sqrt_gm * t * alpha;
  } else if (alpha < -1e-12 / r0n) {
    const double a = 1.0 / alpha, sg = t > 0 ? 1.0 : -1.0;
    const double arg = -2.0 * gm * alpha * t / (r0.dot(v0) + sg * std::sqrt(-gm * a) * b);
    const double guess = sg * std::sqrt(-a) * std::log(arg);
    if (arg > 0 && std::isfinite(guess)) chi = guess;
  }
  const double eps = std::numeric_limits<double>::epsilon();
  constexpr double n = 5;  // Laguerre's order; Conway's choice
  bool converged = false;
  for (int it = 0; it < 100 && !converged; ++it) {
    const double z = alpha * chi * chi;
    const auto [C, S] = detail::stumpff(z);
    const double t1 = sigma0 * chi * chi * C, t2 = b * chi * chi * chi * S, t3 = r0n * chi, t4 = sqrt_gm * t;
    const double F = t1 + t2 + t3 - t4;
    const double dF = sigma0 * chi * (1.0 - z * S) + b * chi * chi * C + r0n;
    const double ddF = sigma0 * (1.0 - z * C) + b * chi * (1.0 - z * S);
    const double root = std::sqrt(std::abs((n - 1) * (n - 1) * dF * dF - n * (n - 1) * F * ddF));
    const double step = n * F / (dF + (dF >= 0 ? root : -root));
    chi -= step;
    // Done when the step is below what rounding in F allows (F's terms are
    // each good to an ulp, so the root is known to about that over F').
    const double noise = 8 * eps * (std::abs(t1) + std::abs(t2) + std::abs(t3) + std::abs(t4)) / std::abs(dF);
    converged = std::abs(step) <= std::max(4 * eps * std::abs(chi), noise);
  }
  const double z = alpha * chi * chi;
  const auto [C, S] = detail::stumpff(z);
  // g = t − χ³S/√GM, written without the difference of the two large terms.
  const double f = 1.0 - chi * chi * C / r0n, g = (sigma0 * chi * chi * C + r0n * chi * (1.0 - z * S)) / sqrt_gm;
  const Eigen::Vector3d r = f * r0 + g * v0;
  const double rn = r.norm();
  const double fd = sqrt_gm * chi * (z * S - 1.0) / (rn * r0n), gd = 1.0 - chi * chi * C / rn;
  const Eigen::Vector3d v = fd * r0 + gd * v0;
  if (!converged || !r.allFinite() || !v.allFinite())
    throw ParameterError("universal_kepler_propagate: Kepler's equation in the universal variable did not converge at t = " +
                         std::to_string(t) + " s (the orbit may pass too far out for double precision)");
  return {r, v};
}

/// The relative position and velocity (m, m/s) at time t (s) of the Kepler
/// orbit through r0, v0 at t = 0, GM in m³/s²: elliptic_kepler_propagate()
/// for a bound orbit (α = 2/r₀ − v₀²/GM > 0), universal_kepler_propagate()
/// for a parabolic or hyperbolic one. Throws ParameterError for a radial orbit.
inline std::pair<Eigen::Vector3d, Eigen::Vector3d> kepler_propagate(double gm, const Eigen::Vector3d& r0,
                                                                    const Eigen::Vector3d& v0, double t) {
  const double alpha = 2.0 / r0.norm() - v0.squaredNorm() / gm;
  if (alpha > 0 && std::isfinite(1.0 / alpha)) return elliptic_kepler_propagate(gm, r0, v0, t);
  return universal_kepler_propagate(gm, r0, v0, t);
}

/// A Kepler orbit in closed form, in its own plane with periapsis on +x:
/// semi-major axis a (m), eccentricity e ∈ [0, 1), gravitational parameter
/// GM = G (m₁ + m₂) (m³/s²), periapsis passage at t_p (s). The relative
/// coordinate of a gravitational pair follows it.
///   n = √(GM/a³),  M = n (t − t_p),  E − e sin E = M  (Kepler's equation),
///   x = a (cos E − e),  y = a √(1 − e²) sin E,
///   ẋ = −a n sin E / (1 − e cos E),  ẏ = a n √(1 − e²) cos E / (1 − e cos E),
///   period P = 2π √(a³/GM).
struct KeplerOrbit {
  double a, e, gm, tp;
  KeplerOrbit(double semi_major_axis, double eccentricity, double gravitational_parameter, double periapsis_time = 0)
      : a(require_positive("KeplerOrbit", "a", semi_major_axis)),
        e(eccentricity),
        gm(require_positive("KeplerOrbit", "GM", gravitational_parameter)),
        tp(require_finite("KeplerOrbit", "t_p", periapsis_time)) {
    if (!(e >= 0.0 && e < 1.0)) lagrangian::detail::parameter_failure("KeplerOrbit", "e", "in [0, 1) (a bound orbit)", e);
  }
  /// Mean motion n (rad/s).
  double mean_motion() const { return std::sqrt(gm / (a * a * a)); }
  /// Orbital period P = 2π √(a³/GM) (s).
  double period() const { return 2.0 * std::acos(-1.0) / mean_motion(); }
  /// Eccentric anomaly E at time t: Kepler's equation by Newton's method
  /// from E₀ = M (e < 0.8) or π, to 4 ulp of 2π or 50 iterations.
  double eccentric_anomaly(double t) const { return solve_kepler(mean_motion() * (t - tp), e); }
  /// Position (x, y) (m) and velocity (ẋ, ẏ) (m/s) at time t.
  std::array<double, 4> state(double t) const {
    const double E = eccentric_anomaly(t), n = mean_motion();
    const double c = std::cos(E), s = std::sin(E), b = std::sqrt(1.0 - e * e);
    const double denom = 1.0 - e * c;
    return {a * (c - e), a * b * s, -a * n * s / denom, a * n * b * c / denom};
  }
  /// Periapsis distance a (1 − e) (m) and speed there √(GM (1 + e) / (a (1 − e))) (m/s).
  double periapsis_distance() const { return a * (1.0 - e); }
  double periapsis_speed() const { return std::sqrt(gm * (1.0 + e) / (a * (1.0 - e))); }
};

}  // namespace lagrangian::models
