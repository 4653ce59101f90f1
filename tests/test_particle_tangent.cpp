// The tangent flow of particle scenes (src/scene/particle_tangent.cpp):
// ∂a/∂(r, v) of the force effects, and of the constrained accelerations of
// links and surfaces, by AD against central differences of the scene's
// composed right-hand side, the Lyapunov spectrum of two bodies against the
// built-in two-body model's (the Euler–Lagrange equations of L = T − V:
// another derivation of the same flow), a closed-form spectrum under linear
// drag, the conical pendulum's closed-form multipliers on a link and on a
// sphere, and the refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/scene/io.hpp"
#include "lagrangian/scene/run.hpp"
#include "../src/scene/particle_engine.hpp"
#include "particle_scenes.hpp"
#include "plane_slide.hpp"

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
// rounding ~1e-10 relative to the entries): the largest difference is
// below 1e-8 of J's largest entry, and a is the run's. Returns J.
Eigen::MatrixXd expect_jacobian_matches_central_differences(const Scene& scene, const std::vector<double>& x) {
  const int n = static_cast<int>(x.size()) / 2;
  Eigen::VectorXd a;
  const Eigen::MatrixXd j = scene::detail::particle_acceleration_jacobian(scene, x, &a);
  EXPECT_EQ(j.rows(), n);
  EXPECT_EQ(j.cols(), 2 * n);
  scene::detail::ComposedRhs rhs(scene);
  std::vector<double> dx(x.size()), up(x.size()), down(x.size());
  rhs(x.data(), dx.data(), 0.0);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(a[i], dx[static_cast<std::size_t>(n + i)], 1e-12 * (1 + std::abs(a[i])));
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
  return j;
}

// Every effect, J at the start.
TEST(ParticleTangent, JacobianOfEveryForceMatchesCentralDifferences) {
  const Scene scene = parse_scene(kEveryForce);
  const std::vector<double> x = scene::detail::initial_state(scene);
  const int n = static_cast<int>(x.size()) / 2;
  const Eigen::MatrixXd j = expect_jacobian_matches_central_differences(scene, x);
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

// Contacts touching at the start, and a gas's Floquet multipliers: refused,
// naming the contact or the scene.
TEST(ParticleTangent, TouchingContactsAndAGasAreRefused) {
  const std::string scenes = std::string(LAGRANGIAN_SOURCE_DIR) + "/examples/scenes/";
  // Newton's cradle starts with its spheres touching at rest: a neighbouring
  // start moves them apart or into each other, so the flow has no
  // derivative there (its links and contacts together are taken:
  // test_particle_impacts_on_rows.cpp).
  try {
    floquet(load_scene(scenes + "newtons_cradle.toml"), FloquetRequest{1.0});
    ADD_FAILURE() << "a start with touching spheres was analysed";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("tangent flow: contact 'b4-b5' touches slower than contact_touch_speed"),
              std::string::npos)
        << e.what();
  }
  try {
    FloquetRequest request;
    request.period = 1.0;
    floquet(load_scene(scenes + "gas_in_container.toml"), request);
    ADD_FAILURE() << "a gas's Floquet multipliers were taken";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("floquet: particle scene 'gas in a container': the Floquet multipliers of "
                                         "a gas are not derived (its motion has no period)"),
              std::string::npos)
        << e.what();
  }
  // (Its Lyapunov exponents are the event-driven engine's: test_gas_tangent.cpp.)
}

// An elastic ball dropped from rest at h = 1.2 m above a floor bounces back
// to the top after T = 2τ, τ = √(2h/g). Over T, in (z, ż): flight
// [[1, τ], [0, 1]], the floor's saltation matrix [[−1, 0], [2g/|v|, −1]]
// (|v| = gτ), flight again: Φ_z = [[1, 0], [2/τ, 1]] (a higher drop takes
// longer: the neighbour is still rising when the ball is back at the top).
// Horizontally the floor does nothing: Φ_x = Φ_y = [[1, T], [0, 1]].
TEST(ParticleTangent, ElasticBallOnAFloorHasTheClosedFormMonodromy) {
  const Scene scene = parse_scene(R"(
name = "elastic ball"
[run]
method = "dopri5"
rtol = 1e-12
atol = 1e-14
t_end = 1.0
[[bodies]]
name = "ball"
mass = 0.2
radius = 0.05
position = [0.3, -0.1, 1.25]
[gravity]
[[contacts.planes]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
restitution = 1.0
)");
  const double g = 9.81, tau = std::sqrt(2 * 1.2 / g), period = 2 * tau;
  const FloquetRun r = floquet(scene, FloquetRequest{period});
  Eigen::MatrixXd expected = Eigen::MatrixXd::Identity(6, 6);
  expected(0, 3) = expected(1, 4) = period;
  expected(5, 2) = 2 / tau;
  EXPECT_LT((r.result.monodromy - expected).cwiseAbs().maxCoeff(), 1e-8) << r.result.monodromy;
  EXPECT_EQ(r.result.impacts, 1);
  EXPECT_LT(r.result.closure, 1e-9);
}

/// Two free spheres (m = 1.5 and 0.8 kg, radii 0.2 and 0.3 m) after time T
/// from x = [r1, r2, u1, u2], written out: they fly straight until
/// |r1 − r2 + (u1 − u2) τ| = R (the smaller root), then exchange the
/// impulse J n̂ along n̂ = d(τ)/R, J = −(1 + e) n̂·(u1 − u2)/(1/m1 + 1/m2),
/// and fly on. Another derivation of what the tangent flow crosses.
Eigen::VectorXd two_spheres_after(const Eigen::VectorXd& x, double t, double e) {
  const double m1 = 1.5, m2 = 0.8, radius = 0.5;
  const Eigen::Vector3d r1 = x.segment<3>(0), r2 = x.segment<3>(3), u1 = x.segment<3>(6), u2 = x.segment<3>(9);
  const Eigen::Vector3d dr = r1 - r2, du = u1 - u2;
  const double a = du.squaredNorm(), b = 2 * dr.dot(du), c = dr.squaredNorm() - radius * radius;
  const double tau = (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
  const Eigen::Vector3d normal = (dr + du * tau) / radius;
  const double impulse = -(1 + e) * normal.dot(du) / (1 / m1 + 1 / m2);
  const Eigen::Vector3d w1 = u1 + impulse / m1 * normal, w2 = u2 - impulse / m2 * normal;
  Eigen::VectorXd out(12);
  out << r1 + u1 * tau + w1 * (t - tau), r2 + u2 * tau + w2 * (t - tau), w1, w2;
  return out;
}

// Two spheres meeting off-centre (impact parameter 0.17 of R = 0.5 m, e =
// 0.7) in free space: Φ(2 s) across the impact, of all 12 coordinates,
// against central differences of the flow written out above (step 1e-6:
// error ~1e-10 of its entries).
TEST(ParticleTangent, TwoSpheresMeetingOffCentreMatchTheFlowWrittenOut) {
  const Scene scene = parse_scene(R"(
name = "two spheres"
[run]
method = "dopri5"
rtol = 1e-12
atol = 1e-14
t_end = 1.0
[contacts.spheres]
restitution = 0.7
[[bodies]]
name = "a"
mass = 1.5
radius = 0.2
position = [0.0, 0.0, 0.0]
velocity = [1.0, 0.1, 0.0]
[[bodies]]
name = "b"
mass = 0.8
radius = 0.3
position = [1.5, 0.25, 0.05]
velocity = [-0.5, 0.0, 0.02]
)");
  const double t = 2.0, e = 0.7;
  const std::vector<double> start = scene::detail::initial_state(scene);
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(start.data(), 12);
  Eigen::MatrixXd expected(12, 12);
  for (int c = 0; c < 12; ++c) {
    const double h = 1e-6 * std::max(1.0, std::abs(x[c]));
    Eigen::VectorXd up = x, down = x;
    up[c] += h;
    down[c] -= h;
    expected.col(c) = (two_spheres_after(up, t, e) - two_spheres_after(down, t, e)) / (2 * h);
  }
  const FloquetRun r = floquet(scene, FloquetRequest{t});
  EXPECT_EQ(r.result.impacts, 1);
  // The motion itself: max |x(t) − x(0)| as written out.
  EXPECT_NEAR(r.result.closure, (two_spheres_after(x, t, e) - x).cwiseAbs().maxCoeff(), 1e-10);
  const double scale = expected.cwiseAbs().maxCoeff();
  EXPECT_LT((r.result.monodromy - expected).cwiseAbs().maxCoeff(), 1e-7 * scale)
      << "tangent flow:\n" << r.result.monodromy << "\nwritten out:\n" << expected;
  // The impact couples what free flight keeps apart: a's final velocity
  // depends on b's start.
  EXPECT_GT(std::abs(expected(6, 3)), 0.01);
}

// Links between bodies and to an anchor, a sphere and a plane, under
// gravity, a spring and linear drag: the constrained accelerations
//   q̈ = a_F + M⁻¹Cᵀλ,  λ = S⁺(−γ − C a_F),  S = C M⁻¹ Cᵀ,
// are a smooth function of the whole state (on the rows and off them), and
// J by AD through the rows and the multipliers must be its derivative:
// against central differences of the right-hand side a run integrates
// (its own rows on doubles, its own solver). Off the velocity constraints
// on purpose (C v ≠ 0), so γ's every term counts.
TEST(ParticleTangent, JacobianWithLinksAndSurfacesMatchesCentralDifferences) {
  const Scene scene = parse_scene(R"(
name = "held"
[run]
t_end = 1.0
[[bodies]]
name = "a"
mass = 2.0
position = [0.6, -0.2, -0.7]
[[bodies]]
name = "b"
mass = 0.7
position = [1.1, 0.3, -1.2]
[[bodies]]
name = "c"
mass = 1.3
position = [-0.5, 0.9, 0.4]
[[bodies]]
name = "d"
mass = 0.4
position = [0.2, -0.8, 0.3]
[gravity]
[[springs]]
a = "b"
b = "c"
stiffness = 7.0
rest_length = 0.5
[[linear_drag]]
coefficient = 0.3
bodies = ["b", "d"]
[[links]]
a = "a"
anchor = [0.0, 0.0, 0.0]
[[links]]
a = "b"
b = "a"
[[surfaces]]
body = "c"
kind = "sphere"
centre = [0.0, 0.0, 1.0]
radius = 1.1916375287812984
[[surfaces]]
body = "d"
kind = "plane"
point = [0.2, -0.8, 0.3]
normal = [0.3, -0.4, 0.8660254037844386]
)");
  // The scene starts at rest on its rows; the state here moves off them.
  std::vector<double> x = scene::detail::initial_state(scene);
  const int n = static_cast<int>(x.size()) / 2;
  for (int i = 0; i < n; ++i) x[static_cast<std::size_t>(n + i)] = std::sin(1.3 + 0.7 * i);
  const Eigen::MatrixXd j = expect_jacobian_matches_central_differences(scene, x);
  // The rows couple what the forces alone do not: the link between a and b
  // makes a's acceleration depend on b's position and velocity (γ = |v_a − v_b|²).
  EXPECT_GT(std::abs(j(0, 3)), 1e-3);
  EXPECT_GT(std::abs(j(0, n + 3)), 1e-3);
}

/// A conical pendulum: a bob of mass 0.7 kg at θ0 = 0.6 rad from the
/// downward vertical on a 1.2 m link to the origin (or on a sphere of that
/// radius), going round at φ̇0 = √(g/(l cos θ0)).
std::string conical_pendulum(const std::string& held_by) {
  const double g = 9.81, l = 1.2, theta = 0.6, rate = std::sqrt(g / (l * std::cos(theta)));
  char body[400];
  std::snprintf(body, sizeof body,
                "name = \"conical\"\n[run]\nmethod = \"dopri5\"\nrtol = 1e-12\natol = 1e-14\nt_end = 1.0\n"
                "[[bodies]]\nname = \"bob\"\nmass = 0.7\nposition = [%.17g, 0.0, %.17g]\n"
                "velocity = [0.0, %.17g, 0.0]\n[gravity]\n",
                l * std::sin(theta), -l * std::cos(theta), l * std::sin(theta) * rate);
  return std::string(body) + held_by;
}

// The conical pendulum is a periodic orbit of the spherical pendulum, of
// period T = 2π/φ̇0. Its monodromy matrix on the 4-dimensional tangent
// space of the manifold |r| = l: the phase and the angular momentum give
// the multipliers 1, 1 (a Jordan block); θ's small oscillations at fixed
// angular momentum h = sin²θ φ̇ obey θ̈ = h² cos θ/sin³θ − (g/l) sin θ,
// whose derivative at θ0 is −φ̇0² (1 + 3 cos² θ0), so over T they turn by
// σ = 2π √(1 + 3 cos² θ0): the pair e^{±iσ}. The same on a link and on a
// sphere (two different rows: ½(|r|² − l²) from a link to the anchor, and
// from the sphere's centre).
TEST(ParticleTangent, ConicalPendulumHasTheClosedFormMultipliersOnALinkAndOnASphere) {
  const double g = 9.81, l = 1.2, theta = 0.6, pi = std::acos(-1.0);
  const double period = 2 * pi / std::sqrt(g / (l * std::cos(theta)));
  const double sigma = 2 * pi * std::sqrt(1 + 3 * std::cos(theta) * std::cos(theta));
  const double turn = std::remainder(sigma, 2 * pi);  // in (−π, π]
  for (const std::string& held_by : {std::string("[[links]]\nname = \"rod\"\na = \"bob\"\nanchor = [0.0, 0.0, 0.0]\n"),
                                    std::string("[[surfaces]]\nname = \"bowl\"\nbody = \"bob\"\nkind = \"sphere\"\n"
                                                "centre = [0.0, 0.0, 0.0]\nradius = 1.2\n")}) {
    const FloquetRun r = floquet(parse_scene(conical_pendulum(held_by)), FloquetRequest{period});
    ASSERT_EQ(r.result.multipliers.size(), 4u) << held_by;
    int unit = 0, turning = 0;
    for (const auto& mu : r.result.multipliers) {
      if (std::abs(mu - 1.0) < 1e-6) {
        ++unit;
      } else {
        ++turning;
        EXPECT_NEAR(std::abs(mu), 1.0, 1e-10) << mu;
        EXPECT_NEAR(std::abs(std::arg(mu)), std::abs(turn), 1e-10) << mu;
      }
    }
    EXPECT_EQ(unit, 2) << held_by;
    EXPECT_EQ(turning, 2) << held_by;
    EXPECT_LT(r.result.closure, 1e-9) << held_by;
  }
}

// The double pendulum as two bobs on links, started in a plane (upper bob
// level with the anchor, lower bob straight above it): 8 exponents on the
// manifold of 2 rows in 6 coordinates, summing to 0 (Hamiltonian: the
// flow keeps volume in canonical coordinates), the largest positive (over
// 20 s the built-in planar double pendulum from θ1 = π/2, θ2 = π gives
// 1.24 1/s, the links 1.25; the scene runs 10 s). One tangent vector along J's direction gives the largest
// exponent of the whole spectrum on a regular motion (the conical
// pendulum), with the rows.
TEST(ParticleTangent, DoublePendulumOnLinksIsChaoticAndKeepsVolume) {
  const Scene scene = load_scene(std::string(LAGRANGIAN_SOURCE_DIR) + "/examples/scenes/double_pendulum_links.toml");
  LyapunovRequest request;
  const LyapunovRun r = lyapunov(scene, request);
  ASSERT_EQ(r.result.spectrum.size(), 8u);
  EXPECT_LT(std::abs(r.result.sum), 1e-8);
  EXPECT_GT(r.result.spectrum[0], 0.5);
  EXPECT_GT(r.result.megno_mean, 4.0);  // chaotic: ⟨Y⟩ grows as λ1 t / 2

  const Scene conical = parse_scene(conical_pendulum(
      "[[links]]\nname = \"rod\"\na = \"bob\"\nanchor = [0.0, 0.0, 0.0]\n"));
  const LyapunovRun one = lyapunov(conical, LyapunovRequest{1, 0.0});
  const LyapunovRun all = lyapunov(conical, LyapunovRequest{});
  ASSERT_EQ(one.result.spectrum.size(), 1u);
  ASSERT_EQ(all.result.spectrum.size(), 4u);
  EXPECT_NEAR(one.result.spectrum[0], all.result.spectrum[0], 1e-6 * (1 + std::abs(all.result.spectrum[0])));
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

/// A body on a spring to an anchor with rest length 0 (a 3-D harmonic
/// oscillator, ω = √(k/m) = 4 rad/s), run to t = 1.3 s.
const char* const kOscillator = R"(
name = "oscillator"
[run]
method = "dopri5"
rtol = 1e-12
atol = 1e-14
t_end = 1.3
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
)";

// A body on a spring to an anchor with rest length 0 (a 3-D harmonic
// oscillator, ω = √(k/m)): over half a period Φ = −I, so all six
// multipliers are −1 (the free flight J = 0 would give +1).
TEST(ParticleTangent, IsotropicOscillatorOverHalfAPeriodHasMultipliersMinusOne) {
  const Scene scene = parse_scene(kOscillator);
  const double omega = std::sqrt(8.0 / 0.5);
  const FloquetRun r = floquet(scene, FloquetRequest{std::acos(-1.0) / omega});
  ASSERT_EQ(r.result.multipliers.size(), 6u);
  for (const auto& mu : r.result.multipliers) EXPECT_LT(std::abs(mu + 1.0), 1e-8) << mu;
  EXPECT_LT((r.result.monodromy + Eigen::MatrixXd::Identity(6, 6)).cwiseAbs().maxCoeff(), 1e-8);
}

// The same oscillator's sensitivities at t = 1.3 s (scene::sensitivity,
// as `lagrangian sensitivity` runs them): per axis Φ = [[cos ωt, sin ωt/ω],
// [−ω sin ωt, cos ωt]], and the columns of its mass and stiffness.
TEST(ParticleTangent, OscillatorSensitivitiesAreTheClosedForm) {
  const Scene scene = parse_scene(kOscillator);
  const SensitivityRun r = sensitivity(scene, SensitivityRequest{});
  ASSERT_EQ(r.model, "particles");
  const double w = std::sqrt(8.0 / 0.5), t = 1.3, c = std::cos(w * t), s = std::sin(w * t);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(6, 6);
  for (int k = 0; k < 3; ++k) {
    expected(k, k) = expected(3 + k, 3 + k) = c;
    expected(k, 3 + k) = s / w;
    expected(3 + k, k) = -w * s;
  }
  EXPECT_LT((r.result.sensitivities.back() - expected).cwiseAbs().maxCoeff(), 1e-9) << r.result.sensitivities.back();
  EXPECT_DOUBLE_EQ(r.result.times.back(), t);
  // The columns of the mass and the stiffness: per axis x(t) = x0 cos ωt +
  // (v0/ω) sin ωt, ω = √(k/m), so ∂x/∂k = (∂x/∂ω)/(2 m ω) and
  // ∂x/∂m = −(∂x/∂ω) ω/(2 m), with ∂x/∂ω = −x0 t sin ωt + v0 (t cos ωt/ω − sin ωt/ω²)
  // and ∂v/∂ω = −x0 (sin ωt + ω t cos ωt) − v0 t sin ωt.
  SensitivityRequest with_mass;
  with_mass.parameters = {"bodies[0].mass", "springs[0].stiffness"};
  with_mass.initial_state = false;
  const SensitivityRun p = sensitivity(scene, with_mass);
  const Eigen::Vector3d x0(0.3, -0.1, 0.2), v0(0.0, 0.4, -0.2);
  Eigen::VectorXd d_omega(6);
  d_omega << -x0 * t * s + v0 * (t * c / w - s / (w * w)), -x0 * (s + w * t * c) - v0 * t * s;
  Eigen::MatrixXd columns(6, 2);
  columns << -d_omega * w / (2 * 0.5), d_omega / (2 * 0.5 * w);
  EXPECT_LT((p.result.sensitivities.back() - columns).cwiseAbs().maxCoeff(), 1e-9) << p.result.sensitivities.back();
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

// A ball dropped on a plane tilted by 0.3 rad (e = 0.5) bounces until the
// Zeno rule lets it rest at t∞ ≈ 1.05 s, then slides down the plane. The
// plane is frictionless, so the motion along it is that of free fall
// projected on it whatever the bounces, and every start comes to rest on
// the plane: at t = 1.6 s the flow's Jacobian is, with P = I − n̂n̂ᵀ,
//   ∂r/∂r0 = P, ∂r/∂v0 = t P, ∂v/∂r0 = 0, ∂v/∂v0 = P
// (the rest removed the normal parts). The tangent run crosses the bounces
// by their saltation matrices and the rest by the plastic impact's.
TEST(ParticleTangent, BallComingToRestOnATiltedPlaneHasTheClosedFormSensitivities) {
  const Scene scene =
      parse_scene(lagrangian_test::precise_scene("ball on an incline", 1.6, lagrangian_test::kBallOnAnIncline));
  const SensitivityRun r = sensitivity(scene, SensitivityRequest{});
  const Eigen::Vector3d n(std::sin(0.3), 0.0, std::cos(0.3));
  const double t = 1.6;
  const Eigen::MatrixXd expected = lagrangian_test::flow_sliding_on_a_plane(n, t);
  const Eigen::Matrix3d p = expected.topLeftCorner(3, 3);  // P = I − n̂n̂ᵀ
  EXPECT_LT((r.result.sensitivities.back() - expected).cwiseAbs().maxCoeff(), 1e-9) << r.result.sensitivities.back();
  EXPECT_DOUBLE_EQ(r.result.times.back(), t);
  EXPECT_GT(r.result.impacts, 10);
  // The state: resting on the plane, sliding down it at g sin α.
  const Eigen::Vector3d rt(r.result.states.back()[0], r.result.states.back()[1], r.result.states.back()[2]);
  const Eigen::Vector3d vt(r.result.states.back()[3], r.result.states.back()[4], r.result.states.back()[5]);
  const Eigen::Vector3d g(0, 0, -9.81), r0(0.2, 0.1, 0.6), v0(0.4, -0.3, 0.0);
  EXPECT_NEAR(n.dot(rt), n.dot(Eigen::Vector3d(0.1, -0.2, 0.03)) + 0.05, 1e-9);
  EXPECT_NEAR(n.dot(vt), 0.0, 1e-9);
  EXPECT_LT((p * (rt - r0 - v0 * t - 0.5 * g * t * t)).norm(), 1e-9);
}

const char* const kBallOnAFloor = R"(
name = "ball on a floor"
[run]
method = "dopri5"
rtol = 1e-12
atol = 1e-14
t_end = 5.0
[[bodies]]
name = "ball"
mass = 0.2
radius = 0.05
position = [0.3, -0.1, 1.0]
velocity = [0.5, 0.2, 0.0]
[gravity]
[[contacts.planes]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
restitution = 0.8
)";

// The same ball on a level floor (e = 0.8), at rest from t∞ = 3.96 s:
// along x and y it flies freely, Φ = [[1, t/m], [0, 1]] in (q, p) on the
// canonical start vectors δx, δy, δp_x, δp_y, whose Benettin factors are
// exactly 1 (exponents 0); δz and δp_z are what the rest removes (−∞, as
// the sum). Asked for three exponents, the third vector is δz: refused.
TEST(ParticleTangent, RestOnAFloorRemovesTwoDirectionsOfTheSpectrum) {
  const Scene scene = parse_scene(kBallOnAFloor);
  const LyapunovRun all = lyapunov(scene, LyapunovRequest{});
  ASSERT_EQ(all.result.spectrum.size(), 6u);
  for (int i = 0; i < 4; ++i) EXPECT_LT(std::abs(all.result.spectrum[static_cast<std::size_t>(i)]), 1e-12) << i;
  for (int i = 4; i < 6; ++i) EXPECT_EQ(all.result.spectrum[static_cast<std::size_t>(i)], -HUGE_VAL) << i;
  EXPECT_EQ(all.result.sum, -HUGE_VAL);
  EXPECT_EQ(all.result.rests, 1);
  EXPECT_EQ(all.result.releases, 0);
  EXPECT_GT(all.result.impacts, 20);
  EXPECT_NEAR(all.result.q_final[2], 0.05, 1e-12);
  const LyapunovRun one = lyapunov(scene, LyapunovRequest{1, 0.0});
  EXPECT_LT(std::abs(one.result.spectrum[0]), 1e-12);
  try {
    lyapunov(scene, LyapunovRequest{3, 0.0});
    ADD_FAILURE() << "three exponents were reported through the rest";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("the rest of contact 'ball-floor' removes the direction of tangent vector 3"),
              std::string::npos)
        << e.what();
  }
}

/// The ball on a floor with a wall through (2.5, 0, 0) of the given normal
/// (TOML array), e_w = 0.9.
Scene ball_on_a_floor_and_a_wall(const std::string& normal) {
  return parse_scene(std::string(kBallOnAFloor) + "[[contacts.planes]]\nname = \"wall\"\npoint = [2.5, 0.0, 0.0]\n" +
                     "normal = " + normal + "\nrestitution = 0.9\n");
}

/// Φ and the columns of the wall's restitution and of its point's x.
SensitivityRun wall_columns(const Scene& scene) {
  SensitivityRequest request;
  request.parameters = {"contacts.planes[1].restitution", "contacts.planes[1].point[0]"};
  return sensitivity(scene, request);
}

// Resting on the floor from 3.96 s, the ball slides into a wall at
// x = 2.5 m (e_w = 0.9) at 4.3 s: the wall's impulse is orthogonal to the
// floor's, so the ball stays at rest on the floor and the impact is crossed
// with it held. Along x, x(t) = W (1 + e_w) − e_w x0 − e_w ẋ0 t after the
// impact (W = 2.5 − R the wall's reach), ẋ = −e_w ẋ0; along y free flight;
// z and ż held: at 5 s
//   ∂x/∂x0 = −e_w, ∂x/∂ẋ0 = −e_w t, ∂ẋ/∂ẋ0 = −e_w, ∂y/∂y0 = ∂ẏ/∂ẏ0 = 1, ∂y/∂ẏ0 = t,
// the rows of z and ż 0; the column of e_w is (W − x0 − ẋ0 t, 0, 0, −ẋ0, 0, 0)
// and that of the wall's point (1 + e_w)(1, 0, 0, 0, 0, 0).
TEST(ParticleTangent, BallRestingOnAFloorBouncesOffAWallAsTheClosedForm) {
  const Scene scene = ball_on_a_floor_and_a_wall("[-1.0, 0.0, 0.0]");
  const SensitivityRun r = wall_columns(scene);
  const double t = 5.0, e = 0.9, w = 2.45, x0 = 0.3, v0 = 0.5;
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(6, 8);
  expected(0, 0) = -e;
  expected(0, 3) = -e * t;
  expected(3, 3) = -e;
  expected(1, 1) = expected(4, 4) = 1.0;
  expected(1, 4) = t;
  expected(0, 6) = w - x0 - v0 * t;
  expected(3, 6) = -v0;
  expected(0, 7) = 1.0 + e;
  const Eigen::MatrixXd& phi = r.result.sensitivities.back();
  EXPECT_LT((phi - expected).cwiseAbs().maxCoeff(), 1e-9) << phi;
  const Eigen::VectorXd& x = r.result.states.back();
  EXPECT_NEAR(x[0], w * (1 + e) - e * x0 - e * v0 * t, 1e-9);
  EXPECT_NEAR(x[2], 0.05, 1e-12);
  const LyapunovRun l = lyapunov(scene, LyapunovRequest{1, 0.0});
  EXPECT_EQ(l.result.rests, 1);
  EXPECT_EQ(l.result.releases, 0);
  EXPECT_GT(l.result.impacts, 20);
}

// The same ball into a wall leaning back (normal n = (−1, 0, 0.3)/√1.09
// through (2.5, 0, 0), e_w = 0.9), reached at rest on the floor (z = R)
// where x = x_w = 2.5 + 0.3 R − R √1.09. Newton's law of the wall alone,
// v⁺ = v − (1 + e_w)(n·v) n, gives ẋ⁺ = c ẋ0 with c = 1 − (1 + e_w)/1.09
// and ż⁺ = 0.3 (1 + e_w) ẋ0 / 1.09 = 0.26 m/s: the impulse lifts the ball
// off the floor, which a plain run releases at the impact and the tangent
// run too; it bounces back to rest within 0.3 s. Along x,
// x(t) = x_w + c ẋ0 t − c (x_w − x0) after the impact, so at 5 s
//   ∂x/∂x0 = c, ∂x/∂ẋ0 = c t, ∂ẋ/∂ẋ0 = c, ∂y/∂y0 = ∂ẏ/∂ẏ0 = 1, ∂y/∂ẏ0 = t,
// the rows of z and ż 0; the column of e_w is −(x0 + ẋ0 t − x_w, 0, 0,
// ẋ0, 0, 0)/1.09 and that of the wall's point (1 − c)(1, 0, 0, 0, 0, 0).
TEST(ParticleTangent, BallLiftedOffAFloorByAWallAsTheClosedForm) {
  const Scene scene = ball_on_a_floor_and_a_wall("[-1.0, 0.0, 0.3]");
  const SensitivityRun r = wall_columns(scene);
  const double t = 5.0, c = 1 - 1.9 / 1.09, x0 = 0.3, v0 = 0.5, xw = 2.5 + 0.3 * 0.05 - 0.05 * std::sqrt(1.09);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(6, 8);
  expected(0, 0) = c;
  expected(0, 3) = c * t;
  expected(3, 3) = c;
  expected(1, 1) = expected(4, 4) = 1.0;
  expected(1, 4) = t;
  expected(0, 6) = -(x0 + v0 * t - xw) / 1.09;
  expected(3, 6) = -v0 / 1.09;
  expected(0, 7) = 1.0 - c;
  const Eigen::MatrixXd& phi = r.result.sensitivities.back();
  EXPECT_LT((phi - expected).cwiseAbs().maxCoeff(), 1e-9) << phi;
  const Eigen::VectorXd& x = r.result.states.back();
  EXPECT_NEAR(x[0], xw + c * v0 * t - c * (xw - x0), 1e-9);
  EXPECT_NEAR(x[2], 0.05, 1e-12);
  const LyapunovRun l = lyapunov(scene, LyapunovRequest{});
  EXPECT_EQ(l.result.rests, 2);
  EXPECT_EQ(l.result.releases, 1);
}

// Resting on the incline (particle_scenes.hpp), the ball slides down (to
// +x) into a wall at x = 4 m whose normal is not orthogonal to the
// incline's: the wall's impulse presses the ball into the incline (a plain
// run releases the resting contact and resolves it as an impact at the same
// instant), which the tangent flow does not derive: the run stops there,
// naming both contacts.
TEST(ParticleTangent, ImpulseThatMovesARestingContactIsRefused) {
  const std::string tables = std::string(lagrangian_test::kBallOnAnIncline) + R"(
[[contacts.planes]]
name = "wall"
point = [4.0, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
restitution = 0.5
)";
  const Scene scene = parse_scene(lagrangian_test::precise_scene("incline and wall", 3.0, tables));
  try {
    lyapunov(scene, LyapunovRequest{});
    ADD_FAILURE() << "an impact that moves a resting contact was crossed";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("the impulse of contact 'ball-wall' sets resting contact 'ball-incline' "
                                         "moving"),
              std::string::npos)
        << e.what();
    EXPECT_GT(e.time(), 1.1);
  }
}

// A ball on a spring (k = 20 N/m, rest length 0.5 m, anchored 1 m above the
// floor) dropped with e = 0: where it lands at x = 0.1 m the spring's upward
// pull is below m g, so it rests and slides out along the floor until the
// pull exceeds m g at x ≈ 0.63 m, where its multiplier falls through 0: it
// lifts off at 0.51 s and is in the air at 1 s. Started further out it lands
// at 0.76 m, where the pull already exceeds m g: a plastic impact straight
// into flight (a plain run rests and lifts off at one instant), then a
// second landing at 0.99 s nearer the anchor, at rest at 1 s. The flow's
// Jacobian across all of it against central differences of plain runs (step
// 1e-6: error ~1e-9 of its entries).
TEST(ParticleTangent, BallLiftingOffAFloorMatchesCentralDifferencesOfPlainRuns) {
  struct Case {
    const char* start;
    int rests, releases;
    bool flying;
  };
  for (const Case& c : {Case{"position = [-0.5, 0.05, 0.3]\nvelocity = [2.0, 0.4, 0.0]", 1, 1, true},
                        Case{"position = [0.0, 0.05, 0.3]\nvelocity = [2.5, 0.4, 0.0]", 1, 0, false}}) {
    const Scene scene = parse_scene(std::string(R"(
name = "ball on a spring"
[run]
method = "dopri5"
rtol = 1e-12
atol = 1e-14
t_end = 1.0
[[bodies]]
name = "ball"
mass = 1.0
radius = 0.1
)") + c.start + R"(
[gravity]
[[springs]]
a = "ball"
anchor = [0.0, 0.0, 1.0]
stiffness = 20.0
rest_length = 0.5
[[contacts.planes]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
restitution = 0.0
)");
    const SensitivityRun r = sensitivity(scene, SensitivityRequest{});
    const LyapunovRun l = lyapunov(scene, LyapunovRequest{1, 0.0});
    EXPECT_EQ(l.result.rests, c.rests) << c.start;
    EXPECT_EQ(l.result.releases, c.releases) << c.start;
    EXPECT_EQ(l.result.q_final[2] > 0.1 + 1e-3, c.flying) << c.start;
    const Eigen::MatrixXd& phi = r.result.sensitivities.back();
    RunControls quiet;
    quiet.write_outputs = false;
    const auto end_state = [&](int which, double shift) {
      Scene s = scene;
      auto& body = s.bodies.front();
      (which < 3 ? body.position : body.velocity)[which % 3] += shift;
      const RunResult run_result = run(s, quiet);
      Eigen::VectorXd x(6);
      for (int i = 0; i < 3; ++i) {
        x[i] = run_result.q_final[static_cast<std::size_t>(i)];
        x[3 + i] = run_result.qd_final[static_cast<std::size_t>(i)];
      }
      return x;
    };
    const double h = 1e-6;
    double worst = 0;
    for (int j = 0; j < 6; ++j) {
      const Eigen::VectorXd column = (end_state(j, h) - end_state(j, -h)) / (2 * h);
      worst = std::max(worst, (column - phi.col(j)).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst, 1e-6 * phi.cwiseAbs().maxCoeff()) << c.start << "\n" << phi;
  }
}

}  // namespace
