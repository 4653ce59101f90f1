// Constraint sets: DOF counts, redundancy, consistent initial states, and
// bad constraint sets get clear errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "constrained_helpers.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

using test_helpers::pendulum_cartesian_state;

TEST(Constraints, DegreesOfFreedom) {
  EXPECT_EQ(dof_report(BeadOnWire{}, State<2>{}).degrees_of_freedom, 1);
  State<3> on_sphere;
  on_sphere.q << 0.0, 0.0, -1.0;
  const DofReport sphere = dof_report(ParticleOnSphere{}, on_sphere);
  EXPECT_EQ(sphere.degrees_of_freedom, 2);
  EXPECT_TRUE(sphere.redundant.empty());
  // N = 3 free particles: 3N coordinates, no constraints.
  const auto free3 = make_model<9>(
      "three_particles", {"x1", "y1", "z1", "x2", "y2", "z2", "x3", "y3", "z3"},
      [](const auto&, const auto& qd, const auto&) { return 0.5 * qd.squaredNorm(); },
      [](const auto& q, const auto&) { return 0 * q[0]; });
  EXPECT_EQ(dof_report(free3, State<9>{}).degrees_of_freedom, 9);
  State<4> dp;
  dp.q << 0.6, -0.8, 1.4, -1.4;
  const DofReport cdp = dof_report(CartesianDoublePendulum{}, dp);
  EXPECT_EQ(cdp.degrees_of_freedom, 2);
  EXPECT_EQ(cdp.holonomic_rank, 2);
  State<3> ke;
  const DofReport knife = dof_report(KnifeEdge{}, ke);
  EXPECT_EQ(knife.degrees_of_freedom, 3);
  EXPECT_EQ(knife.velocity_degrees_of_freedom, 2);
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
  EXPECT_EQ(knife.dof, 3);  // the old spellings still work
  EXPECT_EQ(knife.velocity_dof, 2);
#pragma GCC diagnostic pop
}

TEST(Constraints, ConvenienceFormNeedsNoHandSpelledWorkspace) {
  // A bob of mass m on a rod of length l passing the bottom (0, −l) at speed
  // v: q̈ = (0, v²/l), the centripetal acceleration, and the rod's tension
  // T = m (g + v²/l) along −r̂, i.e. λ = −T for g = |r| − l.
  const double m = 2.0, l = 1.5, g = 9.81, v = 3.0;
  const CartesianPendulum model(m, l, g);
  Vec<double, 2> q(0.0, -l), qd(v, 0.0);
  Vec<double, 1> lambda;
  const Vec<double, 2> qdd = constrained_accelerations(model, q, qd, 0.0, &lambda);
  EXPECT_NEAR(qdd[0], 0.0, 1e-12);
  EXPECT_NEAR(qdd[1], v * v / l, 1e-12);
  EXPECT_NEAR(lambda[0], -m * (g + v * v / l), 1e-11);
  // The same through the explicit workspaces.
  Workspace<2> ws;
  ConstraintWorkspaceFor<CartesianPendulum> cw;
  Vec<double, 2> out;
  constrained_accelerations(model, ws, cw, q, qd, 0.0, out);
  EXPECT_EQ(out, qdd);
}

// The rod constraint stated twice (the second a scaled copy) and a third,
// independent one fixing y.
struct RedundantPendulum : CartesianPendulum {
  std::array<std::string_view, 3> holonomic_names() const { return {"rod", "rod_again", "level"}; }
  std::array<std::string_view, 3> constraint_units() const { return {"m", "m", "m"}; }
  template <class S>
  Vec<S, 3> holonomic(const Vec<S, 2>& q, const S&) const {
    using std::sqrt;
    const S r = sqrt(q[0] * q[0] + q[1] * q[1]) - l;
    return Vec<S, 3>(r, 2.0 * r, q[1] + 0.5);
  }
};

TEST(Constraints, RedundantConstraintsAreNamed) {
  State<2> s;
  s.q << std::sqrt(0.75), -0.5;
  const DofReport d = dof_report(RedundantPendulum(), s);
  EXPECT_EQ(d.holonomic_rank, 2);
  EXPECT_EQ(d.degrees_of_freedom, 0);
  ASSERT_EQ(d.redundant.size(), 1u);
  EXPECT_EQ(d.redundant[0], "rod_again");
}

// The rod written twice: redundant but consistent; the run must go on with
// finite multipliers (minimum-norm split of the tension) and a warning.
struct DoubledRod : CartesianPendulum {
  std::array<std::string_view, 2> holonomic_names() const { return {"rod", "rod_copy"}; }
  std::array<std::string_view, 2> constraint_units() const { return {"m", "m"}; }
  template <class S>
  Vec<S, 2> holonomic(const Vec<S, 2>& q, const S&) const {
    using std::sqrt;
    const S r = sqrt(q[0] * q[0] + q[1] * q[1]) - l;
    return Vec<S, 2>(r, r);
  }
};

TEST(Constraints, RankDeficientJacobianWarnsAndStaysFinite) {
  SimulationOptions o;
  o.t_end = 2.0;
  o.output_interval = 0.5;
  Recorder<2> rec;
  const RunReport r = simulate(DoubledRod(), pendulum_cartesian_state(1.0, 0.7, 0.0), o, rec);
  ASSERT_FALSE(r.constraints.warnings.empty());
  EXPECT_NE(r.constraints.warnings[0].find("rod_copy is redundant at t0"), std::string::npos) << r.constraints.warnings[0];
  for (const auto& s : rec.samples) {
    EXPECT_TRUE(s.multipliers.allFinite());
    EXPECT_NEAR(s.multipliers[0], s.multipliers[1], 1e-9);  // equal shares of the tension
  }
  EXPECT_LE(r.constraints.max_position_residual, 1e-10);
}

TEST(Constraints, InconsistentInitialStateIsRepaired) {
  const BeadOnWire bead(1.0, 0.5, 9.81);
  State<2> guess;
  guess.q << 1.0, 1.0;  // off the wire
  guess.qd << 0.3, -0.2;
  const State<2> s = consistent_initial_state(bead, guess);
  const auto cs = constraint_state(bead, s.q, s.qd, 0.0);
  EXPECT_LE(std::abs(cs.position[0]), 1e-12);
  EXPECT_LE(std::abs(cs.velocity[0]), 1e-12);
  // The nearest point of the line through the origin along (cos α, sin α).
  const Vec<double, 2> u(std::cos(0.5), std::sin(0.5));
  EXPECT_LE((s.q - u.dot(guess.q) * u).norm(), 1e-10);
  // Equal masses: the M-weighted projection keeps the velocity's component along the wire.
  EXPECT_LE((s.qd - u.dot(guess.qd) * u).norm(), 1e-12);
  // simulate() rejects the raw guess and names the constraint.
  try {
    simulate(bead, guess, SimulationOptions{});
    FAIL() << "no error";
  } catch (const ConstraintError& e) {
    EXPECT_NE(std::string(e.what()).find("initial state violates constraint wire"), std::string::npos) << e.what();
  }
}

struct Contradictory : test_helpers::FreePlanarParticle {
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(q[0] * q[0] + q[1] * q[1] + 1.0);  // x² + y² = −1: no real solution
  }
};

struct OverConstrained : Contradictory {
  template <class S>
  Vec<S, 2> holonomic(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 2>(q[0] - 1.0, q[1] + 2.0);
  }
};

TEST(Constraints, UnsatisfiableAndOverConstrainedSetsAreClearErrors) {
  State<2> guess;
  guess.q << 0.3, 0.4;
  try {
    consistent_initial_state(Contradictory{}, guess);
    FAIL() << "no error";
  } catch (const ConstraintError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot satisfy the holonomic constraints"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("g0 = "), std::string::npos) << e.what();
  }
  try {
    consistent_initial_state(OverConstrained{}, guess);
    FAIL() << "no error";
  } catch (const ConstraintError& e) {
    // Judged by the rank at the consistent state, not by counting rows.
    EXPECT_STREQ(e.what(),
                 "the holonomic constraints fix all 2 coordinates (rank 2 at the consistent state): no motion is left");
  }
  State<2> fixed;
  fixed.q << 1.0, -2.0;
  EXPECT_THROW(simulate(OverConstrained{}, fixed, SimulationOptions{}), ConstraintError);
}

TEST(Constraints, CsvCarriesMultipliersAndConstraintForces) {
  const auto path = (std::filesystem::temp_directory_path() / "lagrangian_constraints.csv").string();
  SimulationOptions o;
  o.t_end = 0.5;
  o.output_interval = 0.25;
  simulate(CartesianPendulum{}, pendulum_cartesian_state(1.0, 0.4, 0.0), o, CsvSink(path));
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "t [s],x [m],y [m],x_dot [m/s],y_dot [m/s],energy [J],total_energy [J],lambda_rod [N],Qc_x [N],Qc_y [N]");
  std::filesystem::remove(path);
}

struct QuadraticSkate : KnifeEdge {
  template <class S>
  Vec<S, 1> pfaffian(const Vec<S, 3>&, const Vec<S, 3>& qd, const S&) const {
    return Vec<S, 1>(qd[0] * qd[0] - qd[1]);
  }
};

TEST(Constraints, NonAffinePfaffianIsRejected) {
  try {
    dof_report(QuadraticSkate(), State<3>{});
    FAIL() << "no error";
  } catch (const ConstraintError& e) {
    EXPECT_NE(std::string(e.what()).find("no_sideslip is not affine in the velocities"), std::string::npos) << e.what();
  }
}

struct MisnamedRod : DoubledRod {
  std::array<std::string_view, 1> holonomic_names() const { return {"rod"}; }
};

TEST(Constraints, NameCountMustMatchConstraintCount) {
  try {
    constraint_names(MisnamedRod());
    FAIL() << "no error";
  } catch (const ConstraintError& e) {
    EXPECT_STREQ(e.what(), "holonomic_names() gives 1 names for 2 holonomic constraints");
  }
}

}  // namespace
