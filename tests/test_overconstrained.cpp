// An over-constrained mechanism: more constraint rows than the rank they
// have, so counting rows would call it rigid. A particle on the unit circle
// in the plane z = 0, declared three ways (x² + y² = 1, z = 0 and
// x² + y² + z² = 1): 3 rows on 3 coordinates, rank 2 on the circle (the
// third row repeats the first there), 1 degree of freedom.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "lagrangian/lagrangian.hpp"

namespace {

using namespace lagrangian;

struct CircleThreeWays {
  static constexpr int coordinate_count = 3;
  double m = 0.5, g = 9.81;
  std::string name() const { return "circle_three_ways"; }
  std::array<std::string, 3> holonomic_names() const { return {"cylinder", "plane", "sphere"}; }
  template <class S>
  S kinetic(const Vec<S, 3>&, const Vec<S, 3>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1] + qd[2] * qd[2]);
  }
  template <class S>
  S potential(const Vec<S, 3>& q, const S&) const {
    return m * g * q[1];
  }
  template <class S>
  Vec<S, 3> holonomic(const Vec<S, 3>& q, const S&) const {
    return Vec<S, 3>(q[0] * q[0] + q[1] * q[1] - 1.0, q[2], q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - 1.0);
  }
};

TEST(OverConstrained, TheNearestConsistentStateIsFoundByRankNotByCount) {
  const CircleThreeWays model;
  State<3> guess;
  guess.q << 1.02, 0.03, 0.004;
  guess.qd << 0.1, 2.0, 0.3;
  const State<3> s = consistent_initial_state(model, guess);
  // The nearest point of the circle: (x, y)/|(x, y)| in z = 0.
  const double rho = std::hypot(1.02, 0.03);
  EXPECT_NEAR(s.q[0], 1.02 / rho, 1e-9);
  EXPECT_NEAR(s.q[1], 0.03 / rho, 1e-9);
  EXPECT_NEAR(s.q[2], 0.0, 1e-12);
  // Velocities tangent to the circle and in the plane.
  EXPECT_NEAR(s.q[0] * s.qd[0] + s.q[1] * s.qd[1], 0.0, 1e-12);
  EXPECT_NEAR(s.qd[2], 0.0, 1e-12);
  const DofReport dof = dof_report(model, s);
  EXPECT_EQ(dof.holonomic_rank, 2);
  EXPECT_EQ(dof.degrees_of_freedom, 1);
}

TEST(OverConstrained, AnInconsistentStartIsCalledInconsistentNotRigid) {
  const CircleThreeWays model;
  State<3> x0;
  x0.q << 1.0, 0.0, 1e-4;  // off the plane: there the three rows have rank 3
  SimulationOptions o;
  o.t_end = 1.0;
  try {
    simulate(model, x0, o);
    ADD_FAILURE() << "an inconsistent start ran";
  } catch (const ConstraintError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("initial state violates constraint plane"), std::string::npos) << what;
    EXPECT_EQ(what.find("no motion is left"), std::string::npos) << what;
  }
}

// From the consistent state it runs as the pendulum it is: one coordinate's
// worth of motion on the circle, the repeated row named, energy kept.
TEST(OverConstrained, ItRunsAsAPendulumAndNamesTheRepeatedRow) {
  const CircleThreeWays model;
  State<3> x0;
  x0.q << std::sin(1.0), -std::cos(1.0), 0.0;
  SimulationOptions o;
  o.t_end = 5.0;
  o.output_interval = 0.1;
  Recorder<3> rec;
  const RunReport r = simulate(model, x0, o, rec);
  bool named = false;
  for (const auto& w : r.constraints.warnings) named = named || w.find("constraint sphere is redundant") != std::string::npos;
  EXPECT_TRUE(named) << r.summary();
  EXPECT_LE(r.constraints.max_position_residual, 1e-10);
  EXPECT_LE(r.energy_drift_max, 1e-8);
  // Swinging between ±1 rad about the bottom: y never rises above −cos 1.
  for (const auto& s : rec.samples) EXPECT_LE(s.q[1], -std::cos(1.0) + 1e-8) << s.t;
}

// Three equal parallel cranks (length l) carrying one coupler: ground pivots
// at (0, 0), (a, 0), (2a, 0); q = (x, y, φ) is the coupler's first joint and
// its rotation, joint k at (x, y) + R(φ)(k a, 0). Crank k:
//   |(x + k a cos φ − k a, y + k a sin φ)| = l        (k = 0, 1, 2),
// written as a length (Root) or a squared length (Squared). With φ = 0 all
// three rows are x² + y² = l²: the coupler translates on a circle, 1 DOF, and
// the three rows have rank 2 — rank 1 at y = 0, where the cranks lie along
// the ground line (the singular configuration (±l, 0, 0)). Off the
// manifold the three rows are independent, so a Newton step from a guess
// aims at the point where the three linearised rows meet.
template <bool Squared>
struct ThreeCranks {
  static constexpr int coordinate_count = 3;
  double a = 1.0, l = 0.8, m = 2.0, inertia = 0.15, g = 9.81;
  std::string name() const { return "three_cranks"; }
  std::array<std::string, 3> holonomic_names() const { return {"crank0", "crank1", "crank2"}; }
  template <class S>
  S kinetic(const Vec<S, 3>&, const Vec<S, 3>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * inertia * qd[2] * qd[2];
  }
  template <class S>
  S potential(const Vec<S, 3>& q, const S&) const {
    return m * g * q[1];
  }
  template <class S>
  Vec<S, 3> holonomic(const Vec<S, 3>& q, const S&) const {
    using std::cos;
    using std::sin;
    using std::sqrt;
    Vec<S, 3> r;
    for (int k = 0; k < 3; ++k) {
      const S dx = q[0] + k * a * cos(q[2]) - k * a, dy = q[1] + k * a * sin(q[2]);
      if constexpr (Squared)
        r[k] = dx * dx + dy * dy - l * l;
      else
        r[k] = sqrt(dx * dx + dy * dy) - l;
    }
    return r;
  }
};

template <class Model>
void expect_nearest_three_crank_state(const Model& model) {
  State<3> guess;
  guess.q << 0.4, -0.75, 0.05;
  guess.qd << 0.3, 0.2, 0.1;
  // An independent consistent candidate, from geometry: with φ = 0 the rows
  // are x² + y² = l², and the point of that circle nearest to (0.4, −0.75)
  // is l (0.4, −0.75) / 0.85; its distance to the guess is
  // √((0.85 − l)² + 0.05²) = 0.0707.
  const double rho = std::hypot(0.4, -0.75);
  Vec<double, 3> candidate(model.l * 0.4 / rho, model.l * -0.75 / rho, 0.0);
  ASSERT_LE(model.holonomic(candidate, 0.0).template lpNorm<Eigen::Infinity>(), 1e-15);
  const double candidate_distance = (candidate - guess.q).norm();
  EXPECT_NEAR(candidate_distance, std::hypot(rho - model.l, 0.05), 1e-15);
  ConsistentStateReport report;
  const State<3> s = consistent_initial_state(model, guess, 0.0, 1e-12, &report);
  const double residual = model.holonomic(s.q, 0.0).template lpNorm<Eigen::Infinity>();
  const double distance = (s.q - guess.q).norm();
  EXPECT_LE(residual, 1e-12) << s.q.transpose();
  EXPECT_LE(distance, 0.072) << s.q.transpose() << "\n" << report.note;
  EXPECT_LE(distance, candidate_distance + 1e-12) << s.q.transpose();
  EXPECT_LE((s.q - candidate).norm(), 1e-9) << s.q.transpose();
  EXPECT_NEAR(report.distance, distance, 1e-15);
  EXPECT_NEAR(report.position_residual, residual, 1e-15);
  // A strict local minimum of the distance: along the circle's tangent the
  // curvature of ½‖q − q_g‖² on the manifold is |(x_g, y_g)| / l = 0.85 / 0.8.
  EXPECT_TRUE(report.local_minimum) << report.note;
  EXPECT_NEAR(report.tangent_curvature, rho / model.l, 1e-9);
  EXPECT_FALSE(report.nearest_proven);
  EXPECT_NE(report.note.find("not proven the globally nearest"), std::string::npos) << report.note;
  // Velocities: the M-weighted projection of q̇_g onto the tangent t =
  // (−ŷ, x̂, 0) of the circle at φ = 0 (the only motion there); t carries no
  // φ, so the projection is t (t · q̇_g).
  const Vec<double, 3> tangent(0.75 / rho, 0.4 / rho, 0.0);
  const Vec<double, 3> expected_qd = tangent * tangent.dot(guess.qd);
  EXPECT_LE((s.qd - expected_qd).norm(), 1e-12) << s.qd.transpose();
  EXPECT_LE(report.velocity_residual, 1e-12);
}

// From (0.4, −0.75, 0.05) the former Gauss–Newton/SLSQP path ended at the
// singular configuration (0.8, −1e-6, 1e-8), 0.85 away (length rows), or
// refused the mechanism as rigid (squared rows); the nearest consistent
// point is 0.0707 away.
TEST(OverConstrained, TheThreeCrankGuessGoesToTheNearestPointNotTheSingularOne) {
  expect_nearest_three_crank_state(ThreeCranks<false>{});
  expect_nearest_three_crank_state(ThreeCranks<true>{});
  ThreeCranks<false> wide;
  wide.a = 2.0;
  expect_nearest_three_crank_state(wide);
}

/// A particle on the circle x² + y² = l² (l = 1.3 m).
struct CircleOfRadius {
  static constexpr int coordinate_count = 2;
  double l = 1.3, m = 0.7;
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return 0 * q[0];
  }
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(q[0] * q[0] + q[1] * q[1] - l * l);
  }
};

// The nearest point of a circle to (a, b) ≠ 0 is l (a, b) / |(a, b)|, at
// distance ||(a, b)| − l|, with curvature |(a, b)| / l of ½‖q − q_g‖² along
// the circle there; guesses deep inside, on either side and far outside
// (|(a, b)| = 7.7 l, where a full tangent step overshoots).
TEST(OverConstrained, TheNearestPointOfACircleIsTheRadialOne) {
  const CircleOfRadius model;
  const double guesses[][2] = {{0.05, -0.02}, {6.0, 8.0}, {-2.5, 0.4}, {0.9, 1.1}, {-0.3, -1.0}, {-0.01, 4.0}};
  for (const auto& ab : guesses) {
    State<2> guess;
    guess.q << ab[0], ab[1];
    guess.qd << 0.4, -0.3;
    const double r = guess.q.norm();
    const Vec<double, 2> expected = model.l * guess.q / r;
    ConsistentStateReport report;
    const State<2> s = consistent_initial_state(model, guess, 0.0, 1e-12, &report);
    EXPECT_LE((s.q - expected).norm(), 1e-10) << ab[0] << ", " << ab[1] << ": " << s.q.transpose();
    EXPECT_NEAR(report.distance, std::abs(r - model.l), 1e-10);
    EXPECT_LE(std::abs(model.holonomic(s.q, 0.0)[0]), 1e-12);
    EXPECT_TRUE(report.local_minimum) << report.note;
    EXPECT_NEAR(report.tangent_curvature, r / model.l, 1e-8);
    EXPECT_TRUE(report.unique) << report.note;
    // q̇: the component of q̇_g along the tangent (equal masses).
    const Vec<double, 2> t(-expected[1] / model.l, expected[0] / model.l);
    EXPECT_LE((s.qd - t * t.dot(guess.qd)).norm(), 1e-12);
  }
  // From the centre every point of the circle is nearest: one is returned,
  // and the report says it is not the only one.
  State<2> centre;
  ConsistentStateReport report;
  const State<2> s = consistent_initial_state(model, centre, 0.0, 1e-12, &report);
  EXPECT_NEAR(s.q.norm(), model.l, 1e-12);
  EXPECT_NEAR(report.distance, model.l, 1e-12);
  EXPECT_FALSE(report.unique) << report.note;
  EXPECT_NE(report.note.find("not unique"), std::string::npos) << report.note;
  // A consistent guess is its own nearest point, and that is proven.
  State<2> on;
  on.q << 0.5, std::sqrt(1.3 * 1.3 - 0.25);
  const State<2> same = consistent_initial_state(model, on, 0.0, 1e-12, &report);
  EXPECT_LE((same.q - on.q).norm(), 1e-15);
  EXPECT_TRUE(report.nearest_proven) << report.note;
}

}  // namespace
