#pragma once
/// \file pendulums.hpp
/// Pendulum-family, central-force and oscillator models in generalized coordinates.
/// SI units throughout: masses in kg, lengths in m, g in m/s², angles in rad,
/// stiffness in N/m, energies in J. Angles θ are measured from the downward
/// vertical unless stated otherwise.

#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>

#include "lagrangian/analysis/detail/compiled_tangent_flow.hpp"
#include "lagrangian/integrate/detail/compiled_models.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/model_description.hpp"
#include "lagrangian/models/pendulum_chain.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::models {

/// Plane pendulum: a point mass m on a massless rod of length l.
///   T = ½ m l² θ̇²,  V = −m g l cos θ.
template <class P = double>
struct BasicSimplePendulum {
  static constexpr int coordinate_count = 1;
  static constexpr ModelDescription description{
      "simple_pendulum",
      "Plane pendulum: point mass on a massless rod, theta from the downward vertical",
      {{"theta", "rad"}},
      {{"m", 1.0, "kg", "mass of the bob"},
       {"l", 1.0, "m", "length of the rod"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"}}};
  /// T = ½ m l² θ̇²: M constant (model.hpp, constant_mass_matrix_v).
  static constexpr bool constant_mass_matrix = true;
  P m, l, g;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicSimplePendulum<Q>;
  static constexpr std::array<P BasicSimplePendulum::*, 3> parameter_members() {
    return {&BasicSimplePendulum::m, &BasicSimplePendulum::l, &BasicSimplePendulum::g};
  }
  explicit BasicSimplePendulum(double mass = description.value("m"), double length = description.value("l"),
                               double gravity = description.value("g"))
      : m(require_positive("SimplePendulum", "m", mass)),
        l(require_positive("SimplePendulum", "l", length)),
        g(require_nonnegative("SimplePendulum", "g", gravity)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 1> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 1> coordinate_units() const { return description.coordinate_units(); }
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * m * l * l * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    using std::cos;
    return -m * g * l * cos(q[0]);
  }
  /// The exact motion from `initial` (any amplitude), with ω0 = √(g/l) (1/s)
  /// and the modulus k ≥ 0 fixed by the energy,
  ///   k² = (θ̇0 / 2ω0)² + sin²(θ0/2)   (k² = (h + m g l) / (2 m g l)).
  /// Libration (k < 1, the bob swings below the top, amplitude θmax = 2 asin k):
  ///   sin(θ/2) = k sn(ω0 t + u0 | k),  cos(θ/2) = dn(…),  θ̇ = 2 k ω0 cn(…),
  ///   u0 = F(φ0 | k) with sn u0 = sin φ0, cn u0 = cos φ0:
  ///   φ0 = atan2(sin(θ0/2), θ̇0/(2ω0)); period 4 K(k)/ω0.
  /// Rotation (k > 1, the bob goes over the top in the direction s = sign θ̇0):
  ///   θ/2 = s am(k ω0 t + v0 | 1/k),  θ̇ = 2 s k ω0 dn(…),  v0 = F(s θ0/2 | 1/k).
  /// Separatrix (k = 1): θ/2 = s gd(ω0 t + w0), θ̇ = 2 s ω0 sech(ω0 t + w0),
  ///   w0 = asinh(tan(s θ0/2)) (θ0 taken in [−π, π)); at rest at the top, θ stays.
  /// Modulus convention of Boost.Math (k, not m = k²); t in s from the start.
  State<1> reference(const State<1>& initial, double t) const {
    constexpr double pi = 3.141592653589793;
    const double theta0 = initial.q[0], rate0 = initial.qd[0];
    State<1> s;
    if (g == 0.0) {  // no restoring torque: uniform rotation
      s.q[0] = theta0 + rate0 * t;
      s.qd[0] = rate0;
      return s;
    }
    const double w0 = std::sqrt(g / l);
    // θ0 = 2π n + θr with θr in [−π, π): the motion is the same up to 2π n.
    const double turns = std::round(theta0 / (2 * pi));
    const double half = 0.5 * (theta0 - 2 * pi * turns), c = 0.5 * rate0 / w0;
    const double k2 = c * c + std::sin(half) * std::sin(half);
    if (k2 < 1.0) {
      const double k = std::sqrt(k2);
      const double u = w0 * t + boost::math::ellint_1(k, std::atan2(std::sin(half), c));
      double cn = 0;
      const double sn = boost::math::jacobi_elliptic(k, u, &cn, static_cast<double*>(nullptr));
      // dn = √(1 − k² sn²) > 0 computed here: Boost's dn is off by up to 1e-3
      // at odd multiples of K (the turning points; Boost 1.74 measured).
      const double dn = std::sqrt(1 - k2 * sn * sn);
      s.q[0] = 2 * pi * turns + 2 * std::atan2(k * sn, dn);
      s.qd[0] = 2 * k * w0 * cn;
      return s;
    }
    const double dir = rate0 < 0 ? -1.0 : 1.0;
    if (k2 > 1.0) {
      const double k = std::sqrt(k2), mod = 1 / k;
      const double u = k * w0 * t + boost::math::ellint_1(mod, dir * 0.5 * theta0);
      // am(u) = am(v) + jπ with v = u − 2K j in [−K, K], where cn(v) ≥ 0.
      const double period = 2 * boost::math::ellint_1(mod);
      const double j = std::round(u / period), v = u - period * j;
      double cn = 0;
      const double sn = boost::math::jacobi_elliptic(mod, v, &cn, static_cast<double*>(nullptr));
      const double dn = std::sqrt(1 - mod * mod * sn * sn);  // as above
      s.q[0] = 2 * dir * (std::atan2(sn, cn) + pi * j);
      s.qd[0] = 2 * dir * k * w0 * dn;
      return s;
    }
    if (rate0 == 0.0) {  // at rest at the top (unstable equilibrium)
      s.q[0] = theta0;
      s.qd[0] = 0.0;
      return s;
    }
    const double w = w0 * t + std::asinh(std::tan(dir * half));
    s.q[0] = 2 * pi * turns + 2 * dir * std::atan(std::sinh(w));
    s.qd[0] = 2 * dir * w0 / std::cosh(w);
    return s;
  }
};
/// The plane pendulum with parameters in double precision.
using SimplePendulum = BasicSimplePendulum<>;

/// Harmonic oscillator: a mass m on a linear spring of stiffness k, coordinate
/// x (m) from the spring's rest position.
///   T = ½ m ẋ²,  V = ½ k x²,  ẍ = −ω² x with ω = √(k/m) (rad/s), period 2π/ω.
template <class P = double>
struct BasicHarmonicOscillator {
  static constexpr int coordinate_count = 1;
  static constexpr ModelDescription description{
      "harmonic_oscillator",
      "Harmonic oscillator: mass on a linear spring, x from the rest position (closed form)",
      {{"x", "m"}},
      {{"m", 1.0, "kg", "mass"},
       {"k", 1.0, "N/m", "spring stiffness"}}};
  /// T = ½ m ẋ²: M constant (model.hpp, constant_mass_matrix_v).
  static constexpr bool constant_mass_matrix = true;
  P m, k;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicHarmonicOscillator<Q>;
  static constexpr std::array<P BasicHarmonicOscillator::*, 2> parameter_members() {
    return {&BasicHarmonicOscillator::m, &BasicHarmonicOscillator::k};
  }
  explicit BasicHarmonicOscillator(double mass = description.value("m"), double stiffness = description.value("k"))
      : m(require_positive("HarmonicOscillator", "m", mass)),
        k(require_positive("HarmonicOscillator", "k", stiffness)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 1> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 1> coordinate_units() const { return description.coordinate_units(); }
  /// Angular frequency ω = √(k/m) (rad/s).
  double omega() const { return std::sqrt(k / m); }
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * m * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    return 0.5 * k * q[0] * q[0];
  }
  /// The exact motion from `initial`:
  ///   x = x0 cos ωt + (ẋ0/ω) sin ωt,  ẋ = −x0 ω sin ωt + ẋ0 cos ωt.
  State<1> reference(const State<1>& initial, double t) const {
    const double w = omega(), c = std::cos(w * t), sn = std::sin(w * t);
    State<1> s;
    s.q[0] = initial.q[0] * c + initial.qd[0] / w * sn;
    s.qd[0] = -initial.q[0] * w * sn + initial.qd[0] * c;
    return s;
  }
};
/// The harmonic oscillator with parameters in double precision.
using HarmonicOscillator = BasicHarmonicOscillator<>;

/// Double pendulum: masses m1, m2 on massless rods l1, l2; θ1, θ2 from the
/// downward vertical.
///   T = ½ (m1+m2) l1² θ̇1² + ½ m2 l2² θ̇2² + m2 l1 l2 θ̇1 θ̇2 cos(θ1 − θ2),
///   V = −(m1+m2) g l1 cos θ1 − m2 g l2 cos θ2.
template <class P = double>
struct BasicDoublePendulum {
  static constexpr int coordinate_count = 2;
  static constexpr ModelDescription description{
      "double_pendulum",
      "Double pendulum: two point masses on massless rods, angles from the downward vertical",
      {{"theta1", "rad"}, {"theta2", "rad"}},
      {{"m1", 1.0, "kg", "mass of the upper bob"},
       {"m2", 1.0, "kg", "mass of the lower bob"},
       {"l1", 1.0, "m", "length of the upper rod"},
       {"l2", 1.0, "m", "length of the lower rod"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"}}};
  P m1, m2, l1, l2, g;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicDoublePendulum<Q>;
  static constexpr std::array<P BasicDoublePendulum::*, 5> parameter_members() {
    return {&BasicDoublePendulum::m1, &BasicDoublePendulum::m2, &BasicDoublePendulum::l1, &BasicDoublePendulum::l2,
            &BasicDoublePendulum::g};
  }
  explicit BasicDoublePendulum(double mass1 = description.value("m1"), double mass2 = description.value("m2"),
                               double length1 = description.value("l1"), double length2 = description.value("l2"),
                               double gravity = description.value("g"))
      : m1(require_positive("DoublePendulum", "m1", mass1)),
        m2(require_positive("DoublePendulum", "m2", mass2)),
        l1(require_positive("DoublePendulum", "l1", length1)),
        l2(require_positive("DoublePendulum", "l2", length2)),
        g(require_nonnegative("DoublePendulum", "g", gravity)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 2> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 2> coordinate_units() const { return description.coordinate_units(); }
  template <class S>
  S kinetic(const Vec<S, 2>& q, const Vec<S, 2>& qd, const S&) const {
    using std::cos;
    return 0.5 * (m1 + m2) * l1 * l1 * qd[0] * qd[0] + 0.5 * m2 * l2 * l2 * qd[1] * qd[1] +
           m2 * l1 * l2 * qd[0] * qd[1] * cos(q[0] - q[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    using std::cos;
    return -(m1 + m2) * g * l1 * cos(q[0]) - m2 * g * l2 * cos(q[1]);
  }
};
/// The double pendulum with parameters in double precision.
using DoublePendulum = BasicDoublePendulum<>;

/// Spherical pendulum: polar angle θ from the downward vertical, azimuth φ.
///   T = ½ m l² (θ̇² + sin²θ φ̇²),  V = −m g l cos θ.  φ is cyclic.
template <class P = double>
struct BasicSphericalPendulum {
  static constexpr int coordinate_count = 2;
  static constexpr ModelDescription description{
      "spherical_pendulum",
      "Spherical pendulum: polar angle theta from the downward vertical, azimuth phi (cyclic)",
      {{"theta", "rad"}, {"phi", "rad"}},
      {{"m", 1.0, "kg", "mass of the bob"},
       {"l", 1.0, "m", "length of the rod"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"}}};
  P m, l, g;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicSphericalPendulum<Q>;
  static constexpr std::array<P BasicSphericalPendulum::*, 3> parameter_members() {
    return {&BasicSphericalPendulum::m, &BasicSphericalPendulum::l, &BasicSphericalPendulum::g};
  }
  explicit BasicSphericalPendulum(double mass = description.value("m"), double length = description.value("l"),
                                  double gravity = description.value("g"))
      : m(require_positive("SphericalPendulum", "m", mass)),
        l(require_positive("SphericalPendulum", "l", length)),
        g(require_nonnegative("SphericalPendulum", "g", gravity)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 2> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 2> coordinate_units() const { return description.coordinate_units(); }
  template <class S>
  S kinetic(const Vec<S, 2>& q, const Vec<S, 2>& qd, const S&) const {
    using std::sin;
    const S s = sin(q[0]);
    return 0.5 * m * l * l * (qd[0] * qd[0] + s * s * qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    using std::cos;
    return -m * g * l * cos(q[0]);
  }
};
/// The spherical pendulum with parameters in double precision.
using SphericalPendulum = BasicSphericalPendulum<>;

/// Elastic (spring) pendulum: radial distance r and angle θ; spring of
/// stiffness k and rest length l0.
///   T = ½ m (ṙ² + r² θ̇²),  V = −m g r cos θ + ½ k (r − l0)².
template <class P = double>
struct BasicElasticPendulum {
  static constexpr int coordinate_count = 2;
  static constexpr ModelDescription description{
      "elastic_pendulum",
      "Elastic (spring) pendulum: radial distance r and angle theta of a mass on a spring",
      {{"r", "m"}, {"theta", "rad"}},
      {{"m", 1.0, "kg", "mass of the bob"},
       {"k", 40.0, "N/m", "spring stiffness"},
       {"l0", 1.0, "m", "rest length of the spring"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"}}};
  P m, k, l0, g;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicElasticPendulum<Q>;
  static constexpr std::array<P BasicElasticPendulum::*, 4> parameter_members() {
    return {&BasicElasticPendulum::m, &BasicElasticPendulum::k, &BasicElasticPendulum::l0, &BasicElasticPendulum::g};
  }
  explicit BasicElasticPendulum(double mass = description.value("m"), double stiffness = description.value("k"),
                                double rest_length = description.value("l0"), double gravity = description.value("g"))
      : m(require_positive("ElasticPendulum", "m", mass)),
        k(require_positive("ElasticPendulum", "k", stiffness)),
        l0(require_positive("ElasticPendulum", "l0", rest_length)),
        g(require_nonnegative("ElasticPendulum", "g", gravity)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 2> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 2> coordinate_units() const { return description.coordinate_units(); }
  template <class S>
  S kinetic(const Vec<S, 2>& q, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + q[0] * q[0] * qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    using std::cos;
    const S stretch = q[0] - l0;
    return -m * g * q[0] * cos(q[1]) + 0.5 * k * stretch * stretch;
  }
};
/// The elastic pendulum with parameters in double precision.
using ElasticPendulum = BasicElasticPendulum<>;

/// Bead of mass m on a circular hoop of radius R that spins at a constant
/// rate ω (rad/s) about its vertical diameter (a moving, rheonomic
/// constraint); θ measured from the bottom of the hoop.
///   T = ½ m R² (θ̇² + ω² sin²θ),  V = −m g R cos θ.
/// L has no explicit t, so the Jacobi integral h = ½ m R² (θ̇² − ω² sin²θ) + V
/// is conserved while T + V is not (the motor does work).
template <class P = double>
struct BasicBeadOnRotatingHoop {
  static constexpr int coordinate_count = 1;
  static constexpr ModelDescription description{
      "bead_on_rotating_hoop",
      "Bead on a hoop spinning at a constant rate about its vertical diameter (Jacobi integral conserved, T + V not)",
      {{"theta", "rad"}},
      {{"m", 1.0, "kg", "mass of the bead"},
       {"R", 0.5, "m", "radius of the hoop"},
       {"omega", 6.0, "rad/s", "spin rate of the hoop"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"}}};
  P m, R, omega, g;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicBeadOnRotatingHoop<Q>;
  static constexpr std::array<P BasicBeadOnRotatingHoop::*, 4> parameter_members() {
    using Self = BasicBeadOnRotatingHoop;
    return {&Self::m, &Self::R, &Self::omega, &Self::g};
  }
  explicit BasicBeadOnRotatingHoop(double mass = description.value("m"), double radius = description.value("R"),
                                   double spin_rate = description.value("omega"),
                                   double gravity = description.value("g"))
      : m(require_positive("BeadOnRotatingHoop", "m", mass)),
        R(require_positive("BeadOnRotatingHoop", "R", radius)),
        omega(require_finite("BeadOnRotatingHoop", "omega", spin_rate)),
        g(require_nonnegative("BeadOnRotatingHoop", "g", gravity)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 1> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 1> coordinate_units() const { return description.coordinate_units(); }
  /// The hoop's angle ωt enters the bead's position (R sinθ cos ωt,
  /// R sinθ sin ωt, −R cosθ); squaring its velocity, ωt cancels and leaves
  /// the azimuthal speed ω R sinθ.
  template <class S>
  S kinetic(const Vec<S, 1>& q, const Vec<S, 1>& qd, const S&) const {
    using std::sin;
    const S s = sin(q[0]);
    return 0.5 * m * R * R * (qd[0] * qd[0] + omega * omega * s * s);
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    using std::cos;
    return -m * g * R * cos(q[0]);
  }
};
/// The bead on a spinning hoop with parameters in double precision.
using BeadOnRotatingHoop = BasicBeadOnRotatingHoop<>;

/// Particle of mass m in the attractive inverse-square field V = −k/r, in
/// plane polar coordinates (r, φ); k = G M m (J·m).
///   T = ½ m (ṙ² + r² φ̇²).  φ is cyclic: p_φ = m r² φ̇ is conserved.
template <class P = double>
struct BasicKeplerPolar {
  static constexpr int coordinate_count = 2;
  static constexpr ModelDescription description{
      "kepler_polar",
      "Particle in the inverse-square field V = -k/r in plane polar coordinates (phi cyclic)",
      {{"r", "m"}, {"phi", "rad"}},
      {{"m", 1.0, "kg", "mass of the particle"},
       {"k", 1.0, "J*m", "strength of the field, k = G M m"}}};
  P m, k;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicKeplerPolar<Q>;
  static constexpr std::array<P BasicKeplerPolar::*, 2> parameter_members() {
    return {&BasicKeplerPolar::m, &BasicKeplerPolar::k};
  }
  explicit BasicKeplerPolar(double mass = description.value("m"), double strength = description.value("k"))
      : m(require_positive("KeplerPolar", "m", mass)), k(require_positive("KeplerPolar", "k", strength)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 2> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 2> coordinate_units() const { return description.coordinate_units(); }
  template <class S>
  S kinetic(const Vec<S, 2>& q, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + q[0] * q[0] * qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return -k / q[0];
  }
};
/// The particle in the inverse-square field with parameters in double precision.
using KeplerPolar = BasicKeplerPolar<>;

/// Pendulum (mass m, length l) hanging from a cart of mass M that slides on
/// a horizontal rail and is held by a spring of stiffness k; coordinates the
/// cart position x (m) and the pendulum angle θ.
///   T = ½ (M + m) ẋ² + m l ẋ θ̇ cos θ + ½ m l² θ̇²,  V = ½ k x² − m g l cos θ.
template <class P = double>
struct BasicCartPendulum {
  static constexpr int coordinate_count = 2;
  static constexpr ModelDescription description{
      "cart_pendulum",
      "Pendulum hanging from a cart that slides on a horizontal rail, held by a spring",
      {{"x", "m"}, {"theta", "rad"}},
      {{"M", 2.0, "kg", "mass of the cart"},
       {"m", 1.0, "kg", "mass of the bob"},
       {"l", 1.0, "m", "length of the rod"},
       {"k", 10.0, "N/m", "stiffness of the spring holding the cart"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"}}};
  P M, m, l, k, g;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicCartPendulum<Q>;
  static constexpr std::array<P BasicCartPendulum::*, 5> parameter_members() {
    using Self = BasicCartPendulum;
    return {&Self::M, &Self::m, &Self::l, &Self::k, &Self::g};
  }
  explicit BasicCartPendulum(double cart_mass = description.value("M"), double bob_mass = description.value("m"),
                             double length = description.value("l"), double stiffness = description.value("k"),
                             double gravity = description.value("g"))
      : M(require_positive("CartPendulum", "M", cart_mass)),
        m(require_positive("CartPendulum", "m", bob_mass)),
        l(require_positive("CartPendulum", "l", length)),
        k(require_nonnegative("CartPendulum", "k", stiffness)),
        g(require_nonnegative("CartPendulum", "g", gravity)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 2> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 2> coordinate_units() const { return description.coordinate_units(); }
  template <class S>
  S kinetic(const Vec<S, 2>& q, const Vec<S, 2>& qd, const S&) const {
    using std::cos;
    return 0.5 * (M + m) * qd[0] * qd[0] + m * l * qd[0] * qd[1] * cos(q[1]) + 0.5 * m * l * l * qd[1] * qd[1];
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    using std::cos;
    return 0.5 * k * q[0] * q[0] - m * g * l * cos(q[1]);
  }
};
/// The pendulum on a cart with parameters in double precision.
using CartPendulum = BasicCartPendulum<>;

/// Pendulum whose pivot is driven vertically, y_p(t) = a cos(Ω t) (a in m,
/// Ω in rad/s): an explicitly time-dependent Lagrangian.
///   T = ½ m (l² θ̇² + ẏ_p² + 2 l ẏ_p θ̇ sin θ),  V = m g (y_p − l cos θ),
/// whose equation of motion is θ̈ = −(g + ÿ_p) sin θ / l.
template <class P = double>
struct BasicDrivenPendulum {
  static constexpr int coordinate_count = 1;
  static constexpr ModelDescription description{
      "driven_pendulum",
      "Pendulum whose pivot is driven vertically, y_p = a cos(Omega t): time-dependent Lagrangian",
      {{"theta", "rad"}},
      {{"m", 1.0, "kg", "mass of the bob"},
       {"l", 1.0, "m", "length of the rod"},
       {"a", 0.05, "m", "amplitude of the pivot's motion"},
       {"Omega", 30.0, "rad/s", "angular frequency of the drive"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"}}};
  P m, l, a, Omega, g;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicDrivenPendulum<Q>;
  static constexpr std::array<P BasicDrivenPendulum::*, 5> parameter_members() {
    return {&BasicDrivenPendulum::m, &BasicDrivenPendulum::l, &BasicDrivenPendulum::a, &BasicDrivenPendulum::Omega,
            &BasicDrivenPendulum::g};
  }
  explicit BasicDrivenPendulum(double mass = description.value("m"), double length = description.value("l"),
                               double amplitude = description.value("a"),
                               double drive_rate = description.value("Omega"), double gravity = description.value("g"))
      : m(require_positive("DrivenPendulum", "m", mass)),
        l(require_positive("DrivenPendulum", "l", length)),
        a(require_finite("DrivenPendulum", "a", amplitude)),
        Omega(require_finite("DrivenPendulum", "Omega", drive_rate)),
        g(require_nonnegative("DrivenPendulum", "g", gravity)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 1> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 1> coordinate_units() const { return description.coordinate_units(); }
  template <class S>
  S kinetic(const Vec<S, 1>& q, const Vec<S, 1>& qd, const S& t) const {
    using std::sin;
    const S yd = -a * Omega * sin(Omega * t);
    return 0.5 * m * (l * l * qd[0] * qd[0] + yd * yd + 2.0 * l * yd * qd[0] * sin(q[0]));
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S& t) const {
    using std::cos;
    return m * g * (a * cos(Omega * t) - l * cos(q[0]));
  }
};
/// The driven pendulum with parameters in double precision.
using DrivenPendulum = BasicDrivenPendulum<>;

/// What a scene names built-in models that are presets of the templates above
/// and in pendulum_chain.hpp
/// (the registry builds each from its description's parameters).
namespace presets {

/// PendulumChain<3> with equal masses and rods.
inline constexpr ModelDescription pendulum_chain_3{
    "pendulum_chain_3",
    "Planar chain of three equal point masses on equal massless rods, angles from the downward vertical",
    {{"theta1", "rad"}, {"theta2", "rad"}, {"theta3", "rad"}},
    {{"m", 1.0, "kg", "mass of each bob"},
     {"l", 1.0, "m", "length of each rod"},
     {"g", 9.81, "m/s^2", "acceleration of gravity"}}};

}  // namespace presets

}  // namespace lagrangian::models

// simulate() and the tangent flow (Lyapunov, Floquet, sensitivities) for
// these models are compiled once, in the library (src/models/); see
// lagrangian/integrate/detail/compiled_models.hpp and
// lagrangian/analysis/detail/compiled_tangent_flow.hpp.
#define LAGRANGIAN_PENDULUM_MODELS_A(X) \
  X(lagrangian::models::SimplePendulum) \
  X(lagrangian::models::HarmonicOscillator) \
  X(lagrangian::models::DoublePendulum) \
  X(lagrangian::models::SphericalPendulum) \
  X(lagrangian::models::ElasticPendulum)
LAGRANGIAN_PENDULUM_MODELS_A(LAGRANGIAN_BUILT_IN_MODEL)
LAGRANGIAN_PENDULUM_MODELS_A(LAGRANGIAN_EXTERN_TANGENT_FLOW)
#define LAGRANGIAN_PENDULUM_MODELS_B(X) \
  X(lagrangian::models::BeadOnRotatingHoop) \
  X(lagrangian::models::KeplerPolar) \
  X(lagrangian::models::CartPendulum) \
  X(lagrangian::models::DrivenPendulum) \
  X(lagrangian::models::PendulumChain<3>)
LAGRANGIAN_PENDULUM_MODELS_B(LAGRANGIAN_BUILT_IN_MODEL)
LAGRANGIAN_PENDULUM_MODELS_B(LAGRANGIAN_EXTERN_TANGENT_FLOW)
