// Which momenta a run reports: only those the system's symmetries conserve
// (Noether), each left out with its reason. The judge
// (integrate/detail/momentum_symmetry.hpp) on forces whose conservation laws are
// known, then whole runs of built-in models whose conserved quantities are
// known in closed form.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "lagrangian/integrate/detail/momentum_symmetry.hpp"
#include "lagrangian/integrate/detail/point_momenta_monitor.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/projectile.hpp"

namespace {

using namespace lagrangian;
using detail::MomentumSymmetry;
using Flags = std::array<bool, 3>;

RunReport judged(MomentumSymmetry& sym) {
  RunReport r;
  sym.write(r);
  return r;
}

TEST(MomentumSymmetry, UniformGravityConservesHorizontalPAndVerticalL) {
  // F = m g along −z on two particles at different points: Ṗ = M g, and
  // L̇ = Σ m r × g has no z component.
  MomentumSymmetry sym({0, 0, 0});
  const double g[3] = {0, 0, -9.81};
  const double r1[3] = {0.3, -1.2, 2.0}, r2[3] = {-0.7, 0.4, 0.1};
  sym.add(2.0, r1, g);
  sym.add(0.5, r2, g);
  sym.end_probe(MomentumSymmetry::Source::force);
  const RunReport r = judged(sym);
  EXPECT_EQ(r.linear_momentum_conserved, (Flags{true, true, false}));
  EXPECT_EQ(r.angular_momentum_conserved, (Flags{false, false, true}));
  EXPECT_NE(r.linear_momentum_reason[2].find("external forces have a part along z"), std::string::npos);
  EXPECT_TRUE(r.linear_momentum_reason[0].empty());
}

TEST(MomentumSymmetry, AnInternalCentralForceConservesEverything) {
  // Newton's third law, the forces along the line between the particles:
  // m1 a1 = −m2 a2 = k (r2 − r1).
  MomentumSymmetry sym({0.5, -0.25, 1.0});
  const double r1[3] = {0.3, -1.2, 2.0}, r2[3] = {-0.7, 0.4, 0.1};
  const double m1 = 3.0, m2 = 0.25, k = 7.0;
  double a1[3], a2[3];
  for (int i = 0; i < 3; ++i) {
    a1[i] = k * (r2[i] - r1[i]) / m1;
    a2[i] = -k * (r2[i] - r1[i]) / m2;
  }
  sym.add(m1, r1, a1);
  sym.add(m2, r2, a2);
  sym.end_probe(MomentumSymmetry::Source::force);
  const RunReport r = judged(sym);
  EXPECT_EQ(r.linear_momentum_conserved, (Flags{true, true, true}));
  EXPECT_EQ(r.angular_momentum_conserved, (Flags{true, true, true}));
}

TEST(MomentumSymmetry, AFloorConservesLzButNotPz) {
  // A floor's impulse is along z wherever it acts: no moment about z.
  MomentumSymmetry sym({0, 0, 0});
  const double n[3] = {0, 0, 1};
  for (const auto& point : {std::array<double, 3>{1, 2, 0}, std::array<double, 3>{-3, 0.5, 0}}) {
    sym.add(1.0, point.data(), n);
    sym.end_probe(MomentumSymmetry::Source::contact);
  }
  const RunReport r = judged(sym);
  EXPECT_EQ(r.linear_momentum_conserved, (Flags{true, true, false}));
  EXPECT_EQ(r.angular_momentum_conserved, (Flags{false, false, true}));
  EXPECT_NE(r.linear_momentum_reason[2].find("impacts with fixed surfaces push along z"), std::string::npos);
}

TEST(MomentumSymmetry, DriftIsOverTheConservedComponentsOnly) {
  // One unit mass at the origin (L = 0), P sampled three times; x and y of P
  // conserved, z not, no component of L.
  RunReport r;
  r.linear_momentum_conserved = {true, true, false};
  r.angular_momentum_conserved = {false, false, false};
  detail::PointMomenta momenta({0.0, 0.0, 0.0});
  const double origin[3] = {0, 0, 0};
  auto sample = [&](const std::array<double, 3>& v) {
    momenta.clear();
    momenta.add(1.0, origin, v.data());
    momenta.record(r);
  };
  sample({1, 6, -70});
  EXPECT_EQ(r.linear_momentum_initial, (std::array<double, 3>{1, 6, -70}));
  EXPECT_EQ(r.linear_momentum_drift_final, 0.0);
  sample({1, 2, 30});  // |(0, −4)|, z ignored
  EXPECT_DOUBLE_EQ(r.linear_momentum_drift_final, 4.0);
  sample({4, 2, 30});  // |(3, −4)|
  EXPECT_DOUBLE_EQ(r.linear_momentum_drift_final, 5.0);
  sample({1, 7, 0});  // |(0, 1)|: the final drift falls, the largest stays
  EXPECT_DOUBLE_EQ(r.linear_momentum_drift_final, 1.0);
  EXPECT_DOUBLE_EQ(r.linear_momentum_drift_max, 5.0);
  EXPECT_EQ(r.angular_momentum_drift_max, 0.0);

  // A point off the origin: L = r × m v changes, but no component of L is
  // conserved, so no drift is reported.
  RunReport r2;
  r2.linear_momentum_conserved = r2.angular_momentum_conserved = {false, false, false};
  detail::PointMomenta off({0.0, 0.0, 0.0});
  const double at[3] = {1, 2, 3};
  for (const std::array<double, 3>& v : {std::array<double, 3>{1, 0, 0}, std::array<double, 3>{0, 5, -2}}) {
    off.clear();
    off.add(2.0, at, v.data());
    off.record(r2);
  }
  EXPECT_EQ(r2.linear_momentum_drift_max, 0.0);
  EXPECT_EQ(r2.angular_momentum_drift_max, 0.0);
  EXPECT_NE(off.angular()[0], 0.0);
}

SimulationOptions options(double t_end) {
  SimulationOptions o;
  o.t_end = t_end;
  o.output_interval = 0.01;
  return o;
}

TEST(MomentumSymmetry, ParticleOnASphereReportsLzAndNothingElse) {
  // The spherical pendulum in Cartesian coordinates: gravity along −z and a
  // normal force through the centre have no moment about z, so L_z is
  // conserved; P is not, nor L_x, L_y.
  const models::ParticleOnSphere model(1.0, 1.0, 9.81);
  State<3> s;
  s.q << std::sin(1.0), 0.0, -std::cos(1.0);
  s.qd << 0.0, 1.5, 0.0;
  const RunReport r = simulate(model, s, options(5.0));
  ASSERT_TRUE(r.has_particles);
  EXPECT_EQ(r.linear_momentum_conserved, (Flags{false, false, false}));
  EXPECT_EQ(r.angular_momentum_conserved, (Flags{false, false, true}));
  // L_z = m (x ẏ − y ẋ) = sin(1) · 1.5 at t0.
  EXPECT_NEAR(r.angular_momentum_initial[2], std::sin(1.0) * 1.5, 1e-15);
  EXPECT_LT(r.angular_momentum_drift_max, 1e-8);
  const std::string summary = r.summary();
  EXPECT_NE(summary.find("conserved about z: drift max"), std::string::npos) << summary;
  EXPECT_NE(summary.find("P_z not conserved: the external forces have a part along z"), std::string::npos) << summary;
  const std::string json = r.to_json();
  EXPECT_NE(json.find("\"angular_momentum_conserved\": [false, false, true]"), std::string::npos) << json;
}

TEST(MomentumSymmetry, AProjectileConservesTheHorizontalMomentumOnly) {
  // Gravity along −y: p_x = m ẋ stays m u cos α exactly.
  const models::Projectile model(2.0, 9.81);
  State<2> s;
  s.qd << 3.0, 4.0;
  const RunReport r = simulate(model, s, options(0.8));
  EXPECT_EQ(r.linear_momentum_conserved, (Flags{true, false, true}));  // no motion along z
  EXPECT_NE(r.linear_momentum_reason[1].find("external forces have a part along y"), std::string::npos);
  EXPECT_NEAR(r.linear_momentum_initial[0], 6.0, 1e-15);
  EXPECT_LE(r.linear_momentum_drift_max, 1e-12);
}

TEST(MomentumSymmetry, WallsBreakWhatTheFloorLeaves) {
  // Three spheres in a box without gravity: free flight and sphere–sphere
  // impacts conserve P and L, but the walls push along x and y.
  const models::SpheresInBox<3> box({1.0, 2.0, 1.5}, {0.1, 0.1, 0.1}, 2.0, 2.0, 1.0);
  State<6> s;
  s.q << 0.5, 1.0, 1.5, 1.0, 1.0, 0.3;
  s.qd << 0.7, 0.3, -0.2, 0.5, 0.1, 0.4;
  const RunReport r = simulate(box, s, options(3.0));
  EXPECT_GT(r.impacts, 0u);
  EXPECT_TRUE(r.conserved_momenta.empty());  // every coordinate is cyclic in L, but touched by a contact
  EXPECT_EQ(r.linear_momentum_conserved, (Flags{false, false, true}));  // the plane of motion: P_z = 0
  EXPECT_NE(r.linear_momentum_reason[0].find("impacts with fixed surfaces push along x"), std::string::npos);
  EXPECT_EQ(r.linear_momentum_reason[0].find("external forces"), std::string::npos);
  EXPECT_EQ(r.angular_momentum_conserved, (Flags{true, true, false}));

  // A ball on a floor: x and y are cyclic and the floor pushes along z only.
  const models::BallAndPlane ball(1.0, 0.1, 0.8, 9.81);
  State<3> b;
  b.q << 0.0, 0.0, 1.0;
  b.qd << 0.3, -0.2, 0.0;
  const RunReport rb = simulate(ball, b, options(2.0));
  EXPECT_EQ(rb.conserved_momenta.size(), 2u);
  EXPECT_EQ(rb.linear_momentum_conserved, (Flags{true, true, false}));
  EXPECT_EQ(rb.angular_momentum_conserved, (Flags{false, false, true}));
  EXPECT_GT(rb.impacts, 0u);
  EXPECT_LE(rb.linear_momentum_drift_max, 1e-12);
}

}  // namespace
