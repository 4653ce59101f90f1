// Constrained systems: two formulations agree, multipliers are the physical
// forces, stabilisation holds the manifold, DOF counts, consistent initial
// states, and bad constraint sets get clear errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;
constexpr double kPi = std::numbers::pi;

State<2> pendulum_cartesian_state(double l, double theta, double theta_dot) {
  State<2> s;
  s.q << l * std::sin(theta), -l * std::cos(theta);
  s.qd << l * std::cos(theta) * theta_dot, l * std::sin(theta) * theta_dot;
  return s;
}

TEST(Constraints, PendulumTwoFormulationsAgreeOverTenPeriods) {
  const double l = 1.3, g = 9.81, th0 = 1.2;
  const SimplePendulum angle(1.0, l, g);
  const CartesianPendulum cart(1.0, l, g);
  State<1> a0;
  a0.q[0] = th0;
  const double period = 2 * kPi * std::sqrt(l / g);  // small-angle; only sets the span
  SimulationOptions o;
  o.t_end = 10 * period;
  o.rtol = 1e-11;
  o.atol = 1e-13;
  o.output_interval = period / 20;
  Recorder<1> ra;
  Recorder<2> rc;
  simulate(angle, a0, o, ra);
  const RunReport r = simulate(cart, pendulum_cartesian_state(l, th0, 0.0), o, rc);
  ASSERT_EQ(ra.samples.size(), rc.samples.size());
  double worst = 0;
  for (std::size_t k = 0; k < ra.samples.size(); ++k) {
    const double theta_cart = std::atan2(rc.samples[k].q[0], -rc.samples[k].q[1]);
    worst = std::max(worst, std::abs(theta_cart - ra.samples[k].q[0]));
  }
  EXPECT_LE(worst, 1e-8);
  EXPECT_TRUE(r.constrained);
  EXPECT_LE(r.constraints.max_position_residual, 1e-11);
}

TEST(Constraints, MultiplierIsTheRodTension) {
  // λ is the force along +∇g = r̂; the rod pulls inwards with T = m(g cos θ + l θ̇²).
  const double m = 0.7, l = 0.9, g = 9.81;
  const CartesianPendulum cart(m, l, g);
  SimulationOptions o;
  o.t_end = 3.0;
  o.output_interval = 0.1;
  Recorder<2> rec;
  simulate(cart, pendulum_cartesian_state(l, 2.0, 0.5), o, rec);
  for (const auto& s : rec.samples) {
    const double cos_theta = -s.q[1] / l;
    const double theta_dot_sq = s.qd.squaredNorm() / (l * l);
    const double tension = m * (g * cos_theta + l * theta_dot_sq);
    ASSERT_EQ(s.multipliers.size(), 1);
    EXPECT_NEAR(s.multipliers[0], -tension, 1e-8 * (1 + std::abs(tension))) << "t = " << s.t;
    // Generalized constraint force Cᵀλ = λ r̂.
    EXPECT_NEAR(s.constraint_forces[0], s.multipliers[0] * s.q[0] / l, 1e-8);
    EXPECT_NEAR(s.constraint_forces[1], s.multipliers[0] * s.q[1] / l, 1e-8);
  }
}

TEST(Constraints, ParticleOnSphereMatchesSphericalPendulum) {
  const double R = 1.1, g = 9.81;
  const ParticleOnSphere cart(1.0, R, g);
  const SphericalPendulum sph(1.0, R, g);
  // θ from the downward vertical: (x, y, z) = R (sinθ cosφ, sinθ sinφ, −cosθ).
  const double th = 1.0, ph = 0.3, thd = 0.2, phd = 1.7;
  State<2> s0;
  s0.q << th, ph;
  s0.qd << thd, phd;
  State<3> c0;
  c0.q << R * std::sin(th) * std::cos(ph), R * std::sin(th) * std::sin(ph), -R * std::cos(th);
  c0.qd << R * (std::cos(th) * std::cos(ph) * thd - std::sin(th) * std::sin(ph) * phd),
      R * (std::cos(th) * std::sin(ph) * thd + std::sin(th) * std::cos(ph) * phd), R * std::sin(th) * thd;
  SimulationOptions o;
  o.t_end = 10 * 2 * kPi * std::sqrt(R / g);
  o.rtol = 1e-11;
  o.atol = 1e-13;
  o.output_interval = 0.25;
  Recorder<2> rs;
  Recorder<3> rc;
  simulate(sph, s0, o, rs);
  simulate(cart, c0, o, rc);
  ASSERT_EQ(rs.samples.size(), rc.samples.size());
  double worst = 0;
  for (std::size_t k = 0; k < rs.samples.size(); ++k) {
    const auto& q = rs.samples[k].q;
    const Vec<double, 3> p(R * std::sin(q[0]) * std::cos(q[1]), R * std::sin(q[0]) * std::sin(q[1]),
                           -R * std::cos(q[0]));
    worst = std::max(worst, (p - rc.samples[k].q).norm());
  }
  EXPECT_LE(worst, 1e-8);
}

TEST(Constraints, ProjectionHoldsTheManifoldForTenThousandPeriodsAndNoneDrifts) {
  const CartesianPendulum cart(1.0, 1.0, 9.81);
  const double period = 2 * kPi * std::sqrt(1.0 / 9.81);
  SimulationOptions o;
  o.t_end = 1e4 * period;
  o.rtol = 1e-9;
  o.atol = 1e-11;
  o.output_interval = -1;
  o.stabilization = Stabilization::projection;
  const RunReport proj = simulate(cart, pendulum_cartesian_state(1.0, 0.8, 0.0), o);
  EXPECT_LE(proj.constraints.max_position_residual, 1e-10);
  EXPECT_LE(proj.constraints.final_position_residual, 1e-10);
  EXPECT_LE(proj.constraints.final_velocity_residual, 1e-10);
  EXPECT_EQ(proj.constraints.projections, proj.steps);
  EXPECT_GT(proj.constraints.extra_rhs_evaluations, 0u);
  o.stabilization = Stabilization::none;
  const RunReport none = simulate(cart, pendulum_cartesian_state(1.0, 0.8, 0.0), o);
  EXPECT_GT(none.constraints.final_position_residual, 1e-4);  // visible drift of the rod length
  EXPECT_EQ(none.constraints.projections, 0u);
}

TEST(Constraints, BaumgarteBoundsTheDrift) {
  const CartesianPendulum cart(1.0, 1.0, 9.81);
  const double period = 2 * kPi * std::sqrt(1.0 / 9.81);
  SimulationOptions o;
  o.t_end = 500 * period;
  o.rtol = 1e-8;
  o.atol = 1e-10;
  o.output_interval = -1;
  o.stabilization = Stabilization::none;
  const RunReport none = simulate(cart, pendulum_cartesian_state(1.0, 0.8, 0.0), o);
  o.stabilization = Stabilization::baumgarte;
  const RunReport baum = simulate(cart, pendulum_cartesian_state(1.0, 0.8, 0.0), o);
  EXPECT_EQ(baum.constraints.stabilization, "baumgarte");
  EXPECT_EQ(baum.constraints.baumgarte_omega, 10.0);
  EXPECT_LE(baum.constraints.max_position_residual, 1e-8);
  EXPECT_LT(100 * baum.constraints.final_position_residual, none.constraints.final_position_residual);
}

TEST(Constraints, AtwoodMachineAccelerationAndTension) {
  const AtwoodMachine atwood(3.0, 1.0, 9.81, 0.0);
  State<2> s;
  s.q << 1.0, -1.0;
  SimulationOptions o;
  o.t_end = 1.0;
  o.output_interval = 0.5;
  Recorder<2> rec;
  simulate(atwood, s, o, rec);
  const double a = (atwood.m1 - atwood.m2) * atwood.g / (atwood.m1 + atwood.m2);
  const double tension = 2 * atwood.m1 * atwood.m2 * atwood.g / (atwood.m1 + atwood.m2);
  for (const auto& r : rec.samples) {
    EXPECT_NEAR(r.q[0], 1.0 - 0.5 * a * r.t * r.t, 1e-9);
    EXPECT_NEAR(r.multipliers[0], tension, 1e-9);  // the string pulls both masses up (+∇g)
  }
}

TEST(Constraints, BeadOnRotatingWireFollowsCosh) {
  const BeadOnRotatingWire bead(1.0, 2.0);
  State<2> s;
  s.q << 0.1, 0.0;   // on the wire at t = 0 (along x)
  s.qd << 0.05, 0.2;  // radial 0.05, tangential ω r = 0.2
  SimulationOptions o;
  o.t_end = 2.0;
  o.output_interval = 0.25;
  Recorder<2> rec;
  const RunReport r = simulate(bead, s, o, rec);
  EXPECT_FALSE(r.conservative);  // the constraint depends on t
  for (const auto& x : rec.samples) {
    const double rr = 0.1 * std::cosh(2.0 * x.t) + 0.05 / 2.0 * std::sinh(2.0 * x.t);
    EXPECT_NEAR(x.q.norm(), rr, 1e-8 * rr) << x.t;
  }
}

TEST(Constraints, KnifeEdgeRunsOnACircleAndKeepsItsSpin) {
  const KnifeEdge k(1.0, 0.1);
  const double v = 1.5, w = 0.8, phi0 = 0.3;
  State<3> s;
  s.q << 0.0, 0.0, phi0;
  s.qd << v * std::cos(phi0), v * std::sin(phi0), w;
  SimulationOptions o;
  o.t_end = 10.0;
  o.output_interval = 0.5;
  Recorder<3> rec;
  const RunReport r = simulate(k, s, o, rec);
  for (const auto& x : rec.samples) {
    const double phi = phi0 + w * x.t;
    EXPECT_NEAR(x.q[2], phi, 1e-9);
    EXPECT_NEAR(x.q[0], (v / w) * (std::sin(phi) - std::sin(phi0)), 1e-8);
    EXPECT_NEAR(x.q[1], -(v / w) * (std::cos(phi) - std::cos(phi0)), 1e-8);
  }
  // φ is cyclic and untouched by the constraint: p_φ = I φ̇ conserved. x and y
  // are cyclic too, but the constraint acts on them.
  ASSERT_EQ(r.conserved_momenta.size(), 1u);
  EXPECT_EQ(r.conserved_momenta[0].coordinate, "phi");
  EXPECT_LE(r.conserved_momenta[0].max_abs_drift, 1e-10);
}

TEST(Constraints, DegreesOfFreedom) {
  EXPECT_EQ(dof_report(BeadOnWire{}, State<2>{}).dof, 1);
  State<3> on_sphere;
  on_sphere.q << 0.0, 0.0, -1.0;
  const DofReport sphere = dof_report(ParticleOnSphere{}, on_sphere);
  EXPECT_EQ(sphere.dof, 2);
  EXPECT_TRUE(sphere.redundant.empty());
  // N = 3 free particles: 3N coordinates, no constraints.
  const auto free3 = make_model<9>(
      "three_particles", {"x1", "y1", "z1", "x2", "y2", "z2", "x3", "y3", "z3"},
      [](const auto&, const auto& qd, const auto&) { return 0.5 * qd.squaredNorm(); },
      [](const auto& q, const auto&) { return 0 * q[0]; });
  EXPECT_EQ(dof_report(free3, State<9>{}).dof, 9);
  State<4> dp;
  dp.q << 0.6, -0.8, 1.4, -1.4;
  const DofReport cdp = dof_report(CartesianDoublePendulum{}, dp);
  EXPECT_EQ(cdp.dof, 2);
  EXPECT_EQ(cdp.holonomic_rank, 2);
  State<3> ke;
  const DofReport knife = dof_report(KnifeEdge{}, ke);
  EXPECT_EQ(knife.dof, 3);
  EXPECT_EQ(knife.velocity_dof, 2);
}

// The rod constraint stated twice (the second a scaled copy) and a third,
// independent one fixing y.
struct RedundantPendulum : CartesianPendulum {
  std::array<std::string_view, 3> holonomic_names() const { return {"rod", "rod_again", "level"}; }
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
  const DofReport d = dof_report(RedundantPendulum{}, s);
  EXPECT_EQ(d.holonomic_rank, 2);
  EXPECT_EQ(d.dof, 0);
  ASSERT_EQ(d.redundant.size(), 1u);
  EXPECT_EQ(d.redundant[0], "rod_again");
}

// The rod written twice: redundant but consistent; the run must go on with
// finite multipliers (minimum-norm split of the tension) and a warning.
struct DoubledRod : CartesianPendulum {
  std::array<std::string_view, 2> holonomic_names() const { return {"rod", "rod_copy"}; }
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
  const RunReport r = simulate(DoubledRod{}, pendulum_cartesian_state(1.0, 0.7, 0.0), o, rec);
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

struct Contradictory {
  static constexpr int dof = 2;
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * qd.squaredNorm();
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return 0 * q[0];
  }
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
    EXPECT_STREQ(e.what(),
                 "the model has 2 holonomic constraints for 2 coordinates: no motion is left (need fewer constraints "
                 "than coordinates)");
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
  EXPECT_EQ(header, "t,x,y,x_dot,y_dot,energy,total_energy,lambda_rod,Qc_x,Qc_y");
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
    dof_report(QuadraticSkate{}, State<3>{});
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
    constraint_names(MisnamedRod{});
    FAIL() << "no error";
  } catch (const ConstraintError& e) {
    EXPECT_STREQ(e.what(), "holonomic_names() gives 1 names for 2 holonomic constraints");
  }
}

}  // namespace
