#pragma once
/// \file two_body.hpp
/// The two-body problem and its reduction to one body of reduced mass
/// (course notes 1.6), Kepler orbits in closed form, and the hydrogen atom's
/// reduced mass. SI units.
///
/// Two particles m₁, m₂ at r₁, r₂ interacting through a central potential
/// U(r), r = |r₂ − r₁|:
///   L = ½ m₁|ṙ₁|² + ½ m₂|ṙ₂|² − U(r).
/// With the centre of mass R = (m₁r₁ + m₂r₂)/(m₁ + m₂) and the relative
/// coordinate r = r₂ − r₁ it separates into
///   L = ½ (m₁ + m₂)|Ṙ|² + ½ μ|ṙ|² − U(|r|),   μ = m₁m₂/(m₁ + m₂):
/// R moves uniformly and r moves as one body of mass μ in U.

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/impact.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::models {

/// μ = m₁m₂/(m₁ + m₂) (kg), written as m₁/(1 + m₁/m₂) so that it keeps full
/// relative accuracy for any mass ratio.
inline double reduced_mass(double m1, double m2) {
  require_positive("reduced_mass", "m1", m1);
  require_positive("reduced_mass", "m2", m2);
  return m1 / (1.0 + m1 / m2);
}

/// Newtonian gravity between two masses: U(r) = −k/r with k = G m₁ m₂
/// (J·m); the force on each body points to the other, |F| = k/r².
struct NewtonianGravity {
  double k;
  template <class S>
  S operator()(const S& r) const {
    return -k / r;
  }
};

/// Two bodies interacting through a central potential U(r) in D = 2 or 3
/// dimensions; coordinates (x₁, y₁[, z₁], x₂, y₂[, z₂]) (m).
///   T = ½ m₁|ṙ₁|² + ½ m₂|ṙ₂|²,  V = U(|r₂ − r₁|).
/// `Potential` is any callable `template <class S> S operator()(const S& r)`
/// giving U in J (NewtonianGravity by default).
template <int D, class Potential = NewtonianGravity>
struct TwoBody {
  static_assert(D == 2 || D == 3, "TwoBody is planar (D = 2) or spatial (D = 3)");
  static constexpr int dof = 2 * D;
  double m1, m2;
  Potential U;
  TwoBody(double mass1, double mass2, Potential potential)
      : m1(require_positive("TwoBody", "m1", mass1)), m2(require_positive("TwoBody", "m2", mass2)), U(potential) {}
  std::array<Particle, 2> particles() const {
    return {Particle{m1, {0, 1, D == 3 ? 2 : -1}}, Particle{m2, {D, D + 1, D == 3 ? D + 2 : -1}}};
  }
  std::string name() const { return "two_body"; }
  std::vector<std::string> coordinate_names() const {
    const char* axes[] = {"x", "y", "z"};
    std::vector<std::string> out;
    for (int b = 1; b <= 2; ++b)
      for (int k = 0; k < D; ++k) out.push_back(std::string(axes[k]) + std::to_string(b));
    return out;
  }
  template <class S>
  S kinetic(const Vec<S, dof>&, const Vec<S, dof>& qd, const S&) const {
    S a = S(0), b = S(0);
    for (int k = 0; k < D; ++k) {
      a += qd[k] * qd[k];
      b += qd[D + k] * qd[D + k];
    }
    return 0.5 * m1 * a + 0.5 * m2 * b;
  }
  template <class S>
  S potential(const Vec<S, dof>& q, const S&) const {
    using std::sqrt;
    S r2 = S(0);
    for (int k = 0; k < D; ++k) r2 += (q[D + k] - q[k]) * (q[D + k] - q[k]);
    return U(sqrt(r2));
  }
};

/// Gravitational two-body problem: U = −G m₁ m₂ / r, G in m³/(kg·s²).
template <int D>
TwoBody<D> gravitational_two_body(double m1, double m2, double G) {
  require_positive("TwoBody", "G", G);
  return TwoBody<D>(m1, m2, NewtonianGravity{G * m1 * m2});
}

/// The equivalent one-body problem: the relative coordinate r = r₂ − r₁
/// (m) of a body of reduced mass μ in U(|r|):
///   T = ½ μ |ṙ|²,  V = U(|r|).
/// Declares one watched event, "periapsis": r·ṙ rising through zero (the
/// closest approach of each orbit), so runs log every passage.
template <int D, class Potential = NewtonianGravity>
struct RelativeMotion {
  static_assert(D == 2 || D == 3, "RelativeMotion is planar (D = 2) or spatial (D = 3)");
  static constexpr int dof = D;
  double mu;
  Potential U;
  RelativeMotion(double reduced, Potential potential)
      : mu(require_positive("RelativeMotion", "mu", reduced)), U(potential) {}
  std::string name() const { return "relative_motion"; }
  std::vector<std::string> coordinate_names() const {
    const char* axes[] = {"x", "y", "z"};
    return std::vector<std::string>(axes, axes + D);
  }
  template <class S>
  S kinetic(const Vec<S, D>&, const Vec<S, D>& qd, const S&) const {
    S a = S(0);
    for (int k = 0; k < D; ++k) a += qd[k] * qd[k];
    return 0.5 * mu * a;
  }
  template <class S>
  S potential(const Vec<S, D>& q, const S&) const {
    using std::sqrt;
    S r2 = S(0);
    for (int k = 0; k < D; ++k) r2 += q[k] * q[k];
    return U(sqrt(r2));
  }
  template <class S>
  Vec<S, 1> events(const Vec<S, D>& q, const Vec<S, D>& qd, const S&) const {
    S rv = S(0);
    for (int k = 0; k < D; ++k) rv += q[k] * qd[k];
    return Vec<S, 1>(rv);
  }
  std::array<EventSpec, 1> event_specs() const { return {EventSpec{"periapsis", Direction::rising}}; }
};

/// The reduced problem of a gravitational pair: μ = m₁m₂/(m₁ + m₂) in
/// U = −G m₁ m₂ / r (the same k as the two-body problem).
template <int D>
RelativeMotion<D> gravitational_relative_motion(double m1, double m2, double G) {
  require_positive("RelativeMotion", "G", G);
  return RelativeMotion<D>(reduced_mass(m1, m2), NewtonianGravity{G * m1 * m2});
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
  double eccentric_anomaly(double t) const {
    const double two_pi = 2.0 * std::acos(-1.0);
    double m = std::fmod(mean_motion() * (t - tp), two_pi);
    if (m < 0) m += two_pi;
    double E = e < 0.8 ? m : std::acos(-1.0);
    for (int it = 0; it < 50; ++it) {
      const double f = E - e * std::sin(E) - m;
      const double step = f / (1.0 - e * std::cos(E));
      E -= step;
      if (std::abs(step) <= 4 * std::numeric_limits<double>::epsilon() * two_pi) break;
    }
    return E;
  }
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

/// CODATA 2018 masses (kg): electron and proton (NIST, physics.nist.gov/constants).
inline constexpr double electron_mass = 9.1093837015e-31;
inline constexpr double proton_mass = 1.67262192369e-27;

}  // namespace lagrangian::models
