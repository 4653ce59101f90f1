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

}  // namespace
