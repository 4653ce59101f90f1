// Particle scenes on the ODE engine: each effect, constraint and contact kind
// against a closed form, a conservation law or a second formulation, and the
// proof that undeclared effects are never evaluated.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>
#include <numbers>

#include <boost/math/special_functions/ellint_1.hpp>
#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/run.hpp"
#include "lagrangian/integrate/simulate.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::scene;

RunControls quiet() {
  RunControls c;
  c.write_outputs = false;
  return c;
}

Scene base(double t_end, double rtol = 1e-11, double atol = 1e-13) {
  Scene s;
  s.name = "test";
  s.run.t_end = t_end;
  s.run.rtol = rtol;
  s.run.atol = atol;
  s.run.output_interval = 0.0;
  return s;
}

Eigen::Vector3d pos(const RunResult& r, int i) {
  return {r.q_final[3 * i], r.q_final[3 * i + 1], r.q_final[3 * i + 2]};
}
Eigen::Vector3d vel(const RunResult& r, int i) {
  return {r.qd_final[3 * i], r.qd_final[3 * i + 1], r.qd_final[3 * i + 2]};
}

TEST(Scenes, ProjectileMatchesClosedFormAndOnlyGravityIsEvaluated) {
  Scene s = base(2.0);
  s.bodies.push_back({.name = "ball", .mass = 0.2, .position = {0, 0, 1}, .velocity = {10, 0, 10}});
  s.gravity = UniformGravity{{0, 0, -9.81}};
  const RunResult r = run(s, quiet());
  const double t = 2.0;
  EXPECT_NEAR(pos(r, 0)[0], 10 * t, 1e-11);
  EXPECT_NEAR(pos(r, 0)[2], 1 + 10 * t - 0.5 * 9.81 * t * t, 1e-11);
  EXPECT_NEAR(vel(r, 0)[2], 10 - 9.81 * t, 1e-11);
  EXPECT_EQ(r.engine, "ode");
  ASSERT_EQ(r.effect_evaluations.size(), 1u);
  EXPECT_EQ(r.effect_evaluations.at("uniform_gravity"), r.report.rhs_evaluations);
  EXPECT_GT(r.report.rhs_evaluations, 0u);
}

TEST(Scenes, EveryDeclaredKindIsEvaluatedAndNoOther) {
  Scene s = base(0.5, 1e-9, 1e-11);
  s.bodies.push_back({.name = "a", .mass = 1.0, .radius = 0.1, .position = {0, 0, 1}, .velocity = {0.3, 0, 0}});
  s.bodies.push_back({.name = "b", .mass = 2.0, .radius = 0.1, .position = {1, 0, 1}, .velocity = {-0.3, 0, 0}});
  s.bodies.push_back({.name = "c", .mass = 1.0, .position = {0, 1, 0}, .velocity = {0, 0, 0}});
  s.gravity = UniformGravity{};
  s.newtonian_gravity = NewtonianGravity{1e-3};
  s.springs.push_back({.a = "a", .b = "b", .stiffness = 10, .rest_length = 1});
  s.linear_drag.push_back({.coefficient = 0.01});
  s.quadratic_drag.push_back({.coefficient = 0.01, .bodies = {"a"}});
  s.links.push_back({.a = "c", .anchor = {0, 1, 1}});
  s.sphere_contacts = SphereContacts{0.9, {"a", "b"}};
  s.planes.push_back({.name = "floor", .point = {0, 0, -5}, .normal = {0, 0, 1}, .restitution = 0.5});
  const RunResult r = run(s, quiet());
  for (const char* kind : {"uniform_gravity", "newtonian_gravity", "springs", "linear_drag", "quadratic_drag"})
    EXPECT_EQ(r.effect_evaluations.at(kind), r.report.rhs_evaluations) << kind;
  EXPECT_GT(r.effect_evaluations.at("links"), 0u);
  EXPECT_GT(r.effect_evaluations.at("sphere_contacts"), 0u);
  EXPECT_GT(r.effect_evaluations.at("plane_contacts"), 0u);
  EXPECT_EQ(r.effect_evaluations.count("surfaces"), 0u);
  EXPECT_EQ(r.effect_evaluations.count("box_contacts"), 0u);

  // Springs alone: gravity, drag, constraints and contacts are never visited.
  Scene t = base(1.0);
  t.bodies.push_back({.name = "m", .mass = 1.0, .position = {1, 0, 0}});
  t.springs.push_back({.a = "m", .anchor = {0, 0, 0}, .stiffness = 4.0});
  const RunResult q = run(t, quiet());
  ASSERT_EQ(q.effect_evaluations.size(), 1u);
  EXPECT_EQ(q.effect_evaluations.at("springs"), q.report.rhs_evaluations);
}

TEST(Scenes, AnchoredSpringIsAHarmonicOscillator) {
  // x(t) = A cos ωt, ω = √(k/m), for a zero-length spring to the origin.
  const double k = 4.0, m = 0.25, A = 0.3;
  const double w = std::sqrt(k / m);
  const double t_end = 5 * 2 * std::numbers::pi / w + 0.1;
  Scene s = base(t_end);
  s.bodies.push_back({.name = "m", .mass = m, .position = {A, 0, 0}, .velocity = {0, 0.1, 0}});
  s.springs.push_back({.a = "m", .anchor = {0, 0, 0}, .stiffness = k, .rest_length = 0});
  const RunResult r = run(s, quiet());
  EXPECT_NEAR(pos(r, 0)[0], A * std::cos(w * t_end), 1e-9);
  EXPECT_NEAR(pos(r, 0)[1], 0.1 / w * std::sin(w * t_end), 1e-9);
  EXPECT_LT(r.report.energy_drift_max, 1e-9);
  EXPECT_TRUE(r.report.conservative);
}

TEST(Scenes, Rk4ErrorFallsSixteenfoldWhenTheStepHalves) {
  const double k = 1.0, m = 1.0;
  auto error = [&](double dt) {
    Scene s = base(10.0);
    s.run.method = Method::rk4;
    s.run.dt = dt;
    s.bodies.push_back({.name = "m", .mass = m, .position = {1, 0, 0}});
    s.springs.push_back({.a = "m", .anchor = {0, 0, 0}, .stiffness = k});
    const RunResult r = run(s, quiet());
    return std::abs(pos(r, 0)[0] - std::cos(10.0));
  };
  const double e1 = error(0.02), e2 = error(0.01);
  EXPECT_NEAR(e1 / e2, 16.0, 0.5);
}

TEST(Scenes, CircularOrbitUnderNewtonianGravity) {
  // Two bodies on circular orbits about their centre of mass: period
  // 2π √(d³ / G(m1 + m2)); energy, P and L conserved.
  const double G = 1.0, m1 = 3.0, m2 = 1.0, d = 2.0;
  const double M = m1 + m2;
  const double w = std::sqrt(G * M / (d * d * d));
  const double r1 = d * m2 / M, r2 = d * m1 / M;
  const double period = 2 * std::numbers::pi / w;
  Scene s = base(3 * period);
  s.newtonian_gravity = NewtonianGravity{G};
  s.bodies.push_back({.name = "big", .mass = m1, .position = {-r1, 0, 0}, .velocity = {0, -w * r1, 0}});
  s.bodies.push_back({.name = "small", .mass = m2, .position = {r2, 0, 0}, .velocity = {0, w * r2, 0}});
  const RunResult r = run(s, quiet());
  EXPECT_NEAR(pos(r, 1)[0], r2, 1e-8);
  EXPECT_NEAR(pos(r, 1)[1], 0.0, 1e-8);
  EXPECT_NEAR(pos(r, 0)[0], -r1, 1e-8);
  EXPECT_LT(r.report.energy_drift_max, 1e-9);
  EXPECT_LT(r.report.linear_momentum_drift_max, 1e-10);
  EXPECT_LT(r.report.angular_momentum_drift_max, 1e-9);
}

TEST(Scenes, FallWithLinearDragMatchesClosedForm) {
  // m v̇ = m g − b v: v(t) = v_t + (v0 − v_t) e^{−t/τ}, τ = m/b, v_t = g τ.
  const double m = 0.5, b = 0.2, g = 9.81, v0 = 3.0, t = 4.0;
  const double tau = m / b, vt = -g * tau;
  Scene s = base(t);
  s.bodies.push_back({.name = "m", .mass = m, .velocity = {0, 0, v0}});
  s.gravity = UniformGravity{{0, 0, -g}};
  s.linear_drag.push_back({.coefficient = b});
  const RunResult r = run(s, quiet());
  const double z = vt * t + (v0 - vt) * tau * (1 - std::exp(-t / tau));
  EXPECT_NEAR(vel(r, 0)[2], vt + (v0 - vt) * std::exp(-t / tau), 1e-10);
  EXPECT_NEAR(pos(r, 0)[2], z, 1e-9);
  EXPECT_FALSE(r.report.conservative);
}

TEST(Scenes, FallWithQuadraticDragApproachesTerminalSpeed) {
  // From rest: v(t) = −v_t tanh(g t / v_t), z(t) = −(v_t²/g) ln cosh(g t / v_t), v_t = √(m g / c).
  const double m = 0.1, c = 0.02, g = 9.81, t = 3.0;
  const double vt = std::sqrt(m * g / c);
  Scene s = base(t);
  s.bodies.push_back({.name = "m", .mass = m});
  s.gravity = UniformGravity{{0, 0, -g}};
  s.quadratic_drag.push_back({.coefficient = c});
  const RunResult r = run(s, quiet());
  EXPECT_NEAR(vel(r, 0)[2], -vt * std::tanh(g * t / vt), 1e-9);
  EXPECT_NEAR(pos(r, 0)[2], -(vt * vt / g) * std::log(std::cosh(g * t / vt)), 1e-9);
}

TEST(Scenes, LinkPendulumAgreesWithTheGeneralizedCoordinateModel) {
  // The same pendulum twice: a body on a link (Cartesian, Lagrange
  // multiplier) and models::SimplePendulum (one angle, AD-derived).
  const double l = 1.5, m = 0.7, g = 9.81, theta0 = 1.2, t_end = 6.0;
  Scene s = base(t_end);
  s.bodies.push_back({.name = "bob", .mass = m, .position = {l * std::sin(theta0), 0, -l * std::cos(theta0)}});
  s.gravity = UniformGravity{{0, 0, -g}};
  s.links.push_back({.name = "rod", .a = "bob", .anchor = {0, 0, 0}, .length = l});
  const RunResult r = run(s, quiet());
  const double theta_scene = std::atan2(pos(r, 0)[0], -pos(r, 0)[2]);

  models::SimplePendulum p;
  p.m = m;
  p.l = l;
  p.g = g;
  State<1> x0;
  x0.q[0] = theta0;
  SimulationOptions o;
  o.t_end = t_end;
  o.rtol = 1e-11;
  o.atol = 1e-13;
  Recorder<1> rec;
  simulate(p, x0, o, rec);
  EXPECT_NEAR(theta_scene, rec.samples.back().q[0], 1e-8);
  EXPECT_LT(r.report.constraints.max_position_residual, 1e-10);
  EXPECT_LT(r.report.energy_drift_max, 1e-9);
  EXPECT_EQ(r.report.constraints.initial_rank, 1);
}

// trajectory.csv of a pendulum on a link carries the rod's multiplier and
// the constraint force on the bob, Qc = −T r̂, with the tension of the
// rod from Newton's law along it, T = m (g cos θ + v²/l), at every sample.
/// A light sphere pinned between a heavy one and a wall, as
/// test_impact_cycle.cpp runs it as a model: 1e-9 kg at rest against the
/// left wall, 1 kg arriving at 1 m/s along the line of centres, walls
/// elastic, the pair plastic. The limit of the cycling impacts stops both
/// at the wall; the impacts take all ½ M v² and the wall gives M v.
TEST(Scenes, APinnedLightSphereStopsTheHeavyOneAtTheWall) {
  const double m = 1e-9, M = 1.0, v = 1.0, R = 0.1, r = 0.07;
  Scene s = base(1.0);
  s.bodies.push_back({.name = "light", .mass = m, .radius = R, .position = {R, 0.5, 0.5}});
  s.bodies.push_back({.name = "heavy", .mass = M, .radius = r, .position = {0.6, 0.5, 0.5}, .velocity = {-v, 0, 0}});
  s.box = BoxContact{{0, 0, 0}, {1, 1, 1}, 1.0};
  s.sphere_contacts = SphereContacts{0.0, {}};
  s.run.engine = "ode";  // the event-driven engine is the default for such a scene
  const RunResult res = run(s, quiet());
  EXPECT_EQ(res.report.t_final, 1.0);
  EXPECT_NEAR(vel(res, 0).norm(), 0.0, 1e-9);
  EXPECT_NEAR(vel(res, 1).norm(), 0.0, 1e-9);
  EXPECT_NEAR(pos(res, 0)[0], R, 1e-9);
  EXPECT_NEAR(pos(res, 1)[0], 2 * R + r, 1e-9);
  EXPECT_NEAR(res.report.impact_energy_loss, 0.5 * M * v * v, 1e-9);
  double wall = 0;
  for (const EventRecord& e : res.report.events)
    if (e.kind == EventKind::impact && e.name == "light-wall:x_min") wall += e.impulse;
  EXPECT_NEAR(wall, M * v, 1e-6);
  EXPECT_LT(res.report.impacts, 20u);
}

/// The momenta a scene reports are those its symmetries conserve, each
/// left out with its reason: a conical pendulum on a link anchored at the
/// origin under gravity along −z conserves L_z = m (x ẏ − y ẋ) and nothing
/// else; a ball bouncing on a floor conserves P_x, P_y and L_z.
TEST(Scenes, OnlyConservedMomentaAreReported) {
  const double l = 1.5, m = 0.7, g = 9.81;
  Scene pendulum = base(3.0);
  pendulum.bodies.push_back({.name = "bob", .mass = m, .position = {l * std::sin(1.2), 0, -l * std::cos(1.2)},
                             .velocity = {0, 1.1, 0}});
  pendulum.gravity = UniformGravity{{0, 0, -g}};
  pendulum.links.push_back({.name = "rod", .a = "bob", .anchor = {0, 0, 0}, .length = l});
  const RunResult p = run(pendulum, quiet());
  using Flags = std::array<bool, 3>;
  EXPECT_EQ(p.report.linear_momentum_conserved, (Flags{false, false, false}));
  EXPECT_EQ(p.report.angular_momentum_conserved, (Flags{false, false, true}));
  EXPECT_NEAR(p.report.angular_momentum_initial[2], m * l * std::sin(1.2) * 1.1, 1e-14);
  EXPECT_LT(p.report.angular_momentum_drift_max, 1e-8);
  EXPECT_NE(p.report.angular_momentum_reason[0].find("the external forces have a moment about x"), std::string::npos);

  Scene ball = base(2.0);
  ball.bodies.push_back({.name = "ball", .mass = 0.2, .radius = 0.05, .position = {0, 0, 1}, .velocity = {0.4, -0.1, 0}});
  ball.gravity = UniformGravity{{0, 0, -g}};
  ball.planes.push_back({.name = "floor", .point = {0, 0, 0}, .normal = {0, 0, 1}, .restitution = 0.8});
  const RunResult b = run(ball, quiet());
  EXPECT_GT(b.report.impacts, 0u);
  EXPECT_EQ(b.report.linear_momentum_conserved, (Flags{true, true, false}));
  EXPECT_EQ(b.report.angular_momentum_conserved, (Flags{false, false, true}));
  EXPECT_EQ(b.report.linear_momentum_reason[2],
            "the external forces have a part along z; impacts with fixed surfaces push along z");
  EXPECT_LT(b.report.linear_momentum_drift_max, 1e-14);  // no force along x or y: P_x, P_y exact
  EXPECT_LT(b.report.angular_momentum_drift_max, 1e-12);
}

TEST(Scenes, LinkPendulumWritesTheRodTension) {
  const auto dir = std::filesystem::temp_directory_path() / "lagrangian_link_tension";
  std::filesystem::remove_all(dir);
  const double l = 1.5, m = 0.7, g = 9.81, theta0 = 1.2;
  Scene s = base(3.0);
  s.run.output_interval = 0.05;
  s.bodies.push_back({.name = "bob", .mass = m, .position = {l * std::sin(theta0), 0, -l * std::cos(theta0)}});
  s.gravity = UniformGravity{{0, 0, -g}};
  s.links.push_back({.name = "rod", .a = "bob", .anchor = {0, 0, 0}, .length = l});
  s.output.directory = dir.string();
  s.output.plots = false;
  run(s);
  std::ifstream in(dir / "trajectory.csv");
  std::string header;
  std::getline(in, header);
  ASSERT_EQ(header, "t [s],bob.x [m],bob.y [m],bob.z [m],bob.x_dot [m/s],bob.y_dot [m/s],bob.z_dot [m/s],energy [J],"
            "lambda_rod [N/m],Qc_bob.x [N],Qc_bob.y [N],Qc_bob.z [N]");
  int rows = 0;
  double worst = 0;
  for (std::string line; std::getline(in, line);) {
    std::vector<double> v;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 12u) << line;
    const Eigen::Vector3d r(v[1], v[2], v[3]), u(v[4], v[5], v[6]), Qc(v[9], v[10], v[11]);
    const double cos_theta = -r.z() / r.norm();
    const double T = m * (g * cos_theta + u.squaredNorm() / l);
    worst = std::max(worst, (Qc + T * r / r.norm()).norm() / (m * g));
    ++rows;
  }
  EXPECT_GT(rows, 50);
  EXPECT_LT(worst, 1e-8);
  std::filesystem::remove_all(dir);
}

// Reads trajectory.csv of `dir`: the header and each row's numbers.
std::pair<std::string, std::vector<std::vector<double>>> read_trajectory(const std::filesystem::path& dir) {
  std::ifstream in(dir / "trajectory.csv");
  std::string header;
  std::getline(in, header);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<double> v;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
    rows.push_back(std::move(v));
  }
  return {header, rows};
}

TEST(Scenes, SamplesBetweenStepsMeetTheConstraintsAsStepsDo) {
  // The link pendulum sampled off its steps (every 0.0137 s): each sample is projected onto |r| = l and
  // r·v = 0 as the steps are, so the residuals at the samples are round-off, not the interpolant's error.
  const auto dir = std::filesystem::temp_directory_path() / "lagrangian_sample_residuals";
  std::filesystem::remove_all(dir);
  const double l = 1.0;
  Scene s = base(10.0, 1e-8, 1e-10);
  s.run.output_interval = 0.0137;
  s.bodies.push_back({.name = "bob", .mass = 1.0, .position = {l * std::sin(1.2), 0, -l * std::cos(1.2)}});
  s.gravity = UniformGravity{};
  s.links.push_back({.name = "rod", .a = "bob", .anchor = {0, 0, 0}, .length = l});
  s.output.directory = dir.string();
  s.output.plots = false;
  s.output.animation = false;
  const RunResult r = run(s);
  const auto [header, rows] = read_trajectory(dir);
  ASSERT_GT(rows.size(), 700u);
  double position = 0, velocity = 0, speed = 0;
  for (const auto& v : rows) {
    const Eigen::Vector3d q(v[1], v[2], v[3]), u(v[4], v[5], v[6]);
    position = std::max(position, std::abs(q.norm() - l));
    velocity = std::max(velocity, std::abs(q.dot(u)));
    speed = std::max(speed, u.lpNorm<Eigen::Infinity>());
  }
  // The projection's tolerance, 1e-12 (1 + |r|∞) and 1e-12 (1 + |v|∞), at samples as at steps (the
  // interpolant alone leaves ~1e-9 at rtol 1e-8).
  EXPECT_LE(position, 2e-12);
  EXPECT_LE(velocity, 1e-12 * (1 + speed));
  EXPECT_LE(r.report.constraints.max_position_residual, 2e-12);
  std::filesystem::remove_all(dir);
}

TEST(Scenes, SurfaceMultiplierColumnsAreTheNormalForce) {
  // A bead bound to a sphere of radius ρ about the origin (row ½(|r|² − ρ²) in m², so λ is in N/m): the
  // constraint force Qc = λ ∇row = λ r is along the normal n = r/ρ, and Newton's law along n gives it,
  //   −m v²/ρ = Qc·n − m g n_z   (the centripetal acceleration, gravity (0, 0, −g)).
  const auto dir = std::filesystem::temp_directory_path() / "lagrangian_surface_multipliers";
  std::filesystem::remove_all(dir);
  const double rho = 0.8, m = 0.3, g = 9.81;
  Scene s = base(3.0);
  s.run.output_interval = 0.05;
  s.bodies.push_back({.name = "bead", .mass = m, .position = {rho * std::sin(0.8), 0, -rho * std::cos(0.8)},
                      .velocity = {0, 1.1, 0}});
  s.gravity = UniformGravity{{0, 0, -g}};
  s.surfaces.push_back({.name = "shell", .body = "bead", .kind = Surface::Kind::sphere, .point = {0, 0, 0},
                        .radius = rho});
  s.output.directory = dir.string();
  s.output.plots = false;
  s.output.animation = false;
  run(s);
  const auto [header, rows] = read_trajectory(dir);
  ASSERT_EQ(header, "t [s],bead.x [m],bead.y [m],bead.z [m],bead.x_dot [m/s],bead.y_dot [m/s],bead.z_dot [m/s],"
                    "energy [J],lambda_shell [N/m],Qc_bead.x [N],Qc_bead.y [N],Qc_bead.z [N]");
  double worst = 0;
  for (const auto& v : rows) {
    const Eigen::Vector3d r(v[1], v[2], v[3]), u(v[4], v[5], v[6]), Qc(v[9], v[10], v[11]);
    const Eigen::Vector3d n = r / r.norm();  // outward
    const double radial = -m * u.squaredNorm() / rho + m * g * n.z();
    worst = std::max({worst, std::abs(Qc.dot(n) - radial), (Qc - Qc.dot(n) * n).norm(),
                      std::abs(v[8] * r.norm() - Qc.dot(n))});
  }
  EXPECT_GT(rows.size(), 50u);
  EXPECT_LT(worst, 1e-8);
  std::filesystem::remove_all(dir);
}

// Notes 1.1 and 2.2–2.3 for a body in uniform gravity, from its start
// r₀, v₀: the impulse of the constant force F = m g over T is the change of
// momentum, J = F T; the torque about the origin is τ = r × m g, so
// L(T) = L₀ + m (r₀ × g) T + ½ m (v₀ × g) T² (the g × g term vanishes).
TEST(Scenes, ConstantForceImpulseAndTorqueChangeTheMomenta) {
  const double m = 0.8, T = 2.5;
  const Eigen::Vector3d g(0.3, -0.2, -9.81), r0(1.0, -2.0, 0.5), v0(3.0, 1.0, 4.0);
  Scene s = base(T);
  s.bodies.push_back({.name = "b", .mass = m, .position = {r0.x(), r0.y(), r0.z()}, .velocity = {v0.x(), v0.y(), v0.z()}});
  s.gravity = UniformGravity{{g.x(), g.y(), g.z()}};
  const RunResult r = run(s, quiet());
  const Eigen::Vector3d p = m * vel(r, 0), L = m * pos(r, 0).cross(vel(r, 0));
  EXPECT_LE((p - m * v0 - m * g * T).norm(), 1e-11 * m * g.norm() * T);
  const Eigen::Vector3d L_expected = m * r0.cross(v0) + m * r0.cross(g) * T + 0.5 * m * v0.cross(g) * T * T;
  EXPECT_LE((L - L_expected).norm(), 1e-10 * L_expected.norm());
}

// Notes 2.2: M R̈ = F_ext. Two bodies joined by a spring (an internal force)
// in uniform gravity: the centre of mass falls as one particle,
// R(T) = R₀ + V₀ T + ½ g T², however the spring swings them about it.
TEST(Scenes, TheCentreOfMassMovesUnderTheExternalForceAlone) {
  const double ma = 1.0, mb = 3.0, M = ma + mb, T = 3.0;
  const Eigen::Vector3d g(0, 0, -9.81);
  const Eigen::Vector3d ra(0, 0, 0), rb(1.2, 0.3, 0), va(0, 2.0, 1.0), vb(0.5, -1.0, 0);
  Scene s = base(T);
  s.bodies.push_back({.name = "a", .mass = ma, .position = {ra.x(), ra.y(), ra.z()}, .velocity = {va.x(), va.y(), va.z()}});
  s.bodies.push_back({.name = "b", .mass = mb, .position = {rb.x(), rb.y(), rb.z()}, .velocity = {vb.x(), vb.y(), vb.z()}});
  s.springs.push_back({.a = "a", .b = "b", .stiffness = 40.0, .rest_length = 1.0});
  s.gravity = UniformGravity{{g.x(), g.y(), g.z()}};
  const RunResult r = run(s, quiet());
  const Eigen::Vector3d R = (ma * pos(r, 0) + mb * pos(r, 1)) / M;
  const Eigen::Vector3d R_expected = (ma * ra + mb * rb) / M + (ma * va + mb * vb) / M * T + 0.5 * g * T * T;
  EXPECT_LE((R - R_expected).norm(), 1e-9 * R_expected.norm());
  // The bodies themselves did not fall as particles: the spring acted.
  EXPECT_GT((pos(r, 0) - (ra + va * T + 0.5 * g * T * T)).norm(), 1e-2);
}

TEST(Scenes, DumbbellKeepsItsLengthAndConservesMomenta) {
  Scene s = base(5.0);
  s.bodies.push_back({.name = "a", .mass = 1.0, .position = {0, 0, 0}, .velocity = {0, 1, 0.2}});
  s.bodies.push_back({.name = "b", .mass = 3.0, .position = {1, 0, 0}, .velocity = {0, -0.5, 0}});
  s.links.push_back({.a = "a", .b = "b"});
  const RunResult r = run(s, quiet());
  EXPECT_NEAR((pos(r, 0) - pos(r, 1)).norm(), 1.0, 1e-11);
  EXPECT_LT(r.report.linear_momentum_drift_max, 1e-11);
  EXPECT_LT(r.report.angular_momentum_drift_max, 1e-9);
  EXPECT_LT(r.report.energy_drift_max, 1e-9);
}

TEST(Scenes, BeadOnASphereKeepsItsVerticalAngularMomentum) {
  // A spherical pendulum as a surface constraint: E and L_z about the
  // centre are conserved, the body stays on the sphere.
  const double R = 1.0;
  Scene s = base(10.0);
  s.bodies.push_back({.name = "bead", .mass = 0.3, .position = {R * std::sin(0.8), 0, -R * std::cos(0.8)},
                      .velocity = {0, 1.1, 0}});
  s.gravity = UniformGravity{};
  s.surfaces.push_back({.name = "shell", .body = "bead", .kind = Surface::Kind::sphere, .point = {0, 0, 0},
                        .radius = R});
  const RunResult r = run(s, quiet());
  const Eigen::Vector3d p = pos(r, 0), v = vel(r, 0);
  EXPECT_NEAR(p.norm(), R, 1e-11);
  EXPECT_NEAR(p.dot(v), 0.0, 1e-10);
  const double Lz0 = 0.3 * R * std::sin(0.8) * 1.1;
  EXPECT_NEAR(0.3 * (p.x() * v.y() - p.y() * v.x()), Lz0, 1e-9);
  EXPECT_LT(r.report.energy_drift_max, 1e-9);
}

TEST(Scenes, RedundantConstraintsStillRun) {
  // The same plane twice: rank 1, one redundant row; the motion in the plane is free flight.
  Scene s = base(1.0);
  s.bodies.push_back({.name = "puck", .mass = 1.0, .velocity = {1, 2, 0}});
  s.gravity = UniformGravity{};
  s.surfaces.push_back({.name = "table", .body = "puck", .kind = Surface::Kind::plane, .normal = {0, 0, 1}});
  s.surfaces.push_back({.name = "table_again", .body = "puck", .kind = Surface::Kind::plane, .normal = {0, 0, 2}});
  const RunResult r = run(s, quiet());
  EXPECT_EQ(r.report.constraints.initial_rank, 1);
  // The run names the row that adds no rank, as runs of models do.
  ASSERT_EQ(r.report.constraints.warnings.size(), 1u) << r.report.summary();
  EXPECT_EQ(r.report.constraints.warnings[0],
            "constraint table_again is redundant at t0 (its Jacobian row depends on earlier rows)");
  EXPECT_NEAR(pos(r, 0)[0], 1.0, 1e-12);
  EXPECT_NEAR(pos(r, 0)[1], 2.0, 1e-12);
  EXPECT_NEAR(pos(r, 0)[2], 0.0, 1e-12);
  EXPECT_NE(inspect(s).find("redundant constraints: 1"), std::string::npos) << inspect(s);
}

TEST(Scenes, BouncingBallReboundsWithE2AndComesToRestAtTheZenoTime) {
  // Dropped from h with e: the n-th rebound rises to e^{2n} h and the
  // bounces end at t∞ = t_f (1 + e)/(1 − e), t_f = √(2h/g).
  const double h = 1.0, g = 9.81, e = 0.6, R = 0.05;
  const double tf = std::sqrt(2 * h / g);
  const double t_inf = tf * (1 + e) / (1 - e);
  Scene s = base(t_inf + 0.5);
  s.bodies.push_back({.name = "ball", .mass = 0.1, .radius = R, .position = {0, 0, h + R}});
  s.gravity = UniformGravity{{0, 0, -g}};
  s.planes.push_back({.name = "floor", .point = {0, 0, 0}, .normal = {0, 0, 1}, .restitution = e});
  const RunResult r = run(s, quiet());
  ASSERT_GE(r.report.events.size(), 3u);
  EXPECT_NEAR(r.report.events[0].t, tf, 1e-9);
  EXPECT_NEAR(r.report.events[0].approach_speed, g * tf, 1e-8);
  EXPECT_NEAR(r.report.events[0].separation_speed, e * g * tf, 1e-8);
  EXPECT_NEAR(r.report.events[1].t, tf + 2 * e * tf, 1e-9);
  // It rests on the floor at the end, at the accumulation time.
  const auto& last = r.report.events.back();
  EXPECT_EQ(last.kind, EventKind::rest);
  // The Zeno rule ends the series at an approach speed u ≤ 1e-6 of the
  // first; the bounces it skips would have lasted 2 e u / (g (1 − e)).
  EXPECT_LE(last.approach_speed, 1e-6 * r.report.events[0].approach_speed);
  EXPECT_NEAR(t_inf - last.t, 2 * e * last.approach_speed / (g * (1 - e)), 1e-9);
  EXPECT_NEAR(pos(r, 0)[2], R, 1e-10);
  EXPECT_NEAR(vel(r, 0)[2], 0.0, 1e-10);
  // Energy lost at the impacts is the whole initial potential energy above rest.
  EXPECT_NEAR(r.report.impact_energy_loss, 0.1 * g * h, 1e-7);
}

TEST(Scenes, HeadOnSpheresFollowNewtonsLaw) {
  const double m1 = 1.0, m2 = 3.0, u1 = 2.0, u2 = -1.0, e = 0.7;
  Scene s = base(2.0);
  s.bodies.push_back({.name = "a", .mass = m1, .radius = 0.1, .position = {0, 0, 0}, .velocity = {u1, 0, 0}});
  s.bodies.push_back({.name = "b", .mass = m2, .radius = 0.2, .position = {1, 0, 0}, .velocity = {u2, 0, 0}});
  s.sphere_contacts = SphereContacts{e, {}};
  s.run.engine = "ode";
  const RunResult r = run(s, quiet());
  ASSERT_EQ(r.report.impacts, 1u);
  EXPECT_NEAR(r.report.events[0].t, (1.0 - 0.3) / (u1 - u2), 1e-12);
  const double v1 = ((m1 - e * m2) * u1 + (1 + e) * m2 * u2) / (m1 + m2);
  const double v2 = ((m2 - e * m1) * u2 + (1 + e) * m1 * u1) / (m1 + m2);
  EXPECT_NEAR(vel(r, 0)[0], v1, 1e-12);
  EXPECT_NEAR(vel(r, 1)[0], v2, 1e-12);
  EXPECT_LT(r.report.linear_momentum_drift_max, 1e-12);
}

TEST(Scenes, NewtonsCradlePassesTheMomentumAlong) {
  // Three touching equal spheres hit by a fourth: sequential pairwise
  // impacts leave only the last one moving, with the striker's speed.
  Scene s = base(1.0);
  const double R = 0.1;
  s.bodies.push_back({.name = "s0", .mass = 1, .radius = R, .position = {-0.5, 0, 0}, .velocity = {1, 0, 0}});
  for (int i = 1; i <= 3; ++i)
    s.bodies.push_back({.name = "s" + std::to_string(i), .mass = 1, .radius = R, .position = {2 * R * (i - 1), 0, 0}});
  s.sphere_contacts = SphereContacts{1.0, {}};
  s.run.engine = "ode";
  const RunResult r = run(s, quiet());
  EXPECT_NEAR(vel(r, 0)[0], 0.0, 1e-12);
  EXPECT_NEAR(vel(r, 1)[0], 0.0, 1e-12);
  EXPECT_NEAR(vel(r, 2)[0], 0.0, 1e-12);
  EXPECT_NEAR(vel(r, 3)[0], 1.0, 1e-12);
  EXPECT_EQ(r.report.impacts, 3u);
}

TEST(Scenes, OdeAndEventDrivenEnginesAgreeOnAGasInABox) {
  // Two formulations of one system: the ODE engine locating each contact on
  // the step interpolant, and the exact event-driven engine.
  Scene s = base(3.0);
  s.box = BoxContact{{0, 0, 0}, {1, 1, 1}, 1.0};
  s.sphere_contacts = SphereContacts{1.0, {}};
  s.gas = GasFill{.count = 8, .mass = 1.0, .radius = 0.08, .speed = 1.0, .seed = 7};
  s.run.engine = "ode";
  const RunResult a = run(s, quiet());
  s.run.engine = "event_driven";
  const RunResult b = run(s, quiet());
  EXPECT_EQ(b.engine, "event_driven");
  ASSERT_GT(a.report.impacts, 20u);
  // The same impacts (bodies and walls) at the same times. A gas is chaotic:
  // each sphere–sphere impact multiplies a difference by about the mean free
  // path over the radius, so the two runs drift apart later (1e-16 s for the
  // first wall impacts, 1e-9 s by the 16th event, 1e-4 s by the 65th).
  const std::size_t n = std::min<std::size_t>(16, std::min(a.report.events.size(), b.report.events.size()));
  ASSERT_EQ(n, 16u);
  for (std::size_t k = 0; k < n; ++k) {
    EXPECT_NEAR(a.report.events[k].t, b.report.events[k].t, 1e-8) << k;
    EXPECT_EQ(a.report.events[k].name, b.report.events[k].name) << k;
    EXPECT_NEAR(a.report.events[k].impulse, b.report.events[k].impulse, 1e-8) << k;
  }
  EXPECT_LT(a.report.energy_drift_max, 1e-9);
}

/// The event-driven engine logs the first output.max_events impacts; when a
/// run has more, the summary, report.json and events.csv all say so, while
/// the impact count and the dissipated energy still cover every impact.
TEST(Scenes, ATruncatedEventLogSaysSoEverywhere) {
  Scene s = base(2.0);
  s.box = BoxContact{{0, 0, 0}, {1, 1, 1}, 0.9};
  s.sphere_contacts = SphereContacts{0.9, {}};
  s.gas = GasFill{.count = 20, .mass = 1.0, .radius = 0.05, .speed = 1.0, .seed = 3};
  s.run.engine = "event_driven";
  const auto dir = std::filesystem::temp_directory_path() / "lagrangian_truncated_log";
  std::filesystem::remove_all(dir);
  s.output.directory = dir.string();
  s.output.plots = false;
  s.output.max_events = 50;
  RunControls c;
  c.progress = false;
  const RunResult r = run(s, c);
  ASSERT_GT(r.report.impacts, 50u);
  EXPECT_EQ(r.report.events.size(), 50u);
  EXPECT_EQ(r.report.unlogged_events, r.report.impacts - 50u);
  const std::string total = std::to_string(r.report.impacts);
  EXPECT_NE(r.report.summary().find("warning: event log truncated: it holds the first 50 of " + total + " impacts"),
            std::string::npos)
      << r.report.summary();
  std::ifstream json(dir / "report.json");
  const std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"count\": 50, \"not_logged\": " + std::to_string(r.report.unlogged_events) +
                      ", \"truncated\": true"),
            std::string::npos)
      << text.substr(0, 400);
  std::ifstream csv(dir / "events.csv");
  std::string line, last;
  int rows = -1;  // the header
  while (std::getline(csv, line)) {
    if (line.rfind("#", 0) != 0) ++rows;
    last = line;
  }
  EXPECT_EQ(rows, 50);
  EXPECT_EQ(last, "# truncated: these are the first 50 of " + total +
                      " events; raise output.max_events to log them all");

  // The energy lost in impacts is the same whatever the log keeps.
  s.output.max_events = 100'000;
  const RunResult all = run(s, c);
  EXPECT_EQ(all.report.unlogged_events, 0u);
  EXPECT_EQ(all.report.events.size(), all.report.impacts);
  EXPECT_EQ(all.report.impacts, r.report.impacts);
  EXPECT_EQ(all.report.impact_energy_loss, r.report.impact_energy_loss);
  EXPECT_EQ(all.report.summary().find("truncated"), std::string::npos);
  std::filesystem::remove_all(dir);
}

/// Values whose energies overflow a double are refused before the run,
/// naming the key and the value; an energy that overflows during a run
/// (here under a gravity of 1e300 m/s², from rest, with rk4) stops it with the time
/// and the state instead of writing "energy inf".
TEST(Scenes, OverflowingValuesAreRefusedAndOverflowMidRunStops) {
  auto error_key = [](const Scene& s) {
    try {
      run(s, quiet());
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("overflows a double"), std::string::npos) << e.what();
      return e.key();
    }
    return std::string("no error");
  };
  Scene ball = base(1.0);
  ball.bodies.push_back({.name = "ball", .mass = 1, .velocity = {1e200, 0, 0}});
  EXPECT_EQ(error_key(ball), "bodies[0].velocity");
  ball.bodies[0].velocity = {0, 0, 1e150};  // ½ m v² = 5e299 J: a run can hold it
  ball.bodies[0].position = {1e160, 0, 0};  // but |r|² cannot
  EXPECT_EQ(error_key(ball), "bodies[0].position");

  Scene gas = base(0.2);
  gas.box = BoxContact{{0, 0, 0}, {1, 1, 1}, 1.0};
  gas.sphere_contacts = SphereContacts{1.0, {}};
  gas.gas = GasFill{.count = 3000, .mass = 1.0, .radius = 0.001, .speed = 1e306, .seed = 1};
  EXPECT_EQ(error_key(gas), "gas.speed");
  // A gas fills its box: a box reaching 1e308 m would place molecules where |r|² overflows.
  gas.gas->speed = 1.0;
  gas.gas->count = 20;
  gas.box->max = {1, 1, 1.01e308};
  EXPECT_EQ(error_key(gas), "contacts.box.max");
  gas.box->max = {1, 1, 1};
  gas.box->min = {-1e200, 0, 0};
  EXPECT_EQ(error_key(gas), "contacts.box.min");

  Scene fall = base(1.0);
  fall.bodies.push_back({.name = "ball", .mass = 1});
  fall.gravity = UniformGravity{{0, 0, -1e300}};
  fall.run.method = Method::rk4;  // fixed steps: the first one ends at v = -1e297 m/s, ½ m v² = inf
  fall.run.dt = 1e-3;
  try {
    run(fall, quiet());
    FAIL() << "the run finished";
  } catch (const SimulationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("the energy is not finite at t = "), std::string::npos) << what;
    EXPECT_NE(what.find("x = ["), std::string::npos) << what;
    EXPECT_GT(e.time(), 0.0);
    EXPECT_LT(e.time(), 1.0);
  }
}

TEST(Scenes, OutputDirectoryThatCannotBeWrittenIsABadInput) {
  Scene s = base(0.1);
  s.bodies.push_back({.name = "m", .mass = 1});
  const auto blocker = std::filesystem::temp_directory_path() / "lagrangian_not_a_dir";
  { std::ofstream(blocker) << "x"; }
  s.output.directory = (blocker / "out").string();
  try {
    run(s);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "output.directory");
    EXPECT_NE(std::string(e.what()).find(s.output.directory), std::string::npos) << e.what();
  }
  std::filesystem::remove(blocker);
}

TEST(Scenes, AFailedRunLeavesNoOutputThatLooksComplete) {
  const auto dir = std::filesystem::temp_directory_path() / "lagrangian_failed_run";
  std::filesystem::remove_all(dir);
  Scene s = base(10.0);
  s.bodies.push_back({.name = "m", .mass = 1, .position = {1, 0, 0}});
  s.springs.push_back({.a = "m", .anchor = {0, 0, 0}, .stiffness = 1});
  s.run.max_steps = 5;
  s.output.directory = dir.string();
  s.output.plots = false;
  EXPECT_THROW(run(s), SimulationError);
  for (const char* f : {"trajectory.csv", "events.csv", "report.json", "trajectory.csv.partial"})
    EXPECT_FALSE(std::filesystem::exists(dir / f)) << f;
  // The same scene with enough steps writes all three.
  s.run.max_steps = 1'000'000;
  const RunResult r = run(s);
  for (const char* f : {"trajectory.csv", "events.csv", "report.json"}) EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  std::ifstream json(dir / "report.json");
  const std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"effect_evaluations\": {\"springs\": " + std::to_string(r.report.rhs_evaluations)),
            std::string::npos)
      << text.substr(0, 400);

  // Nothing of an earlier run survives a later one into the same directory:
  // a run with plots, then a failing run, leaves none of the plots; nor does
  // a run without plots after one with them. A file of the user's stays.
  { std::ofstream(dir / "notes.png") << "mine"; }
  s.output.plots = true;
  const RunResult plotted = run(s);
  ASSERT_TRUE(plotted.plot_note.empty()) << plotted.plot_note;  // gnuplot is installed by scripts/setup
  std::vector<std::filesystem::path> plots;
  for (const std::string& f : plotted.files)
    if (f.ends_with(".png") || f.ends_with(".svg") || f.ends_with(".gp")) plots.emplace_back(f);
  ASSERT_GE(plots.size(), 3u);
  for (const auto& p : plots) ASSERT_TRUE(std::filesystem::exists(p)) << p;
  s.run.max_steps = 5;
  EXPECT_THROW(run(s), SimulationError);
  for (const auto& p : plots) EXPECT_FALSE(std::filesystem::exists(p)) << p << " survived a failed run";
  s.run.max_steps = 1'000'000;
  run(s);  // plots again
  for (const auto& p : plots) ASSERT_TRUE(std::filesystem::exists(p)) << p;
  s.output.plots = false;
  run(s);
  for (const auto& p : plots) EXPECT_FALSE(std::filesystem::exists(p)) << p << " survived a run without plots";
  for (const char* f : {"trajectory.csv", "events.csv", "report.json"}) EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  EXPECT_TRUE(std::filesystem::exists(dir / "notes.png"));
  std::filesystem::remove_all(dir);
}

/// An impact whose impulse overflows a double stops the run (log_event)
/// rather than logging J = inf and carrying on with infinite velocities.
/// The inputs are valid: a ball of m = 1e308 kg falls at 1 m/s onto an
/// elastic floor, ½ m v² = 5e307 J and m v = 1e308 N s are finite, but the
/// impulse (1 + e) m u = 2e308 N s is not (nor is the kinetic energy after
/// it: NaN). A run into a directory where the same scene with m = 1 kg wrote its
/// outputs leaves none of them behind.
TEST(Scenes, AnImpactWithANonFiniteImpulseStopsTheRunAndLeavesNoOutput) {
  const auto dir = std::filesystem::temp_directory_path() / "lagrangian_nonfinite_impulse";
  std::filesystem::remove_all(dir);
  Scene s = base(2.0);
  s.run.engine = "ode";
  s.bodies.push_back({.name = "ball", .mass = 1.0, .radius = 0.1, .position = {0, 0, 1}, .velocity = {0, 0, -1}});
  s.planes.push_back({.name = "floor", .point = {0, 0, 0}, .normal = {0, 0, 1}, .restitution = 1.0});
  s.output.directory = dir.string();
  s.output.plots = false;
  const RunResult ok = run(s);  // the same scene at m = 1 kg: one impact at t = 0.9 s, all outputs written
  ASSERT_EQ(ok.report.impacts, 1u);
  EXPECT_NEAR(ok.report.events.at(0).impulse, 2.0, 1e-12);
  for (const char* f : {"trajectory.csv", "events.csv", "report.json"}) ASSERT_TRUE(std::filesystem::exists(dir / f)) << f;

  s.bodies[0].mass = 1e308;
  try {
    run(s);
    FAIL() << "the run finished";
  } catch (const SimulationError& e) {
    const std::string what = e.what();
    EXPECT_NEAR(e.time(), 0.9, 1e-9);  // the ball's surface reaches the floor
    std::ostringstream head;
    head.precision(17);
    head << "impact ball-floor at t = " << e.time()
         << " gave a non-finite impulse or energy (J = inf N s, kinetic energy " << 0.5 * 1e308 << " -> ";
    const std::string tail = " J): its values overflow double precision, so the run was stopped";
    ASSERT_TRUE(what.starts_with(head.str())) << what;
    ASSERT_TRUE(what.ends_with(tail)) << what;
    // The velocity after the impulse is M⁻¹Jᵀ·inf, whose zero components
    // give 0·inf = NaN: the kinetic energy after it is NaN.
    const std::string after = what.substr(head.str().size(), what.size() - head.str().size() - tail.size());
    EXPECT_TRUE(std::isnan(std::strtod(after.c_str(), nullptr))) << after;
  }
  for (const char* f : {"trajectory.csv", "events.csv", "report.json", "trajectory.csv.partial"})
    EXPECT_FALSE(std::filesystem::exists(dir / f)) << f << " survived the failed run";
  std::filesystem::remove_all(dir);
}

}  // namespace

namespace {

TEST(Scenes, NewtonsCradleOnLinksSwingsWithTheLargeAmplitudePeriod) {
  // Five balls on links, the first released from θ0. Between impacts each
  // moving ball is a pendulum: the impacts come every half period
  // T/2 = 2 √(l/g) K(sin(θ0/2)), the first after T/4.
  const double l = 0.5, g = 9.81, theta0 = 0.3, R = 0.025;
  Scene s = base(1.5);
  s.gravity = UniformGravity{{0, 0, -g}};
  s.sphere_contacts = SphereContacts{1.0, {}};
  for (int i = 0; i < 5; ++i) {
    const double ax = 2 * R * i;
    Eigen::Vector3d r{ax, 0, -l};
    if (i == 0) r = {ax - l * std::sin(theta0), 0, -l * std::cos(theta0)};
    s.bodies.push_back({.name = "b" + std::to_string(i + 1), .mass = 0.1, .radius = R, .position = r});
    s.links.push_back({.a = "b" + std::to_string(i + 1), .anchor = {ax, 0, 0}});
  }
  const RunResult r = run(s, quiet());
  const double K = boost::math::ellint_1(std::sin(theta0 / 2));
  const double half = 2 * std::sqrt(l / g) * K;
  ASSERT_EQ(r.report.impacts, 8u);  // two passes of four pairwise impacts in 1.5 s
  EXPECT_NEAR(r.report.events[0].t, half / 2, 1e-8);
  EXPECT_NEAR(r.report.events[4].t, 1.5 * half, 1e-8);
  EXPECT_EQ(r.report.events[0].name, "b1-b2");
  EXPECT_EQ(r.report.events[3].name, "b4-b5");
  EXPECT_EQ(r.report.events[4].name, "b4-b5");
  // Each impact passes the whole momentum on: equal impulses m u.
  const double u = std::sqrt(2 * g * l * (1 - std::cos(theta0)));
  for (int k = 0; k < 8; ++k) EXPECT_NEAR(r.report.events[k].impulse, 0.1 * u, 1e-8) << k;
  EXPECT_LT(r.report.energy_drift_max, 1e-8);
}

}  // namespace

namespace {

TEST(Scenes, TheEventDrivenEngineNeedsSphereContactsDeclared) {
  // It makes every pair collide, so a scene must say that they do.
  Scene s = base(1.0);
  s.box = BoxContact{{0, 0, 0}, {1, 1, 1}, 1.0};
  s.bodies.push_back({.name = "a", .mass = 1, .radius = 0.1, .position = {0.2, 0.5, 0.5}, .velocity = {1, 0, 0}});
  s.bodies.push_back({.name = "b", .mass = 1, .radius = 0.1, .position = {0.8, 0.5, 0.5}});
  s.run.engine = "event_driven";
  try {
    run(s, quiet());
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "run.engine");
    EXPECT_NE(std::string(e.what()).find("[contacts.spheres]"), std::string::npos) << e.what();
  }
  // Without sphere contacts, "auto" runs them on the ODE engine: they pass through each other.
  s.run.engine = "auto";
  const RunResult r = run(s, quiet());
  EXPECT_EQ(r.engine, "ode");
  ASSERT_EQ(r.report.warnings.size(), 1u);  // not silently: the summary and report.json say why
  EXPECT_NE(r.report.warnings[0].find("no [contacts.spheres]: they pass through each other"), std::string::npos)
      << r.report.warnings[0];
  // a passes through b, meets the wall x = 1 − R at t = 0.7 and is back at x = 0.6 at t = 1.
  EXPECT_EQ(r.report.impacts, 1u);
  EXPECT_NEAR(r.report.events[0].t, 0.7, 1e-12);
  EXPECT_NEAR(pos(r, 0)[0], 0.6, 1e-10);
  EXPECT_NEAR(pos(r, 1)[0], 0.8, 1e-15);
}

// A gas without [contacts.spheres] runs on the ODE engine, each wall impact
// cutting a step. Free flight has no error, so the trial steps grow until
// they span the rest of the run and hold a crossing of most walls; the
// engine used to locate every one of them on the step's interpolant at every
// step, so the work per step grew with the run (1000 spheres, 0.02 s: about
// 10^3 s). Only the earliest closing is needed: the located contacts are
// counted, about one per step, whatever the run's length.
TEST(Scenes, AGasAgainstItsWallsLocatesAboutOneContactPerStep) {
  auto walls_only = [](double t_end) {
    Scene s = base(t_end, 1e-10, 1e-12);
    s.gas = GasFill{.count = 125, .mass = 1.0, .radius = 0.01, .speed = 1.0, .seed = 3};
    s.box = BoxContact{{0, 0, 0}, {1, 1, 1}, 1.0};
    return run(s, quiet());
  };
  const RunResult short_run = walls_only(1.0), long_run = walls_only(4.0);
  EXPECT_EQ(long_run.engine, "ode");
  EXPECT_GT(short_run.report.impacts, 20u);
  EXPECT_GT(long_run.report.impacts, 3 * short_run.report.impacts);
  auto per_step = [](const RunResult& r) {
    return static_cast<double>(r.contact_locations) / static_cast<double>(r.report.steps);
  };
  // Every crossing of a trial step located: about 190 a step (half the
  // 375 wall contacts cross in a step spanning the rest of the run).
  EXPECT_LT(per_step(short_run), 5.0) << short_run.contact_locations << " in " << short_run.report.steps;
  EXPECT_LT(per_step(long_run), 5.0) << long_run.contact_locations << " in " << long_run.report.steps;
  EXPECT_LT(per_step(long_run), 1.5 * per_step(short_run));  // does not grow with the run
  // Elastic walls: the energy is kept and every sphere stays in the box.
  EXPECT_LT(long_run.report.energy_drift_max, 1e-9);
  for (int i = 0; i < 125; ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(pos(long_run, i)[k], 0.01 - 1e-9);
      EXPECT_LE(pos(long_run, i)[k], 0.99 + 1e-9);
    }
}

// Built-in models of particles draw every body's path in space, not a
// configuration-space path: two bodies, the oblique impact, Newton's cradle.
TEST(Scenes, ModelsOfParticlesPlotEveryBodysPath) {
  for (const auto& [model, bodies] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"two_body", {"body1", "body2"}}, {"oblique_impact", {"s1", "s2"}},
           {"newtons_cradle", {"s1", "s2", "s3", "s4", "s5"}}}) {
    Scene s;
    s.name = model;
    s.model = ModelSpec{};
    s.model->name = model;
    s.run.t_end = 1.0;
    s.output.animation = false;
    s.output.directory = (std::filesystem::temp_directory_path() / ("lagrangian_model_paths_" + model)).string();
    const RunResult r = run(s);
    ASSERT_TRUE(r.plot_note.empty()) << r.plot_note;
    std::ifstream in(std::filesystem::path(s.output.directory) / "plots.gp");
    const std::string script((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(script.find("configuration space"), std::string::npos) << model;
    for (const std::string& b : bodies) EXPECT_NE(script.find("title '" + b + "'"), std::string::npos) << model << " " << b;
    std::filesystem::remove_all(s.output.directory);
  }
}

}  // namespace
