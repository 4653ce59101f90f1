#pragma once
// Models with contacts written for the tests of the tangent flow across
// impacts (test_saltation.cpp, and their text forms in
// test_text_tangent.cpp): a gap that moves with time, a mass matrix and gap
// gradient that move with the coordinates, a number of contacts chosen at
// run time (also test_unilateral.cpp), and contacts of models with
// holonomic rows (test_constrained_tangent.cpp).

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "lagrangian/ad.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/detail/particles.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace lagrangian::testing {

/// A ball on a table that moves up and down, z_table = A sin ωt: the gap
/// φ = z − A sin ωt changes with t (the saltation matrix's R_t and the
/// impact law's ∂φ/∂t). Its parameters may carry derivatives
/// (sensitivity.hpp), so that a parameter column can be asked for.
template <class P = double>
struct BouncingBall {
  static constexpr int coordinate_count = 1;
  static constexpr std::array<std::string_view, 4> parameter_names{"g", "e", "amplitude", "omega"};
  template <class Q>
  using with_parameter_type = BouncingBall<Q>;
  static constexpr std::array<P BouncingBall::*, 4> parameter_members() {
    return {&BouncingBall::g, &BouncingBall::e, &BouncingBall::amplitude, &BouncingBall::omega};
  }
  P g = 9.81, e = 0.8, amplitude = 0.05, omega = 10.0;
  std::string name() const { return "bouncing_ball"; }
  std::array<P, 1> restitution() const { return {e}; }
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    return g * q[0];
  }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 1>& q, const S& t) const {
    using std::sin;
    return Vec<S, 1>(q[0] - amplitude * sin(omega * t));
  }
};

/// The double pendulum (1 kg, 1 m each) whose lower bob meets a wall at
/// x = 0.9 m: M depends on the angles and the gap's gradient turns with
/// them (∂q̇⁺/∂q ≠ 0 through both).
struct DoublePendulumAgainstWall : models::DoublePendulum {
  std::string name() const { return "double_pendulum_against_wall"; }
  std::array<double, 1> restitution() const { return {0.9}; }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 2>& q, const S&) const {
    using std::sin;
    return Vec<S, 1>(0.9 - (l1 * sin(q[0]) + l2 * sin(q[1])));
  }
};

/// The plane pendulum as a particle (x, y) on a rod (CartesianPendulum: a
/// holonomic row √(x² + y²) − l = 0) whose bob meets a wall at x = a (m):
/// the contact φ = a − x ≥ 0 with restitution e.
struct RodPendulumAgainstWall : models::CartesianPendulum {
  double a = 0.5, e = 0.8;
  std::string name() const { return "rod_pendulum_against_wall"; }
  std::array<std::string_view, 1> unilateral_names() const { return {"wall"}; }
  std::array<std::string_view, 2> constraint_units() const { return {"m", "m"}; }
  std::array<double, 1> restitution() const { return {e}; }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(a - q[0]);
  }
};

/// The double pendulum in Cartesian coordinates (two rods as holonomic
/// rows) whose lower bob meets a wall at x = 0.9 m with e = 0.9:
/// DoublePendulumAgainstWall in other coordinates.
struct CartesianDoublePendulumAgainstWall : models::CartesianDoublePendulum {
  std::string name() const { return "cartesian_double_pendulum_against_wall"; }
  std::array<std::string_view, 1> unilateral_names() const { return {"wall"}; }
  std::array<std::string_view, 3> constraint_units() const { return {"m", "m", "m"}; }
  std::array<double, 1> restitution() const { return {0.9}; }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 4>& q, const S&) const {
    return Vec<S, 1>(0.9 - q[2]);
  }
};

/// A disc of mass m = 1 kg and radius 0.1 m in the vertical plane, its
/// centre at (x, y) (m), gravity g = 9.81 m/s² along −y, on a floor and
/// against a wall through x = 2 m leaning by `lean`:
///   T = ½ m (ẋ² + ẏ²),  V = m g y,
///   contacts "floor" φ_0 = y − 0.1 ≥ 0 and "wall" φ_1 = 1.9 − x + lean (y − 0.1) ≥ 0,
/// both with restitution e = 0.8. At rest on the floor the wall's impulse,
/// along ∇φ_1 = (−1, lean), lifts the disc off for lean > 0 and presses it
/// into the floor for lean < 0.
struct DiscAndLeaningWall : models::detail::PlanarParticle<> {
  static constexpr int coordinate_count = 2;
  explicit DiscAndLeaningWall(double leaning) : PlanarParticle{1.0, 9.81}, lean(leaning) {}
  double lean;
  std::string name() const { return "disc_and_leaning_wall"; }
  std::array<std::string_view, 2> unilateral_names() const { return {"floor", "wall"}; }
  std::array<double, 2> restitution() const { return {0.8, 0.8}; }
  template <class S>
  Vec<S, 2> unilateral(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 2>(q[1] - 0.1, 1.9 - q[0] + lean * (q[1] - 0.1));
  }
};

/// A point mass m (kg) in the plane, x and y (m), inside a regular polygon
/// of N walls at distance a (m) from the origin, N chosen at run time:
///   T = ½ m (ẋ² + ẏ²),  V = 0,
///   contacts φ_k = a − (x cos θ_k + y sin θ_k) ≥ 0,  θ_k = 2πk/N  ("wall<k>"),
/// each with restitution e = 1: a billiard.
struct PolygonBilliard {
  static constexpr int coordinate_count = 2;
  static constexpr bool constant_mass_matrix = true;
  int walls;
  double m = 0.2, a = 1.0;
  int unilateral_count() const { return walls; }
  double angle(int k) const { return 2 * std::numbers::pi * k / walls; }
  std::vector<std::string> unilateral_names() const {
    std::vector<std::string> out;
    for (int k = 0; k < walls; ++k) out.push_back("wall" + std::to_string(k));
    return out;
  }
  std::vector<double> restitution() const { return std::vector<double>(static_cast<std::size_t>(walls), 1.0); }
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>&, const S&) const {
    return S(0);
  }
  template <class S>
  Vec<S, Dynamic> unilateral(const Vec<S, 2>& q, const S&) const {
    Vec<S, Dynamic> g(walls);
    for (int k = 0; k < walls; ++k) g[k] = a - (q[0] * std::cos(angle(k)) + q[1] * std::sin(angle(k)));
    return g;
  }
};

}  // namespace lagrangian::testing
