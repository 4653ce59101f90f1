#pragma once
/// \file two_body.hpp
/// The two-body problem and its reduction to one body of reduced mass
/// (course notes 1.6) and the hydrogen atom's
/// reduced mass (Kepler's closed forms are in kepler.hpp). SI units.
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
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "lagrangian/mechanics/impact.hpp"
#include "lagrangian/analysis/detail/compiled_tangent_flow.hpp"
#include "lagrangian/integrate/detail/compiled_models.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/model_description.hpp"
#include "lagrangian/models/detail/particles.hpp"
#include "lagrangian/models/kepler.hpp"
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
/// (J·m); the force on each body points to the other, |F| = k/r². P is
/// k's type (parameter sensitivities, analysis/sensitivity.hpp); k is 1 J·m
/// unless given, as in the scenes' `two_body` and `kepler`.
template <class P = double>
struct BasicNewtonianGravity {
  P k = P(1.0);
  template <class S>
  S operator()(const S& r) const {
    return -k / r;
  }
};
/// Newtonian gravity with k in double precision.
using NewtonianGravity = BasicNewtonianGravity<>;

namespace detail {
/// The parameters' type of a model over `Potential`: k's type for Newtonian
/// gravity, double for any other potential.
template <class Potential>
struct potential_parameter {
  using type = double;
};
template <class P>
struct potential_parameter<BasicNewtonianGravity<P>> {
  using type = P;
};
/// True for Newtonian gravity of any parameter type.
template <class Potential>
inline constexpr bool is_newtonian_v = false;
template <class P>
inline constexpr bool is_newtonian_v<BasicNewtonianGravity<P>> = true;
}  // namespace detail

/// Two bodies interacting through a central potential U(r) in D = 2 or 3
/// dimensions; coordinates (x₁, y₁[, z₁], x₂, y₂[, z₂]) (m).
///   T = ½ m₁|ṙ₁|² + ½ m₂|ṙ₂|²,  V = U(|r₂ − r₁|).
/// `Potential` is any callable `template <class S> S operator()(const S& r)`
/// giving U in J (NewtonianGravity by default). Under Newtonian gravity the
/// masses and k are numbers of k's type, and the model offers parameter
/// sensitivities (analysis/sensitivity.hpp) along m1, m2 and k.
template <int D, class Potential = NewtonianGravity>
struct TwoBody : detail::ParticlePair<D, typename detail::potential_parameter<Potential>::type> {
  using parameter_type = typename detail::potential_parameter<Potential>::type;
  static constexpr int coordinate_count = 2 * D;
  using detail::ParticlePair<D, parameter_type>::m1;
  using detail::ParticlePair<D, parameter_type>::m2;
  Potential U;
  /// The model with parameters of type Q, and its parameters (m1, m2, k:
  /// the scene's `two_body`), read through accessors as k sits in U.
  template <class Q>
  using with_parameter_type = TwoBody<D, BasicNewtonianGravity<Q>>;
  static constexpr std::array<std::string_view, 3> parameter_names{"m1", "m2", "k"};
  static constexpr std::array<parameter_type& (*)(TwoBody&), 3> parameter_members()
    requires detail::is_newtonian_v<Potential>
  {
    return {[](TwoBody& b) -> parameter_type& { return b.m1; }, [](TwoBody& b) -> parameter_type& { return b.m2; },
            [](TwoBody& b) -> parameter_type& { return b.U.k; }};
  }
  /// Unit masses in the default potential (for Newtonian gravity k = 1 J·m:
  /// the scene `two_body`'s defaults).
  TwoBody() : TwoBody(1.0, 1.0, Potential{}) {}
  TwoBody(double mass1, double mass2, Potential potential)
      : detail::ParticlePair<D, parameter_type>{require_positive("TwoBody", "m1", mass1),
                                                require_positive("TwoBody", "m2", mass2)},
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
/// Under Newtonian gravity μ and k are numbers of k's type, and the model
/// offers parameter sensitivities (analysis/sensitivity.hpp) along μ and k.
template <int D, class Potential = NewtonianGravity>
struct RelativeMotion {
  static_assert(D == 2 || D == 3, "RelativeMotion is planar (D = 2) or spatial (D = 3)");
  using parameter_type = typename detail::potential_parameter<Potential>::type;
  static constexpr int coordinate_count = D;
  /// T = ½ μ|ṙ|²: M constant (model.hpp, constant_mass_matrix_v).
  static constexpr bool constant_mass_matrix = true;
  parameter_type mu;
  Potential U;
  /// The model with parameters of type Q, and its parameters (mu, k: the
  /// scene's `kepler`), read through accessors as k sits in U.
  template <class Q>
  using with_parameter_type = RelativeMotion<D, BasicNewtonianGravity<Q>>;
  static constexpr std::array<std::string_view, 2> parameter_names{"mu", "k"};
  static constexpr std::array<parameter_type& (*)(RelativeMotion&), 2> parameter_members()
    requires detail::is_newtonian_v<Potential>
  {
    return {[](RelativeMotion& b) -> parameter_type& { return b.mu; },
            [](RelativeMotion& b) -> parameter_type& { return b.U.k; }};
  }
  /// μ = 1 kg in the default potential (for Newtonian gravity k = 1 J·m:
  /// the scene `kepler`'s defaults).
  RelativeMotion() : RelativeMotion(1.0, Potential{}) {}
  RelativeMotion(double reduced, Potential potential)
      : mu(require_positive("RelativeMotion", "mu", reduced)), U(potential) {}
  std::string name() const { return "relative_motion"; }
  std::vector<std::string> coordinate_names() const {
    const char* axes[] = {"x", "y", "z"};
    return std::vector<std::string>(axes, axes + D);
  }
  std::vector<std::string> coordinate_units() const { return std::vector<std::string>(D, "m"); }
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
  /// Newtonian gravity: the Kepler orbit through `initial` (any conic;
  /// kepler_propagate), GM = k/μ.
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


/// What a scene names built-in models that are presets of the templates above
/// (the registry builds each from its description's parameters).
namespace presets {

/// TwoBody<2>: with unit masses and k = 1 J*m, a relative orbit of
/// semi-major axis 1 m has the period 2π/√2 s.
inline constexpr ModelDescription two_body{
    "two_body",
    "Two bodies under Newtonian gravity V = -k/r in a plane",
    {{"x1", "m"}, {"y1", "m"}, {"x2", "m"}, {"y2", "m"}},
    {{"m1", 1.0, "kg", "mass of body 1"},
     {"m2", 1.0, "kg", "mass of body 2"},
     {"k", 1.0, "J*m", "strength of the attraction, k = G m1 m2"}}};

/// RelativeMotion<2>: with μ = 1 kg and k = 1 J*m, an orbit of semi-major
/// axis 1 m has the period 2π s.
inline constexpr ModelDescription kepler{
    "kepler",
    "Reduced two-body problem: a body of reduced mass mu in V = -k/r, with a periapsis event",
    {{"x", "m"}, {"y", "m"}},
    {{"mu", 1.0, "kg", "reduced mass m1 m2 / (m1 + m2)"},
     {"k", 1.0, "J*m", "strength of the attraction, k = G m1 m2"}}};

}  // namespace presets

}  // namespace lagrangian::models

// simulate() and the tangent flow (Lyapunov, Floquet, sensitivities) for
// these models are compiled once, in the library (src/models/); see
// lagrangian/integrate/detail/compiled_models.hpp and
// lagrangian/analysis/detail/compiled_tangent_flow.hpp.
#define LAGRANGIAN_TWO_BODY_MODELS(X) \
  X(lagrangian::models::TwoBody<2>) \
  X(lagrangian::models::RelativeMotion<2>)
LAGRANGIAN_TWO_BODY_MODELS(LAGRANGIAN_BUILT_IN_MODEL)
LAGRANGIAN_TWO_BODY_MODELS(LAGRANGIAN_EXTERN_TANGENT_FLOW)
