// Constrained motion: two formulations agree, multipliers are the physical
// forces, stabilisation holds the manifold, closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <string_view>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "constrained_helpers.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;
constexpr double kPi = std::numbers::pi;

using test_helpers::pendulum_cartesian_state;

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

// 10⁴ periods; 10³ in the sanitizer stage (LAGRANGIAN_STABILITY_SHORT, the
// same code paths), where the unstabilised drift is still far above 1e-4.
TEST(Constraints, ProjectionHoldsTheManifoldForTenThousandPeriodsAndNoneDrifts) {
  const CartesianPendulum cart(1.0, 1.0, 9.81);
  const double period = 2 * kPi * std::sqrt(1.0 / 9.81);
  SimulationOptions o;
  o.t_end = (std::getenv("LAGRANGIAN_STABILITY_SHORT") ? 1e3 : 1e4) * period;
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
  EXPECT_GT(none.constraints.final_position_residual, 1e-4)  // visible drift of the rod length
      << none.constraints.final_position_residual;
  EXPECT_EQ(none.constraints.projections, 0u);
}

TEST(Constraints, TheResidualMonitorFlagsADriftNoToleranceExcuses) {
  // The rod of a Cartesian pendulum unstabilised under rk4 steps of a
  // tenth of its period: its length drifts by far more than 1 %; the
  // default projection holds it to rounding.
  const CartesianPendulum cart(1.0, 1.0, 9.81);
  const double period = 2 * kPi * std::sqrt(1.0 / 9.81);
  SimulationOptions o;
  o.method = Method::rk4;
  o.dt = period / 10;
  o.t_end = 20 * period;
  o.output_interval = period / 10;
  o.stabilization = Stabilization::none;
  const RunReport none = simulate(cart, pendulum_cartesian_state(1.0, 0.8, 0.0), o);
  const auto residual = std::find_if(none.monitors.begin(), none.monitors.end(),
                                     [](const MonitorVerdict& v) { return v.name == "constraint residual"; });
  ASSERT_NE(residual, none.monitors.end());
  EXPECT_DOUBLE_EQ(residual->figure, none.constraints.max_position_residual / (1 + none.coordinate_scale));
  EXPECT_TRUE(residual->exceeded) << residual->figure;
  EXPECT_TRUE(none.drift_exceeded);

  o.stabilization = Stabilization::projection;
  o.method = Method::dopri5;
  const RunReport projected = simulate(cart, pendulum_cartesian_state(1.0, 0.8, 0.0), o);
  const auto held = std::find_if(projected.monitors.begin(), projected.monitors.end(),
                                 [](const MonitorVerdict& v) { return v.name == "constraint residual"; });
  ASSERT_NE(held, projected.monitors.end());
  EXPECT_LT(held->figure, 1e-10);
  EXPECT_FALSE(projected.drift_exceeded);
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
  const AtwoodMachine atwood(3.0, 1.0, 9.81, 0.0, 5.0);  // the pulley 5 m up: out of reach in 1 s
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

TEST(Constraints, AtwoodMachineStopsWhereAMassReachesThePulley) {
  // 3 kg and 1 kg from rest at y = 0, the axle d = 1 m up: the light mass rises as ½ a t² with
  // a = g (m1 − m2)/(m1 + m2) and reaches the axle at t = √(2 d / a); the run stops there, naming the edge,
  // and no sample has a mass above the pulley.
  const AtwoodMachine atwood(3.0, 1.0, 9.81, 0.0, 1.0);
  State<2> s;
  SimulationOptions o;
  o.t_end = 2.0;
  o.output_interval = 0.01;
  Recorder<2> rec;
  const RunReport r = simulate(atwood, s, o, rec);
  const double a = 9.81 * (3.0 - 1.0) / 4.0;
  EXPECT_EQ(r.stopped_by, "mass2_at_pulley");
  EXPECT_NEAR(r.stopped_at, std::sqrt(2 * 1.0 / a), 1e-9);
  EXPECT_NEAR(r.t_final, std::sqrt(2 * 1.0 / a), 1e-9);
  for (const auto& x : rec.samples) {
    EXPECT_LE(x.q[0], 1.0 + 1e-9) << x.t;
    EXPECT_LE(x.q[1], 1.0 + 1e-9) << x.t;
  }
  // A start with a mass above the pulley is beyond the model's domain: refused, naming the edge.
  State<2> above;
  above.q << -1.5, 1.5;
  try {
    simulate(atwood, above, o);
    FAIL() << "a mass above the pulley was accepted";
  } catch (const DomainError& e) {
    EXPECT_NE(std::string(e.what()).find("mass2_at_pulley"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("-0.5"), std::string::npos) << e.what();  // c/2 + d − y2
  }
}

TEST(Constraints, BeadLeavesTheRotatingWireAtItsEnd) {
  // r = r0 cosh ωt from rest along the wire: the bead reaches the end r = L at t = acosh(L/r0)/ω.
  const BeadOnRotatingWire bead(1.0, 2.0, 3.0);
  State<2> s;
  s.q << 0.5, 0.0;
  s.qd << 0.0, 1.0;  // turning with the wire: ω r0
  SimulationOptions o;
  o.t_end = 5.0;
  o.rtol = 1e-11;
  o.atol = 1e-13;
  const RunReport r = simulate(bead, s, o);
  EXPECT_EQ(r.stopped_by, "bead_at_wire_end");
  EXPECT_NEAR(r.stopped_at, std::acosh(3.0 / 0.5) / 2.0, 1e-9);
}

TEST(Constraints, MultiplierColumnsCarryTheirUnits) {
  // λ ∂g/∂q is a generalized force: with g in m, λ is in N (the Atwood string's tension).
  const std::string dir = (std::filesystem::temp_directory_path() / "lagrangian_multiplier_units").string();
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/atwood.csv";
  {
    CsvSink csv(path);
    SimulationOptions o;
    o.t_end = 0.1;
    simulate(AtwoodMachine(3.0, 1.0), State<2>{}, o, csv);
    csv.finish();
  }
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_NE(header.find(",lambda_string [N],"), std::string::npos) << header;
  EXPECT_NE(header.find(",Qc_y1 [N]"), std::string::npos) << header;
  std::filesystem::remove_all(dir);
}

/// A vertical disk rolling without slipping on a plane (x, y contact point, φ heading, θ rolling angle):
///   ẋ = R θ̇ cos φ,  ẏ = R θ̇ sin φ   (Pfaffian),  T = ½ m (ẋ² + ẏ²) + ½ I_a θ̇² + ½ I_d φ̇².
struct RollingDisk {
  static constexpr int coordinate_count = 4;
  double m = 1.0, R = 0.3, Ia = 0.045, Id = 0.0225;
  std::array<std::string_view, 2> pfaffian_names() const { return {"roll_x", "roll_y"}; }
  template <class S>
  S kinetic(const Vec<S, 4>&, const Vec<S, 4>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * Ia * qd[3] * qd[3] + 0.5 * Id * qd[2] * qd[2];
  }
  template <class S>
  S potential(const Vec<S, 4>&, const S&) const {
    return S(0);
  }
  template <class S>
  Vec<S, 2> pfaffian(const Vec<S, 4>& q, const Vec<S, 4>& qd, const S&) const {
    using std::cos;
    using std::sin;
    return Vec<S, 2>(qd[0] - R * qd[3] * cos(q[2]), qd[1] - R * qd[3] * sin(q[2]));
  }
};

TEST(Constraints, SamplesBetweenStepsMeetTheStepsTolerance) {
  // The rolling disk's samples come from the dense output between steps; they are projected as the steps are, so the
  // velocity residual at every sample is at the steps' level, not the interpolant's (1e-10 before).
  const RollingDisk disk;
  State<4> s;
  s.qd << disk.R * 5.0, 0.0, 0.7, 5.0;  // rolling at θ̇ = 5 rad/s, turning at 0.7 rad/s
  SimulationOptions o;
  o.t_end = 10.0;
  o.rtol = 1e-10;
  o.atol = 1e-12;
  o.output_interval = 0.0137;  // samples between the steps
  Recorder<4> rec;
  const RunReport r = simulate(disk, s, o, rec);
  double worst = 0;
  for (const auto& x : rec.samples) {
    const double phi = x.q[2], w = x.qd[3];
    worst = std::max({worst, std::abs(x.qd[0] - disk.R * w * std::cos(phi)), std::abs(x.qd[1] - disk.R * w * std::sin(phi))});
  }
  EXPECT_GT(rec.samples.size(), 700u);
  EXPECT_LE(worst, 1e-14);
  EXPECT_LE(r.constraints.max_velocity_residual, 1e-14);
  // Free rolling: the contact point runs on a circle of radius v/φ̇ = 1.5/0.7 m about (0, v/φ̇).
  const double rad = disk.R * 5.0 / 0.7;
  for (const auto& x : rec.samples) EXPECT_NEAR(std::hypot(x.q[0], x.q[1] - rad), rad, 1e-8) << x.t;
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
  // The wire turns: at t = 0 it lies along x and leaves x alone, later it
  // does not, so p_x is not conserved and is not reported as such.
  EXPECT_TRUE(r.conserved_momenta.empty());
  EXPECT_FALSE(r.drift_exceeded);
  for (const auto& x : rec.samples) {
    const double rr = 0.1 * std::cosh(2.0 * x.t) + 0.05 / 2.0 * std::sinh(2.0 * x.t);
    EXPECT_NEAR(x.q.norm(), rr, 1e-8 * rr) << x.t;
  }
}

TEST(Constraints, Rosenbrock4FollowsATimeDependentConstraint) {
  // The wire spinning at ω = 2 rad/s (a rheonomic constraint, g depends on t): rosenbrock4 gives
  // r = r0 cosh ωt + (ṙ0/ω) sinh ωt as the explicit steppers do.
  const BeadOnRotatingWire bead(1.0, 2.0);
  State<2> s;
  s.q << 0.1, 0.0;
  s.qd << 0.05, 0.2;
  SimulationOptions o;
  o.method = Method::rosenbrock4;
  o.t_end = 2.0;
  o.rtol = 1e-9;
  o.atol = 1e-11;
  o.output_interval = 0.25;
  Recorder<2> rec;
  const RunReport r = simulate(bead, s, o, rec);
  EXPECT_EQ(r.method, "rosenbrock4");
  ASSERT_EQ(rec.samples.size(), 9u);
  for (const auto& x : rec.samples) {
    const double rr = 0.1 * std::cosh(2.0 * x.t) + 0.05 / 2.0 * std::sinh(2.0 * x.t);
    EXPECT_NEAR(x.q.norm(), rr, 1e-7 * rr) << x.t;
    // on the wire: (x, y) along (cos ωt, sin ωt)
    EXPECT_NEAR(x.q[0] * std::sin(2.0 * x.t) - x.q[1] * std::cos(2.0 * x.t), 0.0,
                1e-12 * (1 + x.q.lpNorm<Eigen::Infinity>()))  // the projection's tolerance
        << x.t;
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

// The residuals reported are those of the samples the user gets, not only
// of the projected steps: samples between steps come from dense output,
// where nothing holds the constraint. The knife edge's residual
// ẋ sin φ − ẏ cos φ and the particle on a sphere's |r| − R, recomputed from
// every sample, never exceed what the report says.
TEST(Constraints, ReportedResidualsCoverTheSamples) {
  const KnifeEdge k(1.0, 0.1);
  State<3> s;
  s.q << 0.0, 0.0, 0.3;
  s.qd << 1.5 * std::cos(0.3), 1.5 * std::sin(0.3), 0.8;
  // Without stabilization the dense output between steps leaves the constraint, and the report's residual
  // covers the samples; with projection (the default) the samples are projected as the steps are.
  for (const Stabilization stab : {Stabilization::none, Stabilization::projection}) {
    SCOPED_TRACE(to_string(stab));
    SimulationOptions o;
    o.t_end = 10.0;
    o.rtol = 1e-6;
    o.output_interval = 0.01;
    o.stabilization = stab;
    Recorder<3> rec;
    const RunReport r = simulate(k, s, o, rec);
    double worst = 0;
    for (const auto& x : rec.samples)
      worst = std::max(worst, std::abs(x.qd[0] * std::sin(x.q[2]) - x.qd[1] * std::cos(x.q[2])));
    if (stab == Stabilization::none) {
      EXPECT_GT(worst, 1e-12);
    } else {
      EXPECT_LE(worst, 1e-14);
    }
    EXPECT_GE(r.constraints.max_velocity_residual, worst);

    const models::ParticleOnSphere sphere(1.0, 1.0, 9.81);
    State<3> b;
    b.q << std::sin(1.0), 0.0, -std::cos(1.0);
    b.qd << 0.0, 1.5, 0.0;
    Recorder<3> brec;
    const RunReport rb = simulate(sphere, b, o, brec);
    double off = 0;
    for (const auto& x : brec.samples) off = std::max(off, std::abs(x.q.norm() - 1.0));
    if (stab == Stabilization::none) {
      EXPECT_GT(off, 1e-12);
    } else {
      EXPECT_LE(off, o.projection_tolerance * 2);  // the projection's tolerance (1 + |q|∞), as at steps
    }
    EXPECT_GE(rb.constraints.max_position_residual, off);
  }
}

// A free particle with two rheonomic constraints that its natural motion
// x = v t, y = 0 satisfies: g1 = y, g2 = y + (t − 1)(x − v t). Their gradients
// (0, 1) and (t − 1, 1) are parallel at t = 1: the Jacobian loses rank there.
struct DegeneratingPair : test_helpers::FreePlanarParticle {
  double v = 0.5;
  template <class S>
  Vec<S, 2> holonomic(const Vec<S, 2>& q, const S& t) const {
    return Vec<S, 2>(q[1], q[1] + (t - 1.0) * (q[0] - v * t));
  }
};

TEST(Constraints, RankDropAlongTheTrajectoryIsWarnedAndTheRunStaysFinite) {
  State<2> s;
  s.qd << 0.5, 0.0;
  SimulationOptions o;
  o.t_end = 2.0;
  o.output_interval = 0.25;  // a sample lands on t = 1
  Recorder<2> rec;
  const RunReport r = simulate(DegeneratingPair{}, s, o, rec);
  EXPECT_EQ(r.constraints.initial_rank, 2);
  EXPECT_EQ(r.constraints.min_rank, 1);
  // Two warnings: the approach (σ_2/σ_1 below 1e-3) and the rank drop itself.
  ASSERT_EQ(r.constraints.warnings.size(), 2u);
  int near = 0, dropped = 0;
  for (const auto& w : r.constraints.warnings) {
    near += w.rfind("near-singular configuration at t = ", 0) == 0;
    dropped += w == "rank of the constraint Jacobian dropped from 2 to 1 at t = 1 (singular configuration)";
  }
  EXPECT_EQ(near, 1) << r.summary();
  EXPECT_EQ(dropped, 1) << r.summary();
  EXPECT_LT(r.constraints.min_conditioning, 1e-3);
  EXPECT_NEAR(r.constraints.min_conditioning_time, 1.0, 0.1);
  for (const auto& x : rec.samples) {
    EXPECT_TRUE(x.multipliers.allFinite());
    EXPECT_NEAR(x.q[0], 0.5 * x.t, 1e-9);
  }
}

TEST(Constraints, CartesianDoublePendulumMatchesAngles) {
  const DoublePendulum angles(1.0, 1.0, 1.0, 1.0, 9.81);
  const CartesianDoublePendulum cart(1.0, 1.0, 1.0, 1.0, 9.81);
  const double a = 1.0, b = 0.4;
  State<2> s;
  s.q << a, b;
  State<4> c;
  c.q << std::sin(a), -std::cos(a), std::sin(a) + std::sin(b), -std::cos(a) - std::cos(b);
  SimulationOptions o;
  o.t_end = 5.0;
  o.rtol = 1e-11;
  o.atol = 1e-13;
  o.output_interval = 0.5;
  Recorder<2> ra;
  Recorder<4> rc;
  simulate(angles, s, o, ra);
  simulate(cart, c, o, rc);
  for (std::size_t k = 0; k < ra.samples.size(); ++k) {
    const auto& q = rc.samples[k].q;
    EXPECT_NEAR(std::atan2(q[0], -q[1]), ra.samples[k].q[0], 1e-8);
    EXPECT_NEAR(std::atan2(q[2] - q[0], -(q[3] - q[1])), ra.samples[k].q[1], 1e-8);
  }
}

}  // namespace
