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
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "lagrangian/impact.hpp"
#include "lagrangian/detail/compiled_models.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/models/detail/particles.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::models {

/// μ = m₁m₂/(m₁ + m₂) (kg), written as m₁/(1 + m₁/m₂) so that it keeps full
/// relative accuracy for any mass ratio.
inline double reduced_mass(double m1, double m2) {
  require_positive("reduced_mass", "m1", m1);
  require_positive("reduced_mass", "m2", m2);
  return m1 / (1.0 + m1 / m2);
}

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
/// ParameterError for an unbound (a ≤ 0) or radial (h = 0) orbit.
inline std::pair<Eigen::Vector3d, Eigen::Vector3d> kepler_propagate(double gm, const Eigen::Vector3d& r0,
                                                                    const Eigen::Vector3d& v0, double t) {
  const double r = r0.norm(), v2 = v0.squaredNorm();
  const double a = 1.0 / (2.0 / r - v2 / gm);
  const Eigen::Vector3d h = r0.cross(v0);
  if (!(a > 0) || !std::isfinite(a))
    throw ParameterError("kepler_propagate: the orbit is not bound (v^2 >= 2 GM / r); no elliptic closed form");
  if (!(h.norm() > 1e-14 * r * std::sqrt(v2)))
    throw ParameterError("kepler_propagate: the orbit is radial (r x v = 0); no elliptic closed form");
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
struct TwoBody : detail::ParticlePair<D> {
  static constexpr int coordinate_count = 2 * D;
  using detail::ParticlePair<D>::m1;
  using detail::ParticlePair<D>::m2;
  Potential U;
  TwoBody(double mass1, double mass2, Potential potential)
      : detail::ParticlePair<D>{require_positive("TwoBody", "m1", mass1), require_positive("TwoBody", "m2", mass2)},
        U(potential) {}
  std::string name() const { return "two_body"; }
  template <class S>
  S potential(const Vec<S, coordinate_count>& q, const S&) const {
    using std::sqrt;
    S r2 = S(0);
    for (int k = 0; k < D; ++k) r2 += (q[D + k] - q[k]) * (q[D + k] - q[k]);
    return U(sqrt(r2));
  }
  /// Newtonian gravity: the centre of mass moves uniformly and the relative
  /// coordinate follows the Kepler orbit with GM = k (m₁ + m₂)/(m₁ m₂).
  State<coordinate_count> reference(const State<coordinate_count>& initial, double t) const
    requires std::is_same_v<Potential, NewtonianGravity>
  {
    const double M = m1 + m2;
    Eigen::Vector3d R0 = Eigen::Vector3d::Zero(), V0 = Eigen::Vector3d::Zero();
    Eigen::Vector3d r0 = Eigen::Vector3d::Zero(), v0 = Eigen::Vector3d::Zero();
    R0.template head<D>() = (m1 * initial.q.template head<D>() + m2 * initial.q.template tail<D>()) / M;
    V0.template head<D>() = (m1 * initial.qd.template head<D>() + m2 * initial.qd.template tail<D>()) / M;
    r0.template head<D>() = initial.q.template tail<D>() - initial.q.template head<D>();
    v0.template head<D>() = initial.qd.template tail<D>() - initial.qd.template head<D>();
    const auto [r, v] = kepler_propagate(U.k * M / (m1 * m2), r0, v0, t);
    const Eigen::Vector3d R = R0 + V0 * t;
    State<coordinate_count> s;
    s.q << (R - m2 / M * r).template head<D>(), (R + m1 / M * r).template head<D>();
    s.qd << (V0 - m2 / M * v).template head<D>(), (V0 + m1 / M * v).template head<D>();
    return s;
  }
  /// A default scene: centre of mass at rest at the origin, the bodies at
  /// periapsis of a relative orbit a = 1 m, e = 0.5.
  State<coordinate_count> default_state() const
    requires std::is_same_v<Potential, NewtonianGravity>
  {
    const double M = m1 + m2;
    const KeplerOrbit orbit(1.0, 0.5, U.k * M / (m1 * m2));
    const double rp = orbit.periapsis_distance(), vp = orbit.periapsis_speed();
    State<coordinate_count> s;
    s.q[0] = -m2 / M * rp;
    s.q[D] = m1 / M * rp;
    s.qd[1] = -m2 / M * vp;
    s.qd[D + 1] = m1 / M * vp;
    return s;
  }
};

/// Two bodies with a central force given by its law F(r) (N; positive
/// repels, negative attracts) instead of a potential, as in notes 1.6:
///   T = ½ m₁|ṙ₁|² + ½ m₂|ṙ₂|²,  V = 0,
///   Q₁ = −F(r) r̂,  Q₂ = +F(r) r̂,  r̂ = (r₂ − r₁)/r.
/// `Force` is any callable `template <class S> S operator()(const S& r)`.
/// A conservative F is better given as TwoBody's U (then the energy
/// function is monitored as a conserved quantity); this form takes any F.
template <int D, class Force>
struct TwoBodyForce : detail::ParticlePair<D> {
  static constexpr int coordinate_count = 2 * D;
  Force F;
  TwoBodyForce(double mass1, double mass2, Force force)
      : detail::ParticlePair<D>{require_positive("TwoBodyForce", "m1", mass1),
                                require_positive("TwoBodyForce", "m2", mass2)},
        F(force) {}
  std::string name() const { return "two_body_force"; }
  template <class S>
  S potential(const Vec<S, coordinate_count>&, const S&) const {
    return S(0);
  }
  template <class S>
  Vec<S, coordinate_count> generalized_forces(const Vec<S, coordinate_count>& q, const Vec<S, coordinate_count>&, const S&) const {
    using std::sqrt;
    S r2 = S(0);
    for (int k = 0; k < D; ++k) r2 += (q[D + k] - q[k]) * (q[D + k] - q[k]);
    const S r = sqrt(r2);
    const S f = F(r) / r;
    Vec<S, coordinate_count> Q;
    for (int k = 0; k < D; ++k) {
      Q[k] = -f * (q[D + k] - q[k]);
      Q[D + k] = f * (q[D + k] - q[k]);
    }
    return Q;
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
  static constexpr int coordinate_count = D;
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
  /// Newtonian gravity: the Kepler orbit through `initial` (bound orbits),
  /// GM = k/μ.
  State<D> reference(const State<D>& initial, double t) const
    requires std::is_same_v<Potential, NewtonianGravity>
  {
    Eigen::Vector3d r0 = Eigen::Vector3d::Zero(), v0 = Eigen::Vector3d::Zero();
    r0.template head<D>() = initial.q;
    v0.template head<D>() = initial.qd;
    const auto [r, v] = kepler_propagate(U.k / mu, r0, v0, t);
    State<D> s;
    s.q = r.template head<D>();
    s.qd = v.template head<D>();
    return s;
  }
  /// A default scene: periapsis of the orbit a = 1 m, e = 0.5 (GM = k/μ).
  State<D> default_state() const {
    const KeplerOrbit orbit(1.0, 0.5, U.k / mu);
    State<D> s;
    s.q[0] = orbit.periapsis_distance();
    s.qd[1] = orbit.periapsis_speed();
    return s;
  }
};

/// The reduced problem of a gravitational pair: μ = m₁m₂/(m₁ + m₂) in
/// U = −G m₁ m₂ / r (the same k as the two-body problem).
template <int D>
RelativeMotion<D> gravitational_relative_motion(double m1, double m2, double G) {
  require_positive("RelativeMotion", "G", G);
  return RelativeMotion<D>(reduced_mass(m1, m2), NewtonianGravity{G * m1 * m2});
}

/// CODATA 2018 masses (kg): electron and proton (NIST, physics.nist.gov/constants).
inline constexpr double electron_mass = 9.1093837015e-31;
inline constexpr double proton_mass = 1.67262192369e-27;

}  // namespace lagrangian::models

// simulate() for these models is compiled once, in the library
// (src/models/); see lagrangian/detail/compiled_models.hpp.
#define LAGRANGIAN_TWO_BODY_MODELS(X) \
  X(lagrangian::models::TwoBody<2>) \
  X(lagrangian::models::RelativeMotion<2>)
LAGRANGIAN_TWO_BODY_MODELS(LAGRANGIAN_BUILT_IN_MODEL)
