// Impacts of particle scenes whose bodies hang on links (src/scene/
// particle_impact.cpp): Newton's law keeps the links' rows, and the tangent
// flow crosses the impact by the saltation matrix on the rows' manifold. A
// bob on a rod against a wall, as bodies and as a text model (two
// formulations of one motion), against central differences of plain runs,
// against its closed-form loss of phase volume, and the mass that its
// motion does not depend on; two bobs on links meeting (a pair's law under
// two rows) against plain runs; a rest under a link is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/scene/io.hpp"
#include "lagrangian/scene/run.hpp"
#include "particle_scenes.hpp"
#include "plane_slide.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::scene;

constexpr double kG = 9.81, kE = 0.8;

/// A 1 kg bob (R = 0.05 m) on a 1 m rod from the origin, from the bottom at
/// 2 m/s along x, under gravity along −z, against a wall whose face is the
/// plane x = 0.5 m (its contact plane through x = 0.55 m, normal −x: the
/// bob's centre touches it at x = 0.5 m, θ = 30°), e = 0.8.
Scene bob_against_wall(double t_end) {
  return parse_scene(lagrangian_test::precise_scene("bob against a wall", t_end, R"(
[[bodies]]
name = "bob"
mass = 1.0
radius = 0.05
position = [0.0, 0.0, -1.0]
velocity = [2.0, 0.0, 0.0]
[gravity]
g = [0.0, 0.0, -9.81]
[[links]]
name = "rod"
a = "bob"
anchor = [0.0, 0.0, 0.0]
length = 1.0
[[contacts.planes]]
name = "wall"
point = [0.55, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
restitution = 0.8
)"));
}

/// The same motion stated as text in (x, z): L = ½ m (ẋ² + ż²) − m g z, the
/// rod x² + z² − 1 = 0, the wall's gap a − x.
Scene rod_as_text(double t_end) {
  return parse_scene(lagrangian_test::precise_scene("rod against a wall (text)", t_end, R"toml(
[model]
coordinates = ["x", "z"]
units = ["m", "m"]
kinetic = "0.5*m*(x_dot^2 + z_dot^2)"
potential = "m*g*z"
holonomic = ["x^2 + z^2 - 1"]
q = [0.0, -1.0]
qd = [2.0, 0.0]
[model.parameters]
m = 1.0
g = 9.81
a = 0.5
[[model.contacts]]
name = "wall"
gap = "a - x"
restitution = 0.8
unit = "m"
)toml"));
}

SensitivityRun columns_of(const Scene& scene, const std::vector<std::string>& parameters) {
  SensitivityRequest request;
  request.parameters = parameters;
  return sensitivity(scene, request);
}

// Bodies (x, y, z) against text (x, z): the final state, the column of the
// start's ẋ (tangent to both manifolds, so both give Φ e_ẋ), and the
// columns of g and of the wall's position across its two impacts:
// ∂/∂g_z = −∂/∂g, and the plane's point moves the wall as a does. The
// out-of-plane entries are 0.
TEST(ParticleImpactsOnRows, BobAgainstAWallIsTheTextModel) {
  const SensitivityRun bodies = columns_of(bob_against_wall(3.0), {"gravity.g[2]", "contacts.planes[0].point[0]"});
  const SensitivityRun text = columns_of(rod_as_text(3.0), {"g", "a"});
  EXPECT_EQ(bodies.model, "particles");
  EXPECT_EQ(text.model, "text");
  EXPECT_EQ(text.result.impacts, 2);
  EXPECT_EQ(bodies.result.impacts, text.result.impacts);
  const Eigen::VectorXd& xb = bodies.result.states.back();  // (x, y, z, ẋ, ẏ, ż)
  const Eigen::VectorXd& xt = text.result.states.back();    // (x, z, ẋ, ż)
  const int plane[4] = {0, 2, 3, 5};                          // the bodies' rows of (x, z, ẋ, ż)
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(xb[plane[i]], xt[i], 1e-9) << i;
  const Eigen::MatrixXd& sb = bodies.result.sensitivities.back();  // 6 × (6 + 2)
  const Eigen::MatrixXd& st = text.result.sensitivities.back();    // 4 × (4 + 2)
  ASSERT_EQ(sb.cols(), 8);
  ASSERT_EQ(st.cols(), 6);
  Eigen::MatrixXd b(4, 3), t(4, 3);
  for (int i = 0; i < 4; ++i) {
    b.row(i) << sb(plane[i], 3), -sb(plane[i], 6), sb(plane[i], 7);
    t.row(i) << st(i, 2), st(i, 4), st(i, 5);
  }
  const double scale = t.cwiseAbs().maxCoeff(), off = (b - t).cwiseAbs().maxCoeff();
  EXPECT_GT(t.col(2).cwiseAbs().maxCoeff(), 0.1);  // the wall's position matters
  EXPECT_LT(off, 1e-8 * scale) << "bodies:\n" << b << "\ntext:\n" << t;
  for (int i : {1, 4})
    for (int j : {3, 6, 7}) EXPECT_LT(std::abs(sb(i, j)), 1e-12 * scale) << i << ", " << j;
  std::printf("bob against a wall, %d impacts: bodies against text %.1e of %.3g\n", text.result.impacts, off, scale);
}

// The columns of e and of the start's ẋ against central differences of
// plain runs of the scene (e ± 1e-5, ẋ0 ± 1e-6), and the mass's column: a
// pendulum's motion does not depend on its mass, so every entry is 0 (the
// law's δ(M⁻¹) through the rod's impulse cancels).
TEST(ParticleImpactsOnRows, ColumnsMatchPlainRunsAndTheMassDropsOut) {
  const Scene scene = bob_against_wall(3.0);
  const SensitivityRun r = columns_of(scene, {"contacts.planes[0].restitution", "bodies[0].mass"});
  const Eigen::MatrixXd& s = r.result.sensitivities.back();
  ASSERT_EQ(s.cols(), 8);
  const auto end_state = [&](double e, double vx) {
    Scene moved = scene;
    moved.planes[0].restitution = e;
    moved.bodies[0].velocity[0] = vx;
    int impacts = 0;
    const Eigen::VectorXd x = lagrangian_test::plain_end_state(moved, &impacts);
    EXPECT_EQ(impacts, r.result.impacts);
    return x;
  };
  Eigen::MatrixXd fd(6, 2), ad(6, 2);
  fd.col(0) = (end_state(kE + 1e-5, 2.0) - end_state(kE - 1e-5, 2.0)) / 2e-5;
  fd.col(1) = (end_state(kE, 2.0 + 1e-6) - end_state(kE, 2.0 - 1e-6)) / 2e-6;
  ad << s.col(6), s.col(3);
  const double scale = fd.cwiseAbs().maxCoeff(), off = (ad - fd).cwiseAbs().maxCoeff();
  EXPECT_GT(fd.col(0).cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LT(off, 1e-6 * scale) << "AD:\n" << ad << "\ncentral differences:\n" << fd;
  EXPECT_LT(s.col(7).cwiseAbs().maxCoeff(), 1e-9 * scale) << s.col(7);
  std::printf("bob against a wall, %d impacts: e and xdot0 columns against central differences %.1e of %.3g; "
              "mass column %.1e\n",
              r.result.impacts, off, scale, s.col(7).cwiseAbs().maxCoeff());
}

// Two bobs of Newton's cradle on their own links (0.1 and 0.15 kg, 0.5 m,
// anchors 0.05 m apart, R = 0.025 m): the first, released from 0.3 rad,
// meets the second hanging at rest (e = 0.9) and again when it swings back,
// each impact a pair's law with both links' rows kept. The columns of e,
// both masses and g_z at 1.5 s against central differences of plain runs
// (each moved by ±1e-5 of itself).
TEST(ParticleImpactsOnRows, TwoPendulumsMeetingMatchPlainRuns) {
  const Scene scene = parse_scene(lagrangian_test::precise_scene("two bobs", 1.5, R"(
[gravity]
[contacts.spheres]
restitution = 0.9
[[bodies]]
name = "b1"
mass = 0.1
radius = 0.025
position = [-0.197760103, 0.0, -0.477668245]
[[bodies]]
name = "b2"
mass = 0.15
radius = 0.025
position = [0.0, 0.0, -0.5]
[[links]]
a = "b1"
anchor = [-0.05, 0.0, 0.0]
[[links]]
a = "b2"
anchor = [0.0, 0.0, 0.0]
)"));
  const std::vector<std::string> names{"contacts.spheres.restitution", "bodies[0].mass", "bodies[1].mass",
                                       "gravity.g[2]"};
  SensitivityRequest request;
  request.parameters = names;
  request.initial_state = false;
  const SensitivityRun r = sensitivity(scene, request);
  EXPECT_EQ(r.result.impacts, 2);
  const Eigen::MatrixXd& s = r.result.sensitivities.back();
  ASSERT_EQ(s.cols(), 4);
  const auto end_state = [&](const std::array<double, 4>& p) {
    Scene moved = scene;
    moved.sphere_contacts->restitution = p[0];
    moved.bodies[0].mass = p[1];
    moved.bodies[1].mass = p[2];
    moved.gravity->g[2] = p[3];
    int impacts = 0;
    const Eigen::VectorXd x = lagrangian_test::plain_end_state(moved, &impacts);
    EXPECT_EQ(impacts, r.result.impacts);
    return x;
  };
  const Eigen::MatrixXd fd =
      lagrangian_test::central_differences(end_state, std::array{0.9, 0.1, 0.15, -9.81}, 1e-5, 0.0);
  double worst = 0;
  for (int j = 0; j < 4; ++j) {
    const double scale = fd.col(j).cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 1e-3) << names[static_cast<std::size_t>(j)];
    worst = std::max(worst, (s.col(j) - fd.col(j)).cwiseAbs().maxCoeff() / scale);
  }
  EXPECT_LT(worst, 1e-6) << "AD:\n" << s << "\ncentral differences:\n" << fd;
  std::printf("two bobs meeting, %d impacts: columns of e, m1, m2, g_z against central differences %.1e of each "
              "column's largest entry\n",
              r.result.impacts, worst);
}

// Each impact keeps the rod and reverses the bob's speed along the circle
// times e. In the angle θ its saltation matrix is [[−e, 0], [(1 + e) θ̈/θ̇,
// −e]], det e²; out of the plane of the swing (δy, δẏ) the rod's impulse
// μ d (d the rod, along the plane) gives δẏ⁺ = δẏ + (μ/m) δy, det 1; the
// flow between impacts keeps phase volume. So the four exponents of the
// spherical pendulum's manifold sum to 2 ln e · impacts / T.
TEST(ParticleImpactsOnRows, BobAgainstAWallLosesPhaseVolumeAsESquaredPerImpact) {
  const double t_end = 6.0;
  const LyapunovRun r = lyapunov(bob_against_wall(t_end), LyapunovRequest{});
  ASSERT_EQ(r.result.spectrum.size(), 4u);
  EXPECT_EQ(r.result.impacts, 4);
  const double expected = 2 * std::log(kE) * r.result.impacts / t_end;
  EXPECT_NEAR(r.result.sum, expected, 1e-8) << r.result.impacts << " impacts";
  std::printf("bob against a wall: %d impacts, sum %.12f, closed form %.12f 1/s (differ by %.1e)\n",
              r.result.impacts, r.result.sum, expected, std::abs(r.result.sum - expected));
}

// A bob swinging down onto a floor with e = 0 sticks to it: a plain run
// rests the contact, and the tangent flow through a rest under a link is
// not derived: refused, naming the contact.
TEST(ParticleImpactsOnRows, RestUnderALinkIsRefused) {
  Scene scene = bob_against_wall(3.0);
  scene.planes[0].point = Eigen::Vector3d(0.0, 0.0, -0.6);
  scene.planes[0].normal = Eigen::Vector3d(0.0, 0.0, 1.0);
  scene.planes[0].restitution = 0.0;
  scene.planes[0].name = "floor";
  scene.bodies[0].position = Eigen::Vector3d(1.0, 0.0, 0.0);
  scene.bodies[0].velocity = Eigen::Vector3d::Zero();
  try {
    lyapunov(scene, LyapunovRequest{});
    ADD_FAILURE() << "a rest under a link was crossed";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("contact 'bob-floor' comes to rest"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not derived for a model with holonomic or Pfaffian constraints"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
