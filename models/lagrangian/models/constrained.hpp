#pragma once
/// \file constrained.hpp
/// Constrained systems written in redundant coordinates with holonomic or
/// Pfaffian constraints (see constraints.hpp). SI units; gravity along −y
/// (planar models) or −z (spatial models). With g = 0 for a constraint of the
/// form |r| − l, the multiplier λ is the force along +∇g = r̂: a rod in tension
/// T has λ = −T.

#include <array>
#include <cmath>
#include <string>
#include <string_view>

#include "lagrangian/analysis/detail/compiled_tangent_flow.hpp"
#include "lagrangian/integrate/detail/compiled_models.hpp"
#include "lagrangian/mechanics/impact.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/model_description.hpp"
#include "lagrangian/models/detail/particles.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::models {


/// Bead of mass m on a straight wire through the origin at angle α to the
/// horizontal, in a vertical plane; coordinates (x, y).
///   T = ½ m (ẋ² + ẏ²),  V = m g y,  g_wire = x sin α − y cos α = 0.
/// Along the wire s̈ = −g sin α.
struct BeadOnWire : detail::PlanarParticle<> {
  static constexpr int coordinate_count = 2;
  double alpha;
  explicit BeadOnWire(double mass = 1.0, double angle = 0.5, double gravity = 9.81)
      : PlanarParticle{require_positive("BeadOnWire", "m", mass), require_nonnegative("BeadOnWire", "g", gravity)},
        alpha(require_finite("BeadOnWire", "alpha", angle)) {}
  std::string name() const { return "bead_on_wire"; }
  std::array<std::string_view, 1> holonomic_names() const { return {"wire"}; }
  std::array<std::string_view, 1> constraint_units() const { return {"m"}; }  ///< g in m: λ in N
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(q[0] * std::sin(alpha) - q[1] * std::cos(alpha));
  }
};

/// Bead on a straight horizontal wire that spins at a constant rate ω about a
/// vertical axis through the origin (a rheonomic constraint); coordinates
/// (x, y) in the horizontal plane, no gravity in that plane.
///   g = x sin ωt − y cos ωt = 0.  Radially r̈ = ω² r, so
///   r(t) = r0 cosh ωt + (ṙ0/ω) sinh ωt.
/// Domain: the wire reaches L (m) either side of the axis; the bead slides
/// off its end where r = L, the watched event "bead_at_wire_end"
/// (L − r falls through 0), which stops the run.
template <class P = double>
struct BasicBeadOnRotatingWire {
  static constexpr int coordinate_count = 2;
  static constexpr ModelDescription description{
      "bead_on_rotating_wire",
      "Bead on a straight horizontal wire spinning about a vertical axis (rheonomic holonomic constraint); stops at "
      "the wire's end",
      {{"x", "m"}, {"y", "m"}},
      {{"m", 1.0, "kg", "mass of the bead"},
       {"omega", 2.0, "rad/s", "spin rate of the wire"},
       {"L", 10.0, "m", "reach of the wire either side of the axis: the bead leaves its end at r = L"}}};
  P m, omega, L;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicBeadOnRotatingWire<Q>;
  static constexpr std::array<P BasicBeadOnRotatingWire::*, 3> parameter_members() {
    return {&BasicBeadOnRotatingWire::m, &BasicBeadOnRotatingWire::omega, &BasicBeadOnRotatingWire::L};
  }
  explicit BasicBeadOnRotatingWire(double mass = description.value("m"), double spin_rate = description.value("omega"),
                                   double half_length = description.value("L"))
      : m(require_positive("BeadOnRotatingWire", "m", mass)),
        omega(require_finite("BeadOnRotatingWire", "omega", spin_rate)),
        L(require_positive("BeadOnRotatingWire", "L", half_length)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 2> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 2> coordinate_units() const { return description.coordinate_units(); }
  std::array<std::string_view, 1> holonomic_names() const { return {"wire"}; }
  std::array<std::string_view, 1> constraint_units() const { return {"m"}; }  ///< g in m: λ in N
  /// L − r (m): the bead's distance from the wire's end.
  template <class S>
  Vec<S, 1> events(const Vec<S, 2>& q, const Vec<S, 2>&, const S&) const {
    using std::sqrt;
    return Vec<S, 1>(L - sqrt(q[0] * q[0] + q[1] * q[1]));
  }
  std::array<EventSpec, 1> event_specs() const {
    return {EventSpec{"bead_at_wire_end", Direction::falling, EventAction::stop}};
  }
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>&, const S&) const {
    return S(0);
  }
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 2>& q, const S& t) const {
    using std::cos;
    using std::sin;
    return Vec<S, 1>(q[0] * sin(omega * t) - q[1] * cos(omega * t));
  }
};
/// The bead on a spinning wire with parameters in double precision.
using BeadOnRotatingWire = BasicBeadOnRotatingWire<>;

/// Plane pendulum as a particle (x, y) held at distance l from the pivot.
///   T = ½ m (ẋ² + ẏ²),  V = m g y,  g_rod = √(x² + y²) − l = 0.
struct CartesianPendulum : detail::PlanarParticle<> {
  static constexpr int coordinate_count = 2;
  double l;
  explicit CartesianPendulum(double mass = 1.0, double length = 1.0, double gravity = 9.81)
      : PlanarParticle{require_positive("CartesianPendulum", "m", mass),
                       require_nonnegative("CartesianPendulum", "g", gravity)},
        l(require_positive("CartesianPendulum", "l", length)) {}
  std::string name() const { return "cartesian_pendulum"; }
  std::array<std::string_view, 1> holonomic_names() const { return {"rod"}; }
  std::array<std::string_view, 1> constraint_units() const { return {"m"}; }  ///< g in m: λ in N
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 2>& q, const S&) const {
    using std::sqrt;
    return Vec<S, 1>(sqrt(q[0] * q[0] + q[1] * q[1]) - l);
  }
};

/// Particle (x, y, z) on a sphere of radius R about the origin, gravity −z:
/// the spherical pendulum in Cartesian coordinates.
template <class P = double>
struct BasicParticleOnSphere {
  static constexpr int coordinate_count = 3;
  static constexpr ModelDescription description{
      "particle_on_sphere",
      "Particle on a sphere about the origin, gravity along -z: the spherical pendulum in Cartesian coordinates",
      {{"x", "m"}, {"y", "m"}, {"z", "m"}},
      {{"m", 1.0, "kg", "mass of the particle"},
       {"R", 1.0, "m", "radius of the sphere"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"}}};
  P m, R, g;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicParticleOnSphere<Q>;
  static constexpr std::array<P BasicParticleOnSphere::*, 3> parameter_members() {
    return {&BasicParticleOnSphere::m, &BasicParticleOnSphere::R, &BasicParticleOnSphere::g};
  }
  explicit BasicParticleOnSphere(double mass = description.value("m"), double radius = description.value("R"),
                                 double gravity = description.value("g"))
      : m(require_positive("ParticleOnSphere", "m", mass)),
        R(require_positive("ParticleOnSphere", "R", radius)),
        g(require_nonnegative("ParticleOnSphere", "g", gravity)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 3> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 3> coordinate_units() const { return description.coordinate_units(); }
  /// One particle at (x, y, z): P and L are reported, L_z conserved.
  std::array<Particle, 1> particles() const { return {Particle{m, {0, 1, 2}}}; }
  std::array<std::string_view, 1> holonomic_names() const { return {"sphere"}; }
  std::array<std::string_view, 1> constraint_units() const { return {"m"}; }  ///< g in m: λ in N
  template <class S>
  S kinetic(const Vec<S, 3>&, const Vec<S, 3>& qd, const S&) const {
    return 0.5 * m * qd.squaredNorm();
  }
  template <class S>
  S potential(const Vec<S, 3>& q, const S&) const {
    return m * g * q[2];
  }
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 3>& q, const S&) const {
    using std::sqrt;
    return Vec<S, 1>(sqrt(q.squaredNorm()) - R);
  }
};
/// The particle on a sphere with parameters in double precision.
using ParticleOnSphere = BasicParticleOnSphere<>;

/// Atwood machine: masses m1, m2 at heights y1, y2 (m, up) on an
/// inextensible string over a massless pulley whose axle is at height
/// c/2 + d; g_string = y1 + y2 − c = 0.
/// Closed form: ÿ1 = −(m1 − m2) g / (m1 + m2), tension 2 m1 m2 g / (m1 + m2).
/// Domain: a mass reaching the pulley (y_i = c/2 + d) ends the model's
/// motion: the watched events "mass1_at_pulley" and "mass2_at_pulley"
/// (c/2 + d − y_i falls through 0) stop the run. The string never goes
/// slack: its tension, the multiplier, is 2 m1 m2 g / (m1 + m2) ≥ 0 at every
/// state, whatever the velocities.
template <class P = double>
struct BasicAtwoodMachine {
  static constexpr int coordinate_count = 2;
  static constexpr ModelDescription description{
      "atwood_machine",
      "Atwood machine: two masses on a string over a massless pulley, y1 + y2 = c; stops where a mass reaches the "
      "pulley",
      {{"y1", "m"}, {"y2", "m"}},
      {{"m1", 3.0, "kg", "first mass"},
       {"m2", 1.0, "kg", "second mass"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"},
       {"c", 0.0, "m", "string constant: y1 + y2 = c"},
       {"d", 1.0, "m", "height of the pulley's axle above c/2: a mass reaching it stops the run"}}};
  P m1, m2, g, c, d;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicAtwoodMachine<Q>;
  static constexpr std::array<P BasicAtwoodMachine::*, 5> parameter_members() {
    return {&BasicAtwoodMachine::m1, &BasicAtwoodMachine::m2, &BasicAtwoodMachine::g, &BasicAtwoodMachine::c,
            &BasicAtwoodMachine::d};
  }
  explicit BasicAtwoodMachine(double mass1 = description.value("m1"), double mass2 = description.value("m2"),
                              double gravity = description.value("g"), double length = description.value("c"),
                              double pulley_height = description.value("d"))
      : m1(require_positive("AtwoodMachine", "m1", mass1)),
        m2(require_positive("AtwoodMachine", "m2", mass2)),
        g(require_nonnegative("AtwoodMachine", "g", gravity)),
        c(require_finite("AtwoodMachine", "c", length)),
        d(require_positive("AtwoodMachine", "d", pulley_height)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 2> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 2> coordinate_units() const { return description.coordinate_units(); }
  std::array<std::string_view, 1> holonomic_names() const { return {"string"}; }
  std::array<std::string_view, 1> constraint_units() const { return {"m"}; }  ///< g in m: λ, the tension, in N
  /// Height of the pulley's axle (m), where a mass reaches the pulley.
  P pulley_axle() const { return 0.5 * c + d; }
  /// c/2 + d − y_i (m): each mass's distance below the pulley's axle.
  template <class S>
  Vec<S, 2> events(const Vec<S, 2>& q, const Vec<S, 2>&, const S&) const {
    return Vec<S, 2>(pulley_axle() - q[0], pulley_axle() - q[1]);
  }
  std::array<EventSpec, 2> event_specs() const {
    return {EventSpec{"mass1_at_pulley", Direction::falling, EventAction::stop},
            EventSpec{"mass2_at_pulley", Direction::falling, EventAction::stop}};
  }
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m1 * qd[0] * qd[0] + 0.5 * m2 * qd[1] * qd[1];
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return m1 * g * q[0] + m2 * g * q[1];
  }
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(q[0] + q[1] - c);
  }
};
/// The Atwood machine with parameters in double precision.
using AtwoodMachine = BasicAtwoodMachine<>;

/// Double pendulum in Cartesian coordinates (x1, y1, x2, y2) with two rod
/// constraints |r1| = l1 and |r2 − r1| = l2.
template <class P = double>
struct BasicCartesianDoublePendulum {
  static constexpr int coordinate_count = 4;
  static constexpr ModelDescription description{
      "cartesian_double_pendulum",
      "Double pendulum in Cartesian coordinates with two rod constraints",
      {{"x1", "m"}, {"y1", "m"}, {"x2", "m"}, {"y2", "m"}},
      {{"m1", 1.0, "kg", "mass of the upper bob"},
       {"m2", 1.0, "kg", "mass of the lower bob"},
       {"l1", 1.0, "m", "length of the upper rod"},
       {"l2", 1.0, "m", "length of the lower rod"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"}}};
  P m1, m2, l1, l2, g;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicCartesianDoublePendulum<Q>;
  static constexpr std::array<P BasicCartesianDoublePendulum::*, 5> parameter_members() {
    using Self = BasicCartesianDoublePendulum;
    return {&Self::m1, &Self::m2, &Self::l1, &Self::l2, &Self::g};
  }
  explicit BasicCartesianDoublePendulum(double mass1 = description.value("m1"), double mass2 = description.value("m2"),
                                        double length1 = description.value("l1"),
                                        double length2 = description.value("l2"),
                                        double gravity = description.value("g"))
      : m1(require_positive("CartesianDoublePendulum", "m1", mass1)),
        m2(require_positive("CartesianDoublePendulum", "m2", mass2)),
        l1(require_positive("CartesianDoublePendulum", "l1", length1)),
        l2(require_positive("CartesianDoublePendulum", "l2", length2)),
        g(require_nonnegative("CartesianDoublePendulum", "g", gravity)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 4> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 4> coordinate_units() const { return description.coordinate_units(); }
  /// The two bobs in the x–y plane: P and L are reported (neither is
  /// conserved: the pivot and gravity act on the system).
  std::array<Particle, 2> particles() const { return {Particle{m1, {0, 1, -1}}, Particle{m2, {2, 3, -1}}}; }
  std::array<std::string_view, 2> holonomic_names() const { return {"rod1", "rod2"}; }
  std::array<std::string_view, 2> constraint_units() const { return {"m", "m"}; }  ///< g in m: λ in N
  template <class S>
  S kinetic(const Vec<S, 4>&, const Vec<S, 4>& qd, const S&) const {
    return 0.5 * m1 * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * m2 * (qd[2] * qd[2] + qd[3] * qd[3]);
  }
  template <class S>
  S potential(const Vec<S, 4>& q, const S&) const {
    return m1 * g * q[1] + m2 * g * q[3];
  }
  template <class S>
  Vec<S, 2> holonomic(const Vec<S, 4>& q, const S&) const {
    using std::sqrt;
    const S dx = q[2] - q[0], dy = q[3] - q[1];
    return Vec<S, 2>(sqrt(q[0] * q[0] + q[1] * q[1]) - l1, sqrt(dx * dx + dy * dy) - l2);
  }
};
/// The double pendulum in Cartesian coordinates with parameters in double precision.
using CartesianDoublePendulum = BasicCartesianDoublePendulum<>;

/// Knife edge (or skate) on a horizontal plane: contact point (x, y), heading
/// φ; it cannot slide sideways, a nonholonomic (Pfaffian) constraint
///   ẋ sin φ − ẏ cos φ = 0.
///   T = ½ m (ẋ² + ẏ²) + ½ I φ̇².
/// Configuration DOF 3, velocity DOF 2. Free motion: φ̇ and the speed are
/// constant and the contact point runs on a circle of radius v/φ̇.
template <class P = double>
struct BasicKnifeEdge {
  static constexpr int coordinate_count = 3;
  static constexpr ModelDescription description{
      "knife_edge",
      "Knife edge (skate) on a horizontal plane: no sideslip, a nonholonomic (Pfaffian) constraint",
      {{"x", "m"}, {"y", "m"}, {"phi", "rad"}},
      {{"m", 1.0, "kg", "mass"},
       {"I", 0.1, "kg*m^2", "moment of inertia about the vertical"}}};
  P m, I;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's order.
  template <class Q>
  using with_parameter_type = BasicKnifeEdge<Q>;
  static constexpr std::array<P BasicKnifeEdge::*, 2> parameter_members() {
    return {&BasicKnifeEdge::m, &BasicKnifeEdge::I};
  }
  explicit BasicKnifeEdge(double mass = description.value("m"), double inertia = description.value("I"))
      : m(require_positive("KnifeEdge", "m", mass)), I(require_positive("KnifeEdge", "I", inertia)) {}
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 3> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 3> coordinate_units() const { return description.coordinate_units(); }
  std::array<std::string_view, 1> pfaffian_names() const { return {"no_sideslip"}; }
  /// A δq = δx sin φ − δy cos φ is a sideways displacement (m): λ, the side force, in N.
  std::array<std::string_view, 1> constraint_units() const { return {"m"}; }
  template <class S>
  S kinetic(const Vec<S, 3>&, const Vec<S, 3>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * I * qd[2] * qd[2];
  }
  template <class S>
  S potential(const Vec<S, 3>&, const S&) const {
    return S(0);
  }
  template <class S>
  Vec<S, 1> pfaffian(const Vec<S, 3>& q, const Vec<S, 3>& qd, const S&) const {
    using std::cos;
    using std::sin;
    return Vec<S, 1>(qd[0] * sin(q[2]) - qd[1] * cos(q[2]));
  }
};
/// The knife edge with parameters in double precision.
using KnifeEdge = BasicKnifeEdge<>;

/// Particle (x, y) sliding without friction on the outside of a smooth
/// sphere (a circle in the vertical plane) of radius R centred at the origin;
/// gravity −y. The surface pushes but cannot pull: the unilateral constraint
///   g = √(x² + y²) − R ≥ 0.
/// Released at rest at angle θ0 from the top, the normal force is
/// N = m g (3 cos θ − 2 cos θ0) and the particle leaves where it vanishes,
/// cos θ* = (2/3) cos θ0.
struct ParticleOffSphere : detail::PlanarParticle<> {
  static constexpr int coordinate_count = 2;
  double R;
  explicit ParticleOffSphere(double mass = 1.0, double radius = 1.0, double gravity = 9.81)
      : PlanarParticle{require_positive("ParticleOffSphere", "m", mass),
                       require_nonnegative("ParticleOffSphere", "g", gravity)},
        R(require_positive("ParticleOffSphere", "R", radius)) {}
  std::string name() const { return "particle_off_sphere"; }
  std::array<std::string_view, 1> unilateral_names() const { return {"surface"}; }
  std::array<std::string_view, 1> constraint_units() const { return {"m"}; }  ///< gap in m: λ in N
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 2>& q, const S&) const {
    using std::sqrt;
    return Vec<S, 1>(sqrt(q[0] * q[0] + q[1] * q[1]) - R);
  }
};

}  // namespace lagrangian::models

// simulate() and the tangent flow (Lyapunov, Floquet, sensitivities) for
// these models are compiled once, in the library (src/models/); see
// lagrangian/integrate/detail/compiled_models.hpp and
// lagrangian/analysis/detail/compiled_tangent_flow.hpp.
#define LAGRANGIAN_CONSTRAINED_MODELS_A(X) \
  X(lagrangian::models::BeadOnWire) \
  X(lagrangian::models::BeadOnRotatingWire) \
  X(lagrangian::models::CartesianPendulum) \
  X(lagrangian::models::ParticleOnSphere)
LAGRANGIAN_CONSTRAINED_MODELS_A(LAGRANGIAN_BUILT_IN_MODEL)
LAGRANGIAN_CONSTRAINED_MODELS_A(LAGRANGIAN_EXTERN_TANGENT_FLOW)
#define LAGRANGIAN_CONSTRAINED_MODELS_B(X) \
  X(lagrangian::models::AtwoodMachine) \
  X(lagrangian::models::CartesianDoublePendulum) \
  X(lagrangian::models::KnifeEdge) \
  X(lagrangian::models::ParticleOffSphere)
LAGRANGIAN_CONSTRAINED_MODELS_B(LAGRANGIAN_BUILT_IN_MODEL)
LAGRANGIAN_CONSTRAINED_MODELS_B(LAGRANGIAN_EXTERN_TANGENT_FLOW)
