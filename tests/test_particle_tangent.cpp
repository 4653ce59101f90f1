// The tangent flow of particle scenes (src/scene/particle_tangent.cpp):
// ∂a/∂(r, v) of the force effects by AD against central differences of the
// scene's composed right-hand side, the Lyapunov spectrum of two bodies
// against the built-in two-body model's (the Euler–Lagrange equations of
// L = T − V: another derivation of the same flow), a closed-form spectrum
// under linear drag, and the refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/scene/io.hpp"
#include "../src/scene/particle_engine.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::scene;

const char* const kEveryForce = R"(
name = "every force"
[run]
t_end = 1.0
[[bodies]]
name = "a"
mass = 2.0
position = [0.3, -0.2, 0.5]
velocity = [0.4, 1.1, -0.7]
[[bodies]]
name = "b"
mass = 0.7
position = [-0.6, 0.8, 0.1]
velocity = [-0.9, 0.2, 0.5]
[[bodies]]
name = "c"
mass = 1.3
position = [0.9, 0.7, -0.4]
velocity = [0.1, -0.5, 1.4]
[gravity]
[newtonian_gravity]
G = 0.8
[[springs]]
a = "a"
b = "b"
stiffness = 12.0
rest_length = 0.6
[[springs]]
a = "c"
anchor = [0.0, 0.0, 1.0]
stiffness = 5.0
rest_length = 0.0
[[linear_drag]]
coefficient = 0.3
bodies = ["a", "c"]
[[quadratic_drag]]
coefficient = 0.05
)";

// ∂a/∂x by AD against central differences of ẋ = [v; a], the right-hand
// side a run integrates (step 1e-6 · max(1, |x_j|): truncation ~1e-12,
// rounding ~1e-10 relative to the entries).
TEST(ParticleTangent, JacobianOfEveryForceMatchesCentralDifferences) {
  const Scene scene = parse_scene(kEveryForce);
  const std::vector<double> x = scene::detail::initial_state(scene);
  const int n = static_cast<int>(x.size()) / 2;
  Eigen::VectorXd a;
  const Eigen::MatrixXd j = scene::detail::particle_acceleration_jacobian(scene, x, &a);
  ASSERT_EQ(j.rows(), n);
  ASSERT_EQ(j.cols(), 2 * n);
  scene::detail::ComposedRhs rhs(scene);
  std::vector<double> dx(x.size()), up(x.size()), down(x.size());
  rhs(x.data(), dx.data(), 0.0);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(a[i], dx[static_cast<std::size_t>(n + i)], 1e-13 * (1 + std::abs(a[i])));
  double worst = 0, scale = j.cwiseAbs().maxCoeff();
  for (int c = 0; c < 2 * n; ++c) {
    std::vector<double> xp = x, xm = x;
    const double h = 1e-6 * std::max(1.0, std::abs(x[static_cast<std::size_t>(c)]));
    xp[static_cast<std::size_t>(c)] += h;
    xm[static_cast<std::size_t>(c)] -= h;
    rhs(xp.data(), up.data(), 0.0);
    rhs(xm.data(), down.data(), 0.0);
    for (int i = 0; i < n; ++i)
      worst = std::max(worst, std::abs((up[static_cast<std::size_t>(n + i)] - down[static_cast<std::size_t>(n + i)]) /
                                           (2 * h) -
                                       j(i, c)));
  }
  EXPECT_LT(worst, 1e-8 * scale) << "largest entry " << scale;
  // Every effect reaches J: gravity between the bodies couples their
  // positions, the drags their velocities.
  EXPECT_NE(j(0, 3), 0.0);        // ∂a_a,x/∂r_b,x: Newton and the spring
  EXPECT_NE(j(0, n + 0), 0.0);    // ∂a_a,x/∂v_a,x: both drags
  EXPECT_EQ(j(0, n + 3), 0.0);    // no force on a depends on b's velocity
}

// Two bodies under Newtonian gravity: the particle scene (3N = 6
// coordinates) and the built-in two-body model in the plane (4), from the
// same start. Motion in the plane keeps in-plane and out-of-plane tangent
// vectors apart (J is block diagonal there) and the initial vectors are
// the unit vectors in the same order, so Benettin's QR factors each block
// on its own: the model's 8 finite-time exponents are 8 of the scene's 12
// (to the integration error), the other 4 those of the out-of-plane
// motion. Both sums are 0 (Hamiltonian), MEGNO → 2 (Kepler shear).
TEST(ParticleTangent, TwoBodiesHaveTheTwoBodyModelsSpectrum) {
  const std::string run = R"(
[run]
method = "dopri5"
t_end = 30.0
rtol = 1e-12
atol = 1e-14
)";
  const Scene particles = parse_scene("name = \"pair\"\n" + run + R"(
[newtonian_gravity]
G = 1.0
[[bodies]]
name = "primary"
mass = 3.0
position = [-0.5, 0.0, 0.0]
velocity = [0.0, -0.3, 0.0]
[[bodies]]
name = "secondary"
mass = 1.0
position = [1.5, 0.0, 0.0]
velocity = [0.0, 0.9, 0.0]
)");
  const Scene model = parse_scene("name = \"pair model\"\n" + run + R"(
[model]
name = "two_body"
q = [-0.5, 0.0, 1.5, 0.0]
qd = [0.0, -0.3, 0.0, 0.9]
[model.parameters]
m1 = 3.0
m2 = 1.0
k = 3.0
)");
  const LyapunovRun p = lyapunov(particles, LyapunovRequest{});
  const LyapunovRun m = lyapunov(model, LyapunovRequest{});
  ASSERT_EQ(p.result.spectrum.size(), 12u);
  ASSERT_EQ(m.result.spectrum.size(), 8u);
  EXPECT_EQ(p.model, "particles");
  std::vector<bool> taken(12, false);
  for (double lm : m.result.spectrum) {
    int best = -1;
    for (int i = 0; i < 12; ++i)
      if (!taken[static_cast<std::size_t>(i)] &&
          (best < 0 || std::abs(p.result.spectrum[static_cast<std::size_t>(i)] - lm) <
                           std::abs(p.result.spectrum[static_cast<std::size_t>(best)] - lm)))
        best = i;
    taken[static_cast<std::size_t>(best)] = true;
    EXPECT_NEAR(p.result.spectrum[static_cast<std::size_t>(best)], lm, 1e-8) << "model exponent " << lm;
  }
  EXPECT_GT(m.result.spectrum.front(), 0.01);  // the shear's finite-time growth, not 0
  EXPECT_NEAR(p.result.sum, 0.0, 1e-9);
  EXPECT_NEAR(m.result.sum, 0.0, 1e-9);
  // MEGNO follows the first tangent vector, δx₁ of the primary in both.
  EXPECT_NEAR(p.result.megno_mean, m.result.megno_mean, 1e-6);
}

// One body under gravity and linear drag b: per axis, in the canonical
// (q, p = m v), Φ(t) = [[1, (1 − e^(−γt))/(γ m)], [0, e^(−γt)]], γ = b/m,
// is upper triangular, so Benettin's QR of it is Φ itself: the finite-time
// exponents are exactly 0 (three times) and −γ (three times) at every t.
TEST(ParticleTangent, LinearDragGivesZeroAndMinusTheRateExactly) {
  const Scene scene = parse_scene(R"(
name = "dragged"
[run]
method = "dopri5"
t_end = 7.0
rtol = 1e-11
atol = 1e-13
[[bodies]]
name = "ball"
mass = 0.5
position = [0.0, 0.0, 2.0]
velocity = [3.0, -1.0, 4.0]
[gravity]
[[linear_drag]]
coefficient = 0.2
)");
  const LyapunovRun r = lyapunov(scene, LyapunovRequest{});
  const double gamma = 0.2 / 0.5;
  ASSERT_EQ(r.result.spectrum.size(), 6u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(r.result.spectrum[static_cast<std::size_t>(i)], 0.0, 1e-9);
    EXPECT_NEAR(r.result.spectrum[static_cast<std::size_t>(3 + i)], -gamma, 1e-9);
  }
  EXPECT_NEAR(r.result.sum, -3 * gamma, 1e-9);  // Liouville: det Φ = e^(−3γt)
}

// Rows and contacts: refused, naming the scene and what it has.
TEST(ParticleTangent, RowsAndContactsAreRefused) {
  const std::string scenes = std::string(LAGRANGIAN_SOURCE_DIR) + "/examples/scenes/";
  try {
    lyapunov(load_scene(scenes + "bouncing_ball.toml"), LyapunovRequest{});
    ADD_FAILURE() << "a scene with a contact plane was analysed";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("lyapunov: particle scene 'bouncing ball': "), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("this one has 1 contact plane"), std::string::npos) << e.what();
  }
  try {
    floquet(load_scene(scenes + "link_pendulum.toml"), FloquetRequest{1.0});
    ADD_FAILURE() << "a scene with a link was analysed";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("floquet: particle scene"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("without constraints or contacts; this one has 1 link"), std::string::npos) << e.what();
  }
  try {
    lyapunov(load_scene(scenes + "gas_in_container.toml"), LyapunovRequest{});
    ADD_FAILURE() << "a gas was analysed";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("this one has a gas"), std::string::npos) << e.what();
  }
}

// A circular orbit of the pair is periodic: every multiplier of its
// monodromy matrix is 1 (translations, rotations, the energy and the
// orbit's phase give Jordan blocks, so the computed ones split by about
// the square root of the integration error).
TEST(ParticleTangent, CircularBinaryHasUnitMultipliers) {
  const Scene scene = load_scene(std::string(LAGRANGIAN_SOURCE_DIR) + "/examples/scenes/binary_star.toml");
  const double period = 2 * std::acos(-1.0) * std::sqrt(8.0 / 4.0);  // 2π √(d³ / G(m₁ + m₂)), d = 2
  const FloquetRun r = floquet(scene, FloquetRequest{period});
  ASSERT_EQ(r.result.multipliers.size(), 12u);
  for (const auto& mu : r.result.multipliers) EXPECT_LT(std::abs(mu - 1.0), 1e-5) << mu;
  EXPECT_NEAR(r.result.monodromy.determinant(), 1.0, 1e-9);
  EXPECT_LT(r.result.closure, 1e-9);
}

// Quadratic drag on a body at rest: |v| v has the derivative 0 at v = 0
// (|v| has none there); J stays finite and its velocity block is 0.
TEST(ParticleTangent, QuadraticDragOnABodyAtRestHasAZeroDerivative) {
  const Scene scene = parse_scene(R"(
name = "dropped"
[run]
t_end = 1.0
[[bodies]]
name = "ball"
mass = 0.06
position = [0.0, 0.0, 1.0]
[gravity]
[[quadratic_drag]]
coefficient = 0.001
)");
  const std::vector<double> x = scene::detail::initial_state(scene);
  const Eigen::MatrixXd j = scene::detail::particle_acceleration_jacobian(scene, x);
  EXPECT_TRUE(j.allFinite()) << j;
  EXPECT_EQ(j.cwiseAbs().maxCoeff(), 0.0) << j;
  // ... and a run through the rest point at t0 is a normal one: the ball
  // falls, λ of the drag's slowing small and negative.
  const LyapunovRun r = lyapunov(scene, LyapunovRequest{});
  EXPECT_TRUE(std::isfinite(r.result.sum));
  EXPECT_LT(r.result.sum, 0.0);
}

// A body on a spring to an anchor with rest length 0 (a 3-D harmonic
// oscillator, ω = √(k/m)): over half a period Φ = −I, so all six
// multipliers are −1 (the free flight J = 0 would give +1).
TEST(ParticleTangent, IsotropicOscillatorOverHalfAPeriodHasMultipliersMinusOne) {
  const Scene scene = parse_scene(R"(
name = "oscillator"
[run]
method = "dopri5"
rtol = 1e-12
atol = 1e-14
t_end = 1.0
[[bodies]]
name = "bob"
mass = 0.5
position = [0.3, -0.1, 0.2]
velocity = [0.0, 0.4, -0.2]
[[springs]]
a = "bob"
anchor = [0.0, 0.0, 0.0]
stiffness = 8.0
rest_length = 0.0
)");
  const double omega = std::sqrt(8.0 / 0.5);
  const FloquetRun r = floquet(scene, FloquetRequest{std::acos(-1.0) / omega});
  ASSERT_EQ(r.result.multipliers.size(), 6u);
  for (const auto& mu : r.result.multipliers) EXPECT_LT(std::abs(mu + 1.0), 1e-8) << mu;
  EXPECT_LT((r.result.monodromy + Eigen::MatrixXd::Identity(6, 6)).cwiseAbs().maxCoeff(), 1e-8);
}

// The largest exponent from one tangent vector (J along its direction,
// without J) against the first of the whole spectrum (J in passes of four
// directions): the same vector's growth, on a regular motion.
TEST(ParticleTangent, OneDirectionAgreesWithTheWholeJacobian) {
  const Scene scene = load_scene(std::string(LAGRANGIAN_SOURCE_DIR) + "/examples/scenes/binary_star.toml");
  const LyapunovRun one = lyapunov(scene, LyapunovRequest{1, 0.0});
  const LyapunovRun all = lyapunov(scene, LyapunovRequest{});
  ASSERT_EQ(one.result.spectrum.size(), 1u);
  EXPECT_GT(one.result.spectrum[0], 0.01);
  EXPECT_NEAR(one.result.spectrum[0], all.result.spectrum[0], 1e-6 * (1 + all.result.spectrum[0]));
}

// The circular binary's orbit found from a period guessed 3 % long: any
// Kepler orbit of energy E has the period 2π √(a³ / G(m₁ + m₂)) with
// a = G m₁ m₂ / (−2E): the period found is that of its own energy.
TEST(ParticleTangent, BinaryOrbitFoundFromALongGuess) {
  const Scene scene = load_scene(std::string(LAGRANGIAN_SOURCE_DIR) + "/examples/scenes/binary_star.toml");
  const double period = 2 * std::acos(-1.0) * std::sqrt(2.0);
  FloquetRequest request{1.03 * period};
  request.find_orbit = true;
  const FloquetRun r = floquet(scene, request);
  ASSERT_EQ(r.result.q.size(), 6u);
  EXPECT_GT(r.result.iterations, 1);
  const double m1 = 3.0, m2 = 1.0;
  Eigen::Vector3d d, v1, v2;
  for (int k = 0; k < 3; ++k) {
    d[k] = r.result.q[static_cast<std::size_t>(3 + k)] - r.result.q[static_cast<std::size_t>(k)];
    v1[k] = r.result.qd[static_cast<std::size_t>(k)];
    v2[k] = r.result.qd[static_cast<std::size_t>(3 + k)];
  }
  const double energy = 0.5 * m1 * v1.squaredNorm() + 0.5 * m2 * v2.squaredNorm() - m1 * m2 / d.norm();
  const double a = m1 * m2 / (-2 * energy);
  // Near the start's orbit (d = 2): the energy row holds E to first order
  // in each step only, and the degenerate directions of the pair (its
  // centre of mass, the orbit's orientation and shape) let Newton's
  // minimum-norm steps wander along the family (measured a = 2.108 m).
  EXPECT_NEAR(a, 2.0, 0.2);
  EXPECT_NEAR(r.period, 2 * std::acos(-1.0) * std::sqrt(a * a * a / (m1 + m2)), 1e-8 * period);
  EXPECT_LT(r.result.closure, 1e-7);
}

}  // namespace
