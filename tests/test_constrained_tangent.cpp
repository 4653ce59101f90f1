// The tangent flow of models with holonomic and Pfaffian constraints
// (analysis/tangent_flow.hpp, analysis/detail/tangent_solve.hpp) and the
// Lyapunov exponents on the constraint manifold (analysis/lyapunov.hpp):
// against a closed-form Jacobian (the knife edge), the same system in other
// coordinates (the double pendulum in angles and in Cartesian coordinates
// with two rods), the closed-form flow of a bead on a spinning wire, the
// sensitivities on the manifold (the Atwood machine's closed form; the two
// double pendulums), parameter columns through the energies and through the
// rows (the Atwood machine's masses and g, an incline's slope, the spinning
// wire's rate from the axis; the Cartesian double pendulum and the particle
// on a sphere against their angle models; a free knife edge's mass and
// inertia), the periodic-orbit search's energy row under constraint
// forces, and impacts under holonomic rows (a rod pendulum against a wall:
// the exponents' sum in closed form; the Cartesian double pendulum against
// a wall: the angle model's Φ).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <Eigen/LU>

#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/saltation.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/mechanics/constrained_accelerations.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "contact_models.hpp"
#include "jet_jacobian.hpp"
#include "tangent_options.hpp"

namespace {

using lagrangian::Vec;
namespace lm = lagrangian::models;

// The knife edge, M = diag(m, m, I), no sideslip φ = ẋ sin ϕ − ẏ cos ϕ = 0
// (ϕ the heading). C = (sin ϕ, −cos ϕ, 0), γ = (ẋ cos ϕ + ẏ sin ϕ) ϕ̇ = u ϕ̇,
// so M q̈ = Cᵀλ with C q̈ = −γ gives λ = −m u ϕ̇ and
//   q̈ = −u ϕ̇ (sin ϕ, −cos ϕ, 0),   u = ẋ cos ϕ + ẏ sin ϕ,
// at every state, on the constraint or off it. Its derivatives, by hand:
TEST(ConstrainedTangent, KnifeEdgeJacobianIsTheClosedForm) {
  const lm::KnifeEdge knife(1.7, 0.3);
  for (const auto& [phi, xd, yd, phid] : {std::array<double, 4>{0.3, 1.2, -0.4, 0.9},
                                           std::array<double, 4>{2.1, -0.5, 0.8, -1.3},
                                           std::array<double, 4>{-1.0, 0.6 * std::cos(-1.0), 0.6 * std::sin(-1.0), 2.0}}) {
    const Vec<double, 3> q(0.4, -0.2, phi), qd(xd, yd, phid);
    Vec<double, 3> qdd;
    Eigen::Matrix<double, 3, 6> jac;
    lagrangian::state_jacobian(knife, q, qd, 0.0, qdd, jac);
    const double s = std::sin(phi), c = std::cos(phi);
    const double u = xd * c + yd * s, du_dphi = -xd * s + yd * c;
    EXPECT_NEAR(qdd[0], -u * phid * s, 1e-14);
    EXPECT_NEAR(qdd[1], u * phid * c, 1e-14);
    EXPECT_NEAR(qdd[2], 0.0, 1e-14);
    const Vec<double, 3> library = lagrangian::constrained_accelerations(knife, q, qd, 0.0);
    EXPECT_LE((qdd - library).norm(), 1e-14);
    Eigen::Matrix<double, 3, 6> expected = Eigen::Matrix<double, 3, 6>::Zero();
    expected(0, 2) = -phid * (du_dphi * s + u * c);
    expected(0, 3) = -phid * c * s;
    expected(0, 4) = -phid * s * s;
    expected(0, 5) = -u * s;
    expected(1, 2) = phid * (du_dphi * c - u * s);
    expected(1, 3) = phid * c * c;
    expected(1, 4) = phid * s * c;
    expected(1, 5) = u * c;
    EXPECT_LE((jac - expected).norm(), 1e-13) << "AD:\n" << jac << "\nclosed form:\n" << expected;
  }
}

// The double pendulum in angles x = (θ, θ̇) and in Cartesian coordinates
// X = ψ(x) = (r1, r2, ṙ1, ṙ2), r1 = l1 (sin θ1, −cos θ1),
// r2 = r1 + l2 (sin θ2, −cos θ2), with the rods as holonomic constraints.
template <class S>
Eigen::Matrix<S, 8, 1> to_cartesian(const Eigen::Matrix<S, 4, 1>& x, double l1, double l2) {
  using std::cos;
  using std::sin;
  Eigen::Matrix<S, 8, 1> y;
  y[0] = l1 * sin(x[0]);
  y[1] = -l1 * cos(x[0]);
  y[2] = y[0] + l2 * sin(x[1]);
  y[3] = y[1] - l2 * cos(x[1]);
  y[4] = l1 * cos(x[0]) * x[2];
  y[5] = l1 * sin(x[0]) * x[2];
  y[6] = y[4] + l2 * cos(x[1]) * x[3];
  y[7] = y[5] + l2 * sin(x[1]) * x[3];
  return y;
}

// The two flows are one: ψ(φ_a(t, x)) = φ_c(t, ψ(x)). Differentiating
// along δ and then in t at t = 0:
//   J_c(ψ(x)) Dψ(x) δ = D²ψ(x)[f_a(x), δ] + Dψ(x) J_a(x) δ,
// and f_c(ψ(x)) = Dψ(x) f_a(x): the constrained model's J on tangent
// vectors of its manifold against the angle model's J, to rounding.
// Dψ and D²ψ by a second-order Jet along (f_a, δ).
TEST(ConstrainedTangent, CartesianDoublePendulumIsTheAngleModel) {
  const double m1 = 1.3, m2 = 0.7, l1 = 1.0, l2 = 0.8, g = 9.81;
  const lm::DoublePendulum angles(m1, m2, l1, l2, g);
  const lm::CartesianDoublePendulum cartesian(m1, m2, l1, l2, g);
  for (const auto& x : {Eigen::Vector4d(2.0, 2.0, 0.0, 0.0), Eigen::Vector4d(0.4, -1.1, 1.7, -0.6),
                        Eigen::Vector4d(-2.5, 0.9, -3.0, 4.2)}) {
    Vec<double, 2> qdd_a;
    Eigen::Matrix<double, 2, 4> j_a;
    lagrangian::state_jacobian(angles, Vec<double, 2>(x.head<2>()), Vec<double, 2>(x.tail<2>()), 0.0, qdd_a, j_a);
    Eigen::Matrix4d full_a = Eigen::Matrix4d::Zero();
    full_a.topRightCorner<2, 2>().setIdentity();
    full_a.bottomRows<2>() = j_a;
    const Eigen::Vector4d f_a(x[2], x[3], qdd_a[0], qdd_a[1]);

    const Eigen::Matrix<double, 8, 1> big = to_cartesian(x, l1, l2);
    const Vec<double, 4> q_c = big.head<4>(), qd_c = big.tail<4>();
    Vec<double, 4> qdd_c;
    Eigen::Matrix<double, 4, 8> j_c;
    lagrangian::state_jacobian(cartesian, q_c, qd_c, 0.0, qdd_c, j_c);
    const double scale = 1.0 + j_c.norm();
    for (int d = 0; d < 4; ++d) {
      using J = lagrangian::ad::Jet<double, 2, 2>;
      Eigen::Matrix<J, 4, 1> xs;
      for (int k = 0; k < 4; ++k) {
        xs[k] = J(x[k]);
        xs[k].g[0] = f_a[k];
        xs[k].g[1] = d == k ? 1.0 : 0.0;
      }
      const Eigen::Matrix<J, 8, 1> y = to_cartesian(xs, l1, l2);
      Eigen::Matrix<double, 8, 1> dpsi_f, dpsi_delta, second;
      for (int i = 0; i < 8; ++i) {
        dpsi_f[i] = y[i].g[0];
        dpsi_delta[i] = y[i].g[1];
        second[i] = y[i].hess(0, 1);
      }
      // Dψ (J_a δ): Dψ along the vector J_a δ, by a first-order Jet.
      Eigen::Matrix<double, 8, 1> dpsi_j_delta;
      {
        using J1 = lagrangian::ad::Jet<double, 1, 1>;
        const Eigen::Vector4d direction = full_a.col(d);
        Eigen::Matrix<J1, 4, 1> x1;
        for (int k = 0; k < 4; ++k) {
          x1[k] = J1(x[k]);
          x1[k].g[0] = direction[k];
        }
        const Eigen::Matrix<J1, 8, 1> y1 = to_cartesian(x1, l1, l2);
        for (int i = 0; i < 8; ++i) dpsi_j_delta[i] = y1[i].g[0];
      }
      const Eigen::Matrix<double, 8, 1> expected = second + dpsi_j_delta;
      // J_c Dψ δ: the bottom rows (the top ones are the identity's).
      const Eigen::Matrix<double, 4, 1> got = j_c * dpsi_delta;
      EXPECT_LE((got - expected.tail<4>()).norm(), 1e-12 * scale)
          << "direction " << d << " at " << x.transpose() << "\nJ_c Dpsi d: " << got.transpose()
          << "\nexpected:   " << expected.tail<4>().transpose();
      EXPECT_LE((dpsi_delta.tail<4>() - expected.head<4>()).norm(), 1e-12 * scale);
      if (d == 0) {
        EXPECT_LE((qdd_c - dpsi_f.tail<4>()).norm(), 1e-12 * (1 + qdd_c.norm()));
      }
    }
  }
}

lagrangian::LyapunovOptions options(double t_end, double rtol = 1e-11) {
  return lagrangian_test::lyapunov_options(t_end, rtol);
}

// A bead on a horizontal wire spinning at ω: in the wire's frame r̈ = ω² r,
// so the flow on the manifold (dimension 2: r, ṙ) is
//   [[cosh ωt, sinh ωt / ω], [ω sinh ωt, cosh ωt]],  det = 1.
// In the reduced canonical coordinates (Uᵀδq, Uᵀδp), U = e_r the wire's
// direction, a tangent vector (δr, δṙ) is (δr, m δṙ): areas in them are m
// times areas in (r, ṙ), so the two exponents sum to 0 at every time. The
// first tangent vector grows as a e^{ωT} + b e^{−ωT}:
// T λ₁(T) = ωT + log|a| + O(e^{−2ωT}), so the growth of T λ₁ between T₁ and
// T₂ is ω (T₂ − T₁). (The bead would leave the wire's end, L = 10 m, at
// 4.9 s: the exponents are those of the equations of motion, which go on.)
TEST(ConstrainedLyapunov, BeadOnASpinningWireClosedForm) {
  const double omega = 1.0;
  const lm::BeadOnRotatingWire bead(0.8, omega, 10.0);
  lagrangian::State<2> s;
  s.q = Vec<double, 2>(0.1, 0.0);
  s.qd = Vec<double, 2>(0.05, omega * 0.1);  // ġ = ẋ sin ωt − ẏ cos ωt + ω x cos ωt + ω y sin ωt = 0 at t = 0
  const double t1 = 10, t2 = 20;
  const lagrangian::LyapunovResult a = lagrangian::lyapunov_spectrum(bead, s, options(t1));
  const lagrangian::LyapunovResult b = lagrangian::lyapunov_spectrum(bead, s, options(t2));
  ASSERT_EQ(a.spectrum.size(), 2u);
  ASSERT_EQ(b.spectrum.size(), 2u);
  EXPECT_NEAR(a.sum, 0.0, 1e-8);
  EXPECT_NEAR(b.sum, 0.0, 1e-8);
  EXPECT_NEAR((t2 * b.spectrum[0] - t1 * a.spectrum[0]) / (t2 - t1), omega, 1e-6)
      << a.spectrum[0] << " " << b.spectrum[0];
  EXPECT_NEAR((t2 * b.spectrum[1] - t1 * a.spectrum[1]) / (t2 - t1), -omega, 1e-6);
  // The state stays on the wire: r(T) = r0 cosh ωT + (ṙ0/ω) sinh ωT.
  const double r = 0.1 * std::cosh(omega * t2) + 0.05 / omega * std::sinh(omega * t2);
  EXPECT_NEAR(std::hypot(b.q_final[0], b.q_final[1]) / r, 1.0, 1e-8);
  EXPECT_NEAR(std::atan2(b.q_final[1], b.q_final[0]), std::remainder(omega * t2, 2 * M_PI), 1e-8);
  // The largest exponent alone (one tangent vector, J along it) is the same.
  lagrangian::LyapunovOptions one = options(t2);
  one.exponents = 1;
  const lagrangian::LyapunovResult c = lagrangian::lyapunov_spectrum(bead, s, one);
  EXPECT_NEAR(c.spectrum[0], b.spectrum[0], 1e-9);
}

// The chaotic double pendulum (θ1 = θ2 = 2 rad from rest) in both
// formulations over 10 s: the same motion, whose tangent flows map into
// each other by Dψ (checked state by state above). The two runs measure a tangent vector in different
// Darboux coordinates ((δθ, δp_θ) and (Uᵀδq, Uᵀδp)), related by a
// symplectic map that changes lengths by a bounded factor κ (and they start
// from different first vectors), so their finite-time exponents differ by
// O(log κ / T): the largest ones agree to 0.25 1/s over 10 s (measured:
// 0.12), both well above the 0.5 1/s of chaos; each spectrum sums to 0.
TEST(ConstrainedLyapunov, CartesianDoublePendulumAgreesWithAngles) {
  const double m1 = 1.0, m2 = 1.0, l1 = 1.0, l2 = 1.0, g = 9.81;
  const lm::DoublePendulum angles(m1, m2, l1, l2, g);
  const lm::CartesianDoublePendulum cartesian(m1, m2, l1, l2, g);
  lagrangian::State<2> sa;
  sa.q = Vec<double, 2>(2.0, 2.0);
  sa.qd.setZero();
  const Eigen::Matrix<double, 8, 1> big = to_cartesian(Eigen::Vector4d(2.0, 2.0, 0.0, 0.0), l1, l2);
  lagrangian::State<4> sc;
  sc.q = big.head<4>();
  sc.qd = big.tail<4>();
  const double t_end = 10;
  const lagrangian::LyapunovResult a = lagrangian::lyapunov_spectrum(angles, sa, options(t_end));
  const lagrangian::LyapunovResult c = lagrangian::lyapunov_spectrum(cartesian, sc, options(t_end));
  ASSERT_EQ(c.spectrum.size(), 4u);
  EXPECT_GT(a.spectrum[0], 0.5);
  EXPECT_GT(c.spectrum[0], 0.5);
  EXPECT_NEAR(c.spectrum[0], a.spectrum[0], 0.25) << "angles " << a.spectrum[0] << ", Cartesian " << c.spectrum[0];
  // The same final state, mapped.
  const Eigen::Matrix<double, 8, 1> end =
      to_cartesian(Eigen::Vector4d(a.q_final[0], a.q_final[1], a.qd_final[0], a.qd_final[1]), l1, l2);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(c.q_final[static_cast<std::size_t>(i)], end[i], 1e-5);
    EXPECT_NEAR(c.qd_final[static_cast<std::size_t>(i)], end[4 + i], 1e-4);
  }
  // Measured in the reduced canonical coordinates (Uᵀ δq, Uᵀ δp), volumes
  // are phase-space volumes, which the constrained Hamiltonian flow keeps:
  // the spectrum sums to 0 at every time, as the angle model's does.
  EXPECT_NEAR(c.sum, 0.0, 1e-8);
  EXPECT_NEAR(a.sum, 0.0, 1e-8);
}

// The knife edge (Pfaffian: no sideslip), 1 m/s turning at 0.5 rad/s. On
// the manifold, in (x, y, ϕ, v, ω) with v the speed and ω = ϕ̇, the motion
// is ẋ = v cos ϕ, ẏ = v sin ϕ, ϕ̇ = ω, v̇ = ω̇ = 0: divergence-free, so it
// keeps dx dy dϕ dv dω; the reduced coordinates (δq, δp) of that basis'
// tangent vectors have a constant Gram determinant ((1 + m²v²) m² I²), so
// the five exponents sum to 0 at every time. A change of ω or v shifts the
// phase along a circle: tangent vectors grow polynomially (linearly), not
// exponentially, so every |T λ_j(T)| stays below 2 log(T / 1 s) (quadratic
// growth), where an exponent λ would give λ T.
TEST(ConstrainedLyapunov, KnifeEdgeHasFiveExponentsThatVanish) {
  const lm::KnifeEdge knife(1.0, 0.1);
  lagrangian::State<3> s;
  s.q.setZero();
  s.qd = Vec<double, 3>(1.0, 0.0, 0.5);
  const lagrangian::LyapunovResult a = lagrangian::lyapunov_spectrum(knife, s, options(50.0));
  const lagrangian::LyapunovResult b = lagrangian::lyapunov_spectrum(knife, s, options(200.0));
  ASSERT_EQ(a.spectrum.size(), 5u);
  EXPECT_NEAR(a.sum, 0.0, 1e-8);
  EXPECT_NEAR(b.sum, 0.0, 1e-8);
  EXPECT_GT(b.spectrum[0], 0.0);
  for (double l : a.spectrum) EXPECT_LE(50.0 * std::abs(l), 2 * std::log(50.0));
  for (double l : b.spectrum) EXPECT_LE(200.0 * std::abs(l), 2 * std::log(200.0));
  // The speed is kept: the state stays on the no-sideslip manifold.
  EXPECT_NEAR(std::hypot(b.qd_final[0], b.qd_final[1]), 1.0, 1e-9);
  EXPECT_NEAR(b.qd_final[0] * std::sin(b.q_final[2]) - b.qd_final[1] * std::cos(b.q_final[2]), 0.0, 1e-9);
}

TEST(ConstrainedLyapunov, RefusalsSayWhy) {
  const lm::CartesianPendulum pendulum;
  lagrangian::State<2> s;
  s.q = Vec<double, 2>(std::sin(0.5), -std::cos(0.5));
  s.qd.setZero();
  // More exponents than the manifold has dimensions (2: one degree of freedom).
  lagrangian::LyapunovOptions o = options(1.0);
  o.exponents = 3;
  try {
    lagrangian::lyapunov_spectrum(pendulum, s, o);
    FAIL() << "3 exponents of a 2-dimensional manifold were computed";
  } catch (const lagrangian::OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("exponents = 3 is outside [0, 2] (0 asks for all 2, the dimension of the "
                                         "constraint manifold's tangent space)"),
              std::string::npos)
        << e.what();
  }
  // A start off the rod.
  lagrangian::State<2> off = s;
  off.q *= 1.01;
  try {
    lagrangian::lyapunov_spectrum(pendulum, off, options(1.0));
    FAIL() << "a start off the constraint was taken";
  } catch (const lagrangian::ConstraintError& e) {
    EXPECT_NE(std::string(e.what()).find("the initial state violates constraint rod (0.01)"), std::string::npos)
        << e.what();
  }
  lagrangian::SensitivityOptions so;
  so.run.t_end = 1.0;
  try {
    lagrangian::sensitivities(pendulum, off, so);
    FAIL() << "sensitivities from a start off the constraint were computed";
  } catch (const lagrangian::ConstraintError& e) {
    EXPECT_NE(std::string(e.what()).find("the initial state violates constraint rod (0.01)"), std::string::npos)
        << e.what();
  }
}

// Refusals that need no model: a TangentModel (one coordinate) whose
// manifold rows h = (g, ġ) have the Jacobian `rank` rows of the identity
// (rank 2: a coordinate pinned by a rheonomic row g = x − A sin ωt, whose
// ġ fixes ẋ too; rank 1: one row). Nothing is integrated.
template <int rank>
void pinned_rows(const void*, const double*, const double*, double, double* residual, double* jacobian) {
  residual[0] = residual[1] = 0;
  jacobian[0] = 1, jacobian[1] = 0, jacobian[2] = 0, jacobian[3] = rank == 2 ? 1 : 0;  // 2 × 2, column-major
}

lagrangian::detail::TangentModel pinned(int rank) {
  lagrangian::detail::TangentModel tm;
  tm.n = 1;
  tm.manifold = 2;
  tm.manifold_holonomic = 1;
  tm.manifold_names = {"pin", "pin (rate)"};
  tm.manifold_rows = rank == 2 ? &pinned_rows<2> : &pinned_rows<1>;
  return tm;
}

TEST(ConstrainedSensitivity, RefusalsSayWhy) {
  const double q = 0, qd = 0;
  lagrangian::SensitivityOptions o;
  o.run.t_end = 1.0;
  try {
    lagrangian::detail::sensitivities(pinned(2), &q, &qd, {}, {}, o);
    FAIL() << "the sensitivities of a motion the constraints fix were computed";
  } catch (const lagrangian::AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("sensitivity: the constraints leave no motion (the constraint manifold's "
                                         "tangent space has dimension 0)"),
              std::string::npos)
        << e.what();
  }
  try {
    lagrangian::detail::sensitivities(pinned(1), &q, &qd, {0}, {"A"}, o);
    FAIL() << "a parameter column of a model without the rows' derivative along it was computed";
  } catch (const lagrangian::AnalysisError& e) {
    EXPECT_EQ(std::string(e.what()),
              "sensitivity: the model gives no derivative of its constraint rows along a parameter ('A'); ask for "
              "the initial state's columns only");
  }
}

// The Atwood machine (y1 + y2 = c) falls with the constant acceleration
// a = −(m1 − m2) g / (m1 + m2) of the first mass, so along any perturbation
// that keeps the string's length and rate (δy1 + δy2 = 0, δẏ1 + δẏ2 = 0)
//   δy(t) = δy(0) + t δẏ(0),  δẏ(t) = δẏ(0).
// The sensitivities on the manifold are Φ(t) P0, P0 the orthogonal
// projector on those perturbations, blockdiag(P, P) with
// P = ½ [[1, −1], [−1, 1]]: [[P, t P], [0, P]] at every sample.
TEST(ConstrainedSensitivity, AtwoodMachineClosedForm) {
  const lm::AtwoodMachine atwood(3.0, 1.0, 9.81, 0.0, 1.0);
  lagrangian::State<2> s;
  s.q = Vec<double, 2>(0.2, -0.2);
  s.qd = Vec<double, 2>(0.3, -0.3);
  lagrangian::SensitivityOptions o;
  o.run = lagrangian_test::lyapunov_options(0.5, 1e-12).run;
  o.run.output_interval = 0.125;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(atwood, s, o);
  ASSERT_EQ(r.times.size(), 5u);
  EXPECT_EQ(r.state_columns, 4);
  Eigen::Matrix2d p;
  p << 0.5, -0.5, -0.5, 0.5;
  for (std::size_t i = 0; i < r.times.size(); ++i) {
    const double t = r.times[i];
    Eigen::Matrix4d expected = Eigen::Matrix4d::Zero();
    expected.topLeftCorner<2, 2>() = p;
    expected.topRightCorner<2, 2>() = t * p;
    expected.bottomRightCorner<2, 2>() = p;
    ASSERT_EQ(r.sensitivities[i].rows(), 4);
    ASSERT_EQ(r.sensitivities[i].cols(), 4);
    EXPECT_LE((r.sensitivities[i] - expected).norm(), 1e-10) << "t = " << t << "\n" << r.sensitivities[i];
  }
  // The state: y1(t) = y1(0) + ẏ1(0) t + ½ a t².
  const double a = -(3.0 - 1.0) * 9.81 / 4.0, t = r.times.back();
  EXPECT_NEAR(r.states.back()[0], 0.2 + 0.3 * t + 0.5 * a * t * t, 1e-10);
  EXPECT_NEAR(r.states.back()[0] + r.states.back()[1], 0.0, 1e-10);
}

// The Atwood machine's parameter columns. y1(t) = y1(0) + ẏ1(0) t + ½ a t²
// with a = −(m1 − m2) g / (m1 + m2) and y2 = c − y1, so
//   ∂y1/∂p = ½ t² ∂a/∂p,  ∂ẏ1/∂p = t ∂a/∂p,  ∂y2/∂p = −∂y1/∂p,
//   ∂a/∂m1 = −2 m2 g/(m1 + m2)²,  ∂a/∂m2 = 2 m1 g/(m1 + m2)²,
//   ∂a/∂g = −(m1 − m2)/(m1 + m2),
// and the pulley's height d enters no energy and no row: its column is 0.
// The string's constant c moves the manifold past the start (∂g/∂c = −1):
// refused, naming it.
TEST(ConstrainedSensitivity, AtwoodMachineParametersClosedForm) {
  const double m1 = 3.0, m2 = 1.0, g = 9.81;
  const lm::AtwoodMachine atwood(m1, m2, g, 0.0, 1.0);
  lagrangian::State<2> s;
  s.q = Vec<double, 2>(0.2, -0.2);
  s.qd = Vec<double, 2>(0.3, -0.3);
  lagrangian::SensitivityOptions o;
  o.run = lagrangian_test::lyapunov_options(0.5, 1e-12).run;
  o.run.output_interval = 0.25;
  o.parameters = {"m1", "m2", "g", "d"};
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(atwood, s, o);
  ASSERT_EQ(r.times.size(), 3u);
  ASSERT_EQ(r.parameters, (std::vector<std::string>{"m1", "m2", "g", "d"}));
  const double sum = m1 + m2;
  const double da[4] = {-2 * m2 * g / (sum * sum), 2 * m1 * g / (sum * sum), -(m1 - m2) / sum, 0.0};
  double worst = 0;
  for (std::size_t i = 0; i < r.times.size(); ++i) {
    const double t = r.times[i];
    ASSERT_EQ(r.sensitivities[i].cols(), 4 + 4);
    for (int j = 0; j < 4; ++j) {
      Eigen::Vector4d expected(0.5 * t * t * da[j], -0.5 * t * t * da[j], t * da[j], -t * da[j]);
      worst = std::max(worst, (r.sensitivities[i].col(4 + j) - expected).norm());
      EXPECT_LE((r.sensitivities[i].col(4 + j) - expected).norm(), 1e-10)
          << "d/d" << r.parameters[static_cast<std::size_t>(j)] << " at t = " << t << "\n"
          << r.sensitivities[i].col(4 + j).transpose();
    }
  }
  std::printf("Atwood machine, columns of m1, m2, g, d against the closed form: %.1e\n", worst);
  EXPECT_GT(r.sensitivities.back().col(4).norm(), 0.1);
  o.parameters = {"c"};
  try {
    lagrangian::sensitivities(atwood, s, o);
    FAIL() << "a parameter that moves the string's manifold past the start was taken";
  } catch (const lagrangian::AnalysisError& e) {
    EXPECT_EQ(std::string(e.what()),
              "sensitivity: parameter 'c' moves the constraint manifold past the start: d(string)/dc = -1 there, so "
              "the start would leave the constraints when c changes; ask for other parameters, or start where the "
              "constraints do not depend on it");
  }
}

// A block on a frictionless incline y = s x of slope s (a parameter of the
// row itself) under gravity, released at rest at the origin, where every
// incline passes: the start stays on the manifold when s changes
// (g = y − s x = 0 and ġ = ẏ − s ẋ = 0 there for every s). Along the
// incline the block accelerates at g sin α, tan α = s, downhill:
//   x(t) = −½ g t² s/(1 + s²),  y = s x,
// so ∂x/∂s = −½ g t² (1 − s²)/(1 + s²)² and ∂y/∂s = −g t² s/(1 + s²)²
// (both by a Jet over s of the closed form below). The motion's energies do
// not contain s, so the column comes from the row's derivative alone: the
// test fails if the rows are read without it. A start elsewhere on the
// incline would leave it as s changes (∂g/∂s = −x ≠ 0): refused.
template <class P = double>
struct Incline {
  static constexpr int coordinate_count = 2;
  P m = 1.0, g = 9.81, s = 0.5;
  template <class Q>
  using with_parameter_type = Incline<Q>;
  static constexpr std::array<std::string_view, 3> parameter_names{"m", "g", "s"};
  static constexpr std::array<P Incline::*, 3> parameter_members() { return {&Incline::m, &Incline::g, &Incline::s}; }
  std::string name() const { return "incline"; }
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return m * g * q[1];
  }
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(q[1] - s * q[0]);
  }
};

TEST(ConstrainedSensitivity, InclineSlopeEntersThroughTheRowClosedForm) {
  const Incline<> incline;
  lagrangian::State<2> at_rest;
  at_rest.q.setZero();
  at_rest.qd.setZero();
  lagrangian::SensitivityOptions o;
  o.run = lagrangian_test::lyapunov_options(1.0, 1e-12).run;
  o.run.output_interval = 0.5;
  o.parameters = {"s", "g", "m"};
  o.initial_state = false;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(incline, at_rest, o);
  ASSERT_EQ(r.times.size(), 3u);
  using J = lagrangian::ad::Jet<double, 2, 1>;  // along s and g
  J sj(incline.s), gj(incline.g);
  sj.g[0] = 1.0;
  gj.g[1] = 1.0;
  double worst = 0;
  for (std::size_t i = 0; i < r.times.size(); ++i) {
    const double t = r.times[i];
    const J x = -0.5 * gj * t * t * sj / (1.0 + sj * sj), xd = -gj * t * sj / (1.0 + sj * sj);
    const J y = sj * x, yd = sj * xd;
    ASSERT_EQ(r.sensitivities[i].cols(), 3);
    for (int j = 0; j < 2; ++j) {
      const Eigen::Vector4d expected(x.g[j], y.g[j], xd.g[j], yd.g[j]);
      worst = std::max(worst, (r.sensitivities[i].col(j) - expected).norm() / (1 + expected.norm()));
      EXPECT_LE((r.sensitivities[i].col(j) - expected).norm(), 1e-10 * (1 + expected.norm()))
          << "d/d" << r.parameters[static_cast<std::size_t>(j)] << " at t = " << t << "\n"
          << r.sensitivities[i].col(j).transpose() << "\n" << expected.transpose();
    }
    EXPECT_LE(r.sensitivities[i].col(2).norm(), 1e-12);  // m: the motion does not depend on it
  }
  std::printf("incline, columns of s and g against the closed form: %.1e relative; m: %.1e\n", worst,
              r.sensitivities.back().col(2).norm());
  EXPECT_GT(r.sensitivities.back().col(0).norm(), 1.0);
  // On the incline away from the origin: x = 1, y = s.
  lagrangian::State<2> up;
  up.q = Vec<double, 2>(1.0, incline.s);
  up.qd.setZero();
  o.parameters = {"g", "s"};
  try {
    lagrangian::sensitivities(incline, up, o);
    FAIL() << "a start the slope moves the incline away from was taken";
  } catch (const lagrangian::AnalysisError& e) {
    EXPECT_EQ(std::string(e.what()),
              "sensitivity: parameter 's' moves the constraint manifold past the start: d(g0)/ds = -1 there, so the "
              "start would leave the constraints when s changes; ask for other parameters, or start where the "
              "constraints do not depend on it");
  }
  // Off the incline altogether: the start's own check speaks first.
  up.q[1] = 0.0;
  try {
    lagrangian::sensitivities(incline, up, o);
    FAIL() << "a start off the incline was taken";
  } catch (const lagrangian::ConstraintError& e) {
    EXPECT_NE(std::string(e.what()).find("the initial state violates constraint g0 (-0.5)"), std::string::npos)
        << e.what();
  }
}

// The double pendulum in Cartesian coordinates with two rods, and in
// angles, over 1 s from a regular start: one flow, so for every angle
// perturbation δ (whose image Dψ(x0) δ lies in the manifold's tangent
// space, where P0 is the identity)
//   S_c(t) Dψ(x0) δ = Dψ(x(t)) S_a(t) δ,
// S_c the Cartesian model's sensitivities (8 × 8, Φ P0) and S_a the angle
// model's (4 × 4). Dψ by a first-order Jet.
Eigen::Matrix<double, 8, 4> dpsi(const Eigen::Vector4d& x, double l1, double l2) {
  return lagrangian_test::value_and_jacobian<8>([&](const auto& xs) { return to_cartesian(xs, l1, l2); }, x).second;
}

/// The double pendulum in angles and in Cartesian coordinates (m1 = 1.3,
/// m2 = 0.7 kg, l1 = 1, l2 = 0.8 m) from the same start x0, both run with
/// `o` for 1 s; `start` is the Cartesian start ψ(x0).
struct TwoDoublePendulums {
  static constexpr double m1 = 1.3, m2 = 0.7, l1 = 1.0, l2 = 0.8, g = 9.81;
  const lm::CartesianDoublePendulum cartesian{m1, m2, l1, l2, g};
  const Eigen::Vector4d x0{0.4, -1.1, 1.7, -0.6};
  const Eigen::Matrix<double, 8, 1> start = to_cartesian(x0, l1, l2);
  lagrangian::SensitivityResult angles_run, cartesian_run;

  explicit TwoDoublePendulums(lagrangian::SensitivityOptions o) {
    o.run = lagrangian_test::lyapunov_options(1.0, 1e-12).run;
    angles_run = lagrangian::sensitivities(lm::DoublePendulum(m1, m2, l1, l2, g), state<2>(x0), o);
    cartesian_run = lagrangian::sensitivities(cartesian, state<4>(start), o);
  }
  template <int n, class V>
  static lagrangian::State<n> state(const V& x) {
    lagrangian::State<n> s;
    s.q = x.template head<n>();
    s.qd = x.template tail<n>();
    return s;
  }
};

TEST(ConstrainedSensitivity, CartesianDoublePendulumIsTheAngleModel) {
  const TwoDoublePendulums both{lagrangian::SensitivityOptions{}};
  constexpr double l1 = TwoDoublePendulums::l1, l2 = TwoDoublePendulums::l2;
  const lagrangian::SensitivityResult &ra = both.angles_run, &rc = both.cartesian_run;
  const Eigen::Vector4d& x0 = both.x0;
  const Eigen::Matrix<double, 8, 1>& big = both.start;
  ASSERT_EQ(rc.sensitivities.back().rows(), 8);
  ASSERT_EQ(rc.sensitivities.back().cols(), 8);
  EXPECT_EQ(rc.state_columns, 8);
  const Eigen::Vector4d x1 = ra.states.back();
  const Eigen::Matrix<double, 8, 4> left = rc.sensitivities.back() * dpsi(x0, l1, l2);
  const Eigen::Matrix<double, 8, 4> right = dpsi(x1, l1, l2) * ra.sensitivities.back();
  EXPECT_LE((left - right).norm(), 1e-9 * right.norm()) << "Cartesian:\n" << left << "\nangles:\n" << right;
  // Both runs reach the same state.
  EXPECT_LE((rc.states.back() - to_cartesian(x1, l1, l2)).norm(), 1e-8);
  // The first bob moved outward along its rod, the second kept: the
  // gradient of the first rod's constraint (zero in q̇), normal to the
  // manifold, so P0 and with it S_c map it to 0.
  Eigen::Matrix<double, 8, 1> outward = Eigen::Matrix<double, 8, 1>::Zero();
  outward.head<2>() = big.head<2>() / l1;
  EXPECT_LE((rc.sensitivities.back() * outward).norm(), 1e-9 * right.norm());
}

/// `parameter` (asked for in `o`) moves the constraint manifold of `model`
/// past the start `s`: refused with AnalysisError naming it.
template <class M>
void expect_refused_as_moving_the_manifold(const M& model, const lagrangian::State<M::coordinate_count>& s,
                                           const lagrangian::SensitivityOptions& o, const std::string& parameter) {
  try {
    lagrangian::sensitivities(model, s, o);
    ADD_FAILURE() << "parameter '" << parameter << "', which moves the manifold past the start, was taken";
  } catch (const lagrangian::AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("parameter '" + parameter + "' moves the constraint manifold past the start"),
              std::string::npos)
        << e.what();
  }
}

// The same two models along their shared parameters m1, m2 and g: ψ does
// not depend on them and both start at the same state, so the columns are
// one, s_c(t) = Dψ(x(t)) s_a(t). The rods' lengths move the Cartesian
// model's manifold past the start and are refused, naming the parameter.
TEST(ConstrainedSensitivity, CartesianDoublePendulumParametersAreTheAngleModels) {
  lagrangian::SensitivityOptions o;
  o.initial_state = false;
  o.parameters = {"m1", "m2", "g"};
  const TwoDoublePendulums both(o);
  const lagrangian::SensitivityResult &ra = both.angles_run, &rc = both.cartesian_run;
  ASSERT_EQ(rc.sensitivities.back().rows(), 8);
  ASSERT_EQ(rc.sensitivities.back().cols(), 3);
  const Eigen::Matrix<double, 8, 3> expected =
      dpsi(ra.states.back(), TwoDoublePendulums::l1, TwoDoublePendulums::l2) * ra.sensitivities.back();
  const double error = (rc.sensitivities.back() - expected).cwiseAbs().maxCoeff();
  std::printf("Cartesian double pendulum d/dm1, d/dm2, d/dg against the angle model's: %.2e of the largest %.2f\n",
              error, expected.cwiseAbs().maxCoeff());
  EXPECT_GT(expected.cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LE(error, 1e-8 * expected.cwiseAbs().maxCoeff()) << rc.sensitivities.back() << "\n\n" << expected;
  o.parameters = {"g", "l1"};
  expect_refused_as_moving_the_manifold(both.cartesian, TwoDoublePendulums::state<4>(both.start), o, "l1");
}

// The bead on the wire spinning at ω, started at t0 = 0 on the axis at
// speed v along the wire: r(t) = (v/ω) sinh ωt, (x, y) = r (cos ωt,
// sin ωt). The start lies on the manifold for every ω (g = ġ = 0 and
// ∂g/∂ω = ∂ġ/∂ω = 0 there, as x = y = 0 and t0 = 0; at another t0,
// ∂ġ/∂ω = t0 (ẋ cos ωt0 + ẏ sin ωt0) would not vanish), so ω has a column: the closed form differentiated in ω by
// a first-order Jet. The mass and the wire's reach L (a watched event, not
// applied) leave the motion as it is: their columns are 0.
TEST(ConstrainedSensitivity, BeadOnASpinningWireFromTheAxisClosedForm) {
  const double omega = 1.3, v = 0.4, T = 1.7;
  const lm::BeadOnRotatingWire bead(0.8, omega, 10.0);
  lagrangian::State<2> s;
  s.q = Vec<double, 2>(0.0, 0.0);
  s.qd = Vec<double, 2>(v, 0.0);
  lagrangian::SensitivityOptions o;
  o.run = lagrangian_test::lyapunov_options(T, 1e-12).run;
  o.initial_state = false;
  o.parameters = {"omega", "m", "L"};
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(bead, s, o);
  using J = lagrangian::ad::Jet<double, 1, 1>;
  J w(omega);
  w.g[0] = 1.0;
  using std::cos;
  using std::cosh;
  using std::sin;
  using std::sinh;
  const J radius = v / w * sinh(w * T), rate = v * cosh(w * T);
  const J c = cos(w * T), sn = sin(w * T);
  const std::array<J, 4> x = {radius * c, radius * sn, rate * c - radius * w * sn, rate * sn + radius * w * c};
  Eigen::Vector4d expected;
  for (int i = 0; i < 4; ++i) expected[i] = x[static_cast<std::size_t>(i)].g[0];
  const Eigen::MatrixXd& got = r.sensitivities.back();
  ASSERT_EQ(got.cols(), 3);
  std::printf("bead on a spinning wire from the axis, d/domega: %.2e of the largest %.2f\n",
              (got.col(0) - expected).cwiseAbs().maxCoeff(), expected.cwiseAbs().maxCoeff());
  EXPECT_LE((got.col(0) - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.cwiseAbs().maxCoeff())
      << got.col(0) << "\n\n" << expected;
  EXPECT_LE(got.rightCols(2).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff()) << got.rightCols(2);
  // Off the axis the start's rate row ġ = ẋ sin ωt + x ω cos ωt − … moves with ω.
  s.q = Vec<double, 2>(0.5, 0.0);
  s.qd = Vec<double, 2>(v, omega * 0.5);
  expect_refused_as_moving_the_manifold(bead, s, o, "omega");
}

// A free knife edge turns at its constant φ̇ and runs at its constant
// speed on a circle, whatever its mass and moment of inertia: both columns
// vanish (the side force, which does depend on m, does no work).
TEST(ConstrainedSensitivity, FreeKnifeEdgeDoesNotDependOnItsMassOrInertia) {
  const lm::KnifeEdge knife(1.7, 0.3);
  lagrangian::State<3> s;
  s.q = Vec<double, 3>(0.1, -0.2, 0.5);
  s.qd = Vec<double, 3>(0.8 * std::cos(0.5), 0.8 * std::sin(0.5), 1.4);
  lagrangian::SensitivityOptions o;
  o.run = lagrangian_test::lyapunov_options(3.0, 1e-12).run;
  o.parameters = {"m", "I"};
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(knife, s, o);
  const Eigen::MatrixXd& got = r.sensitivities.back();
  ASSERT_EQ(got.cols(), 6 + 2);
  const double state_scale = got.leftCols(6).cwiseAbs().maxCoeff();
  std::printf("free knife edge: d/dm, d/dI largest entry %.2e (state columns up to %.2f)\n",
              got.rightCols(2).cwiseAbs().maxCoeff(), state_scale);
  EXPECT_GT(state_scale, 1.0);
  EXPECT_LE(got.rightCols(2).cwiseAbs().maxCoeff(), 1e-12 * state_scale) << got.rightCols(2);
}

// The particle on a sphere is the spherical pendulum in Cartesian
// coordinates, X = ψ(θ, φ, θ̇, φ̇) with r = R (sin θ cos φ, sin θ sin φ,
// −cos θ): along g the columns are one, s_c(t) = Dψ(x(t)) s_a(t) (Dψ by a
// first-order Jet); the mass cancels from both; the radius moves the
// sphere past the start and is refused.
TEST(ConstrainedSensitivity, ParticleOnASphereIsTheSphericalPendulumAlongGravity) {
  const double m = 0.9, R = 1.2, g = 9.81;
  const lm::SphericalPendulum angles(m, R, g);
  const lm::ParticleOnSphere cartesian(m, R, g);
  const auto psi = [R](const Eigen::Vector4d& x) {
    return lagrangian_test::value_and_jacobian<6>(
        [R](const auto& a) {
          using S = typename std::decay_t<decltype(a)>::Scalar;
          using std::cos;
          using std::sin;
          const S st = sin(a[0]), ct = cos(a[0]), sp = sin(a[1]), cp = cos(a[1]);
          Eigen::Matrix<S, 6, 1> y;
          y << R * st * cp, R * st * sp, -R * ct, R * (ct * cp * a[2] - st * sp * a[3]),
              R * (ct * sp * a[2] + st * cp * a[3]), R * st * a[2];
          return y;
        },
        x);
  };
  const Eigen::Vector4d x0(0.8, 0.2, 0.5, 1.1);
  lagrangian::SensitivityOptions o;
  o.run = lagrangian_test::lyapunov_options(1.5, 1e-12).run;
  o.initial_state = false;
  o.parameters = {"g", "m"};
  lagrangian::State<2> sa;
  sa.q = x0.head<2>();
  sa.qd = x0.tail<2>();
  const lagrangian::SensitivityResult ra = lagrangian::sensitivities(angles, sa, o);
  const Eigen::Matrix<double, 6, 1> big = psi(x0).first;
  lagrangian::State<3> sc;
  sc.q = big.head<3>();
  sc.qd = big.tail<3>();
  const lagrangian::SensitivityResult rc = lagrangian::sensitivities(cartesian, sc, o);
  ASSERT_EQ(rc.sensitivities.back().cols(), 2);
  const Eigen::Matrix<double, 6, 1> expected = psi(ra.states.back()).second * ra.sensitivities.back().col(0);
  const double error = (rc.sensitivities.back().col(0) - expected).cwiseAbs().maxCoeff();
  std::printf("particle on a sphere d/dg against the spherical pendulum's: %.2e of the largest %.3f\n", error,
              expected.cwiseAbs().maxCoeff());
  EXPECT_GT(expected.cwiseAbs().maxCoeff(), 0.01);
  EXPECT_LE(error, 1e-8 * expected.cwiseAbs().maxCoeff()) << rc.sensitivities.back() << "\n\n" << expected;
  EXPECT_LE(rc.sensitivities.back().col(1).cwiseAbs().maxCoeff(), 1e-12) << rc.sensitivities.back().col(1);
  o.parameters = {"R"};
  expect_refused_as_moving_the_manifold(cartesian, sc, o, "R");
}

lagrangian::FloquetOptions floquet_over(double period) { return lagrangian_test::floquet_options(period); }

// The bead on the wire spinning at ω: the constraint repeats after
// T = 2π/ω and r̈ = ω² r is linear, so over T the flow on the manifold has
// the multipliers e^{±ωT} = e^{±2π} (an unstable, hyperbolic motion),
// whatever the start.
TEST(ConstrainedFloquet, BeadOnASpinningWireHasMultipliersExpOfPlusMinusTwoPi) {
  const double omega = 1.5;
  const lm::BeadOnRotatingWire bead(0.8, omega, 1e6);
  lagrangian::State<2> s;
  s.q = Vec<double, 2>(0.3, 0.0);
  s.qd = Vec<double, 2>(-0.2, omega * 0.3);
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(bead, s, floquet_over(2 * M_PI / omega));
  ASSERT_EQ(r.multipliers.size(), 2u);
  ASSERT_EQ(r.monodromy.rows(), 2);
  EXPECT_NEAR(r.multipliers[0].real() / std::exp(2 * M_PI), 1.0, 1e-8);
  EXPECT_NEAR(r.multipliers[1].real() / std::exp(-2 * M_PI), 1.0, 1e-6);
  EXPECT_EQ(r.multipliers[0].imag(), 0.0);
  EXPECT_NEAR(r.monodromy.determinant(), 1.0, 1e-8);
  EXPECT_FALSE(r.stable);
}

// The pendulum released at rest from 1 rad, as a particle on a rod, over
// its period T = 4 K(k) / ω0, k = sin(θ0/2), ω0 = √(g/l): a closed orbit of
// a conservative system, so its monodromy on the manifold is a Jordan block
// [[1, a], [0, 1]] (a shift along the orbit family): trace 2, det 1, both
// multipliers 1 — as for the same pendulum in its angle.
// The rod pendulum of the tests below: 0.7 kg on a 1.3 m rod released at
// rest from 1 rad; the period of a pendulum swinging to θ0 is
// 4 K(sin(θ0/2)) / √(g/l).
constexpr double kRodMass = 0.7, kRodLength = 1.3, kGravity = 9.81, kRodRelease = 1.0;
double pendulum_period(double theta0, double l, double g) {
  return 4 * std::comp_ellint_1(std::sin(theta0 / 2)) / std::sqrt(g / l);
}
lagrangian::State<2> rod_at_rest(double theta0, double l) {
  lagrangian::State<2> s;
  s.q = Vec<double, 2>(l * std::sin(theta0), -l * std::cos(theta0));
  s.qd.setZero();
  return s;
}

TEST(ConstrainedFloquet, RodPendulumOrbitHasUnitMultipliersAsTheAngleModel) {
  const double m = kRodMass, l = kRodLength, g = kGravity, theta0 = kRodRelease;
  const double period = pendulum_period(theta0, l, g);
  const lm::CartesianPendulum rod(m, l, g);
  const lagrangian::State<2> s = rod_at_rest(theta0, l);
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(rod, s, floquet_over(period));
  ASSERT_EQ(r.multipliers.size(), 2u);
  EXPECT_LE(r.closure, 1e-9);
  EXPECT_NEAR(r.monodromy.trace(), 2.0, 1e-7) << r.monodromy;
  EXPECT_NEAR(r.monodromy.determinant(), 1.0, 1e-9);
  for (const auto& mu : r.multipliers) EXPECT_LE(std::abs(mu - 1.0), 1e-3) << mu;
  const lm::SimplePendulum angle(m, l, g);
  lagrangian::State<1> a;
  a.q[0] = theta0;
  const lagrangian::FloquetResult ra = lagrangian::floquet_multipliers(angle, a, floquet_over(period));
  EXPECT_NEAR(ra.monodromy.trace(), 2.0, 1e-7);
  EXPECT_NEAR(ra.monodromy.determinant(), 1.0, 1e-9);
  EXPECT_TRUE(r.stable);
}

// Newton's method for the orbit on the manifold: the rod pendulum released
// at rest from θ0 = 1 rad, the period guessed 5 % short. The energy row
// holds the start's energy to first order in each step, so the orbit found
// swings to about θ0; it is a periodic orbit (it closes to 1e-10) whose
// period is the closed form 4 K(sin(θm/2)) / √(g/l) of its own amplitude
// θm (from its energy −m g l cos θm), and its start is on the rod.
TEST(ConstrainedFloquet, RodPendulumOrbitFoundFromAShortGuess) {
  const double m = kRodMass, l = kRodLength, g = kGravity, theta0 = kRodRelease;
  const double period = pendulum_period(theta0, l, g);
  const lm::CartesianPendulum rod(m, l, g);
  const lagrangian::State<2> s = rod_at_rest(theta0, l);
  lagrangian::FloquetOptions o = floquet_over(0.95 * period);
  o.find_orbit = true;
  o.closure_tolerance = 1e-10;
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(rod, s, o);
  EXPECT_GT(r.iterations, 1);
  ASSERT_EQ(r.q.size(), 2u);
  EXPECT_NEAR(std::hypot(r.q[0], r.q[1]), l, 1e-10);             // on the rod
  EXPECT_NEAR(r.q[0] * r.qd[0] + r.q[1] * r.qd[1], 0.0, 1e-10);  // moving along it
  const double energy = 0.5 * m * (r.qd[0] * r.qd[0] + r.qd[1] * r.qd[1]) + m * g * r.q[1];
  const double amplitude = std::acos(-energy / (m * g * l));
  EXPECT_NEAR(amplitude, theta0, 1e-3);  // near the start's orbit
  EXPECT_NEAR(r.period, pendulum_period(amplitude, l, g), 1e-8 * period);
  EXPECT_GT(std::abs(r.period - 0.95 * period), 0.04 * period);  // not the guess
  EXPECT_NEAR(r.monodromy.trace(), 2.0, 1e-6);
}

// find_orbit's energy row is ∇E of E = p·q̇ − L from L alone: at a state
// where the constraint force is not zero it must not take it in (a row
// from ṗ = ∂L/∂q + Cᵀλ would). The knife edge moving at 0.9 m/s while
// turning at 0.7 rad/s (side force λ = −m u φ̇), E = ½ m (ẋ² + ẏ²) + ½ I φ̇²:
// ∇E = (0, 0, 0, m ẋ, m ẏ, I φ̇); the pendulum on a rod (tension), with
// V = m g y: ∇E = (0, m g, m ẋ, m ẏ).
TEST(ConstrainedFloquet, EnergyRowIsTheEnergysGradientUnderConstraintForces) {
  const double m = 1.3, inertia = 0.2, u = 0.9, phi = 0.4, turn = 0.7;
  const lm::KnifeEdge knife(m, inertia);
  Eigen::VectorXd x(6);
  x << 0.3, -0.2, phi, u * std::cos(phi), u * std::sin(phi), turn;
  Eigen::VectorXd expected(6);
  expected << 0, 0, 0, m * x[3], m * x[4], inertia * turn;
  const auto knife_model = lagrangian::detail::tangent_model_of(knife, "");
  const double knife_error = (lagrangian::detail::energy_gradient(knife_model, x, 0.0) - expected).norm();
  EXPECT_LE(knife_error, 1e-14);

  const lm::CartesianPendulum rod(kRodMass, kRodLength, kGravity);
  Eigen::VectorXd y(4);
  y << kRodLength * std::sin(0.6), -kRodLength * std::cos(0.6), 0.8 * std::cos(0.6), 0.8 * std::sin(0.6);
  Eigen::VectorXd expected_rod(4);
  expected_rod << 0, kRodMass * kGravity, kRodMass * y[2], kRodMass * y[3];
  const auto rod_model = lagrangian::detail::tangent_model_of(rod, "");
  const double rod_error = (lagrangian::detail::energy_gradient(rod_model, y, 0.0) - expected_rod).norm();
  EXPECT_LE(rod_error, 1e-13);
  std::printf("energy row against the energy's gradient: knife edge %.1e, rod %.1e\n", knife_error, rod_error);
}

// The rod of the tests above with a Pfaffian row beside its holonomic one:
// the rod's rate x ẋ + y ẏ = 0, redundant with ġ (a genuinely nonholonomic
// row leaves no libration to find: the knife edge's motions turn its
// heading without end). The search takes the Pfaffian row as it takes the
// holonomic ones, and from the start and the period guess of
// RodPendulumOrbitFoundFromAShortGuess finds that test's orbit: its period
// the closed form of its amplitude, at the start's energy.
struct RodWithItsRate : lm::CartesianPendulum {
  using lm::CartesianPendulum::CartesianPendulum;
  std::array<std::string_view, 1> pfaffian_names() const { return {"radial_rate"}; }
  std::array<std::string_view, 2> constraint_units() const { return {"m", "m^2/s"}; }
  template <class S>
  Vec<S, 1> pfaffian(const Vec<S, 2>& q, const Vec<S, 2>& qd, const S&) const {
    return Vec<S, 1>(q[0] * qd[0] + q[1] * qd[1]);
  }
};

TEST(ConstrainedFloquet, OrbitFoundWithAPfaffianRowAsWithoutIt) {
  const double m = kRodMass, l = kRodLength, g = kGravity;
  const double period = pendulum_period(kRodRelease, l, g);
  const RodWithItsRate rod(m, l, g);
  const lagrangian::State<2> s = rod_at_rest(kRodRelease, l);
  lagrangian::FloquetOptions o = floquet_over(0.95 * period);
  o.find_orbit = true;
  o.closure_tolerance = 1e-10;
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(rod, s, o);
  const lagrangian::FloquetResult plain = lagrangian::floquet_multipliers(lm::CartesianPendulum(m, l, g), s, o);
  ASSERT_EQ(r.multipliers.size(), 2u);  // rank 2: the Pfaffian row repeats ġ
  EXPECT_GT(r.iterations, 1);
  EXPECT_NEAR(std::hypot(r.q[0], r.q[1]), l, 1e-10);
  const double energy = 0.5 * m * (r.qd[0] * r.qd[0] + r.qd[1] * r.qd[1]) + m * g * r.q[1];
  // The start's energy, to second order in Newton's steps (5 % of the period).
  EXPECT_NEAR(energy, m * g * s.q[1], 1e-3 * m * g * l);
  const double amplitude = std::acos(-energy / (m * g * l));
  EXPECT_NEAR(r.period, pendulum_period(amplitude, l, g), 1e-8 * period);
  EXPECT_NEAR(r.period, plain.period, 1e-8 * period);
  std::printf("with the Pfaffian row: %d iterations, period %.12f s (without it %.12f s, its amplitude's closed "
              "form %.12f s), energy %.1e relative from the start's, trace - 2 = %.1e\n",
              r.iterations, r.period, plain.period, pendulum_period(amplitude, l, g),
              (energy - m * g * s.q[1]) / (m * g * l), r.monodromy.trace() - 2.0);
  EXPECT_GT(std::abs(r.period - 0.95 * period), 0.04 * period);  // not the guess
  EXPECT_NEAR(r.monodromy.trace(), 2.0, 1e-6);
}

// Impacts under holonomic rows (saltation.hpp: Newton's law keeps the rows,
// the saltation matrix acts on the manifold's tangent space).
//
// The rod pendulum against a wall at x = 0.5 m (e = 0.8), from the bottom at
// 2 m/s, 6 s. In its angle θ an impact maps θ̇ to −e θ̇ whatever θ, and its
// saltation matrix in (θ, θ̇) is [[−e, 0], [(1 + e) θ̈/θ̇, −e]], det e²;
// between impacts the flow keeps phase volume in (θ, p_θ). The reduced
// canonical coordinates of the rod model, (Uᵀδq, Uᵀδp) with U the unit
// tangent of the circle, are (l δθ, m l δθ̇) (Uᵀ ∂U/∂θ = 0): a constant
// scaling of (θ, p_θ). So the two exponents sum to 2 ln e · impacts / T
// exactly (the rows' impulses included: without them the bob would leave
// the circle and the sum would differ).
TEST(ConstrainedImpact, RodPendulumAgainstAWallLosesPhaseVolumeAsESquaredPerImpact) {
  const lagrangian::testing::RodPendulumAgainstWall pendulum;
  lagrangian::State<2> s;
  s.q << 0.0, -1.0;
  s.qd << 2.0, 0.0;
  const double t_end = 6.0;
  const lagrangian::LyapunovResult r = lagrangian::lyapunov_spectrum(pendulum, s, lagrangian_test::lyapunov_options(t_end));
  ASSERT_EQ(r.spectrum.size(), 2u);
  EXPECT_GE(r.impacts, 3);
  const double expected = 2 * std::log(pendulum.e) * r.impacts / t_end;
  EXPECT_NEAR(r.sum, expected, 1e-8) << r.impacts << " impacts";
  std::printf("rod pendulum against a wall: %d impacts, sum %.12f, closed form %.12f 1/s (differ by %.1e)\n",
              r.impacts, r.sum, expected, std::abs(r.sum - expected));
}

// The Cartesian double pendulum against a wall (3 rows: two rods, one
// contact) and the angle model against the same wall
// (DoublePendulumAgainstWall: 0.9 − (l1 sin θ1 + l2 sin θ2) ≥ 0) are one
// motion, impact included: S_c(t) Dψ(x0) = Dψ(x(t)) S_a(t) as without the
// wall (ConstrainedSensitivity above), now across the impact, where the
// angle model's law has no rows and the Cartesian one's keeps two.
TEST(ConstrainedImpact, CartesianDoublePendulumAgainstAWallIsTheAngleModel) {
  const lagrangian::testing::CartesianDoublePendulumAgainstWall cartesian;
  const lagrangian::testing::DoublePendulumAgainstWall angles;
  const Eigen::Vector4d x0{0.2, 0.2, 1.0, 1.5};
  const Eigen::Matrix<double, 8, 1> big = to_cartesian(x0, 1.0, 1.0);
  const lagrangian::SensitivityOptions o = lagrangian_test::sensitivity_options(3.0, {}, -1.0);
  const lagrangian::SensitivityResult ra =
      lagrangian::sensitivities(angles, TwoDoublePendulums::state<2>(x0), o);
  const lagrangian::SensitivityResult rc =
      lagrangian::sensitivities(cartesian, TwoDoublePendulums::state<4>(big), o);
  EXPECT_GE(ra.impacts, 2);
  EXPECT_EQ(rc.impacts, ra.impacts);
  const Eigen::Vector4d x1 = ra.states.back();
  EXPECT_LE((rc.states.back() - to_cartesian(x1, 1.0, 1.0)).norm(), 1e-8);
  const Eigen::Matrix<double, 8, 4> left = rc.sensitivities.back() * dpsi(x0, 1.0, 1.0);
  const Eigen::Matrix<double, 8, 4> right = dpsi(x1, 1.0, 1.0) * ra.sensitivities.back();
  EXPECT_LE((left - right).norm(), 1e-8 * right.norm()) << "Cartesian:\n" << left << "\nangles:\n" << right;
  std::printf("Cartesian double pendulum against a wall: %d impacts, |S_c Dpsi - Dpsi S_a| = %.1e of %.3g (%.1e)\n",
              ra.impacts, (left - right).norm(), right.norm(), (left - right).norm() / right.norm());
}

// The impact law under a row, in closed form: the rod pendulum (m = 1 kg,
// l = 1 m) meets the wall at θ = 30° (x = 0.5 m) moving along the circle,
// q̇ = θ̇ (cos θ, sin θ); the rod keeps it on the circle and the wall
// reverses θ̇ times e, so q̇⁺ = −e q̇. Off the velocity manifold, with M = 1
// and W = [C; G] square (C = q/|q| the rod's row, G = (−1, 0) the wall's),
// W q̇⁺ = (0, −e G q̇) gives ∂q̇⁺/∂q̇ = W⁻¹ [0; −e G]. The same rod written
// twice (a redundant row) gives the same q̇⁺ and derivatives; a contact
// whose gap is |q| itself, which the rod fixes, has no impact.
struct RodTwiceAgainstWall : lagrangian::testing::RodPendulumAgainstWall {
  std::array<std::string_view, 2> holonomic_names() const { return {"rod", "rod_again"}; }
  std::array<std::string_view, 3> constraint_units() const { return {"m", "m", "m"}; }
  template <class S>
  Vec<S, 2> holonomic(const Vec<S, 2>& q, const S& t) const {
    const S g = RodPendulumAgainstWall::holonomic(q, t)[0];
    return Vec<S, 2>(g, 2.0 * g);
  }
};
struct RodAgainstItsOwnLength : lagrangian::testing::RodPendulumAgainstWall {
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 2>& q, const S&) const {
    using std::sqrt;
    return Vec<S, 1>(1.5 - sqrt(q[0] * q[0] + q[1] * q[1]));
  }
};

TEST(ConstrainedImpact, ImpactUnderARodHasTheClosedForm) {
  const lagrangian::testing::RodPendulumAgainstWall rod;
  const RodTwiceAgainstWall twice;
  const double theta = std::acos(-1.0) / 6, rate = 1.3;
  const Vec<double, 2> q(std::sin(theta), -std::cos(theta)), qd = rate * Vec<double, 2>(std::cos(theta), std::sin(theta));
  Eigen::Matrix2d w;
  w << q[0], q[1], -1.0, 0.0;
  Eigen::Matrix2d rhs = Eigen::Matrix2d::Zero();
  rhs.row(1) << rod.e * 1.0, 0.0;  // −e G
  const Eigen::Matrix2d expected = w.inverse() * rhs;
  for (const bool redundant : {false, true}) {
    const auto map = redundant ? lagrangian::impact_map(twice, q, qd, 0.0, 0) : lagrangian::impact_map(rod, q, qd, 0.0, 0);
    EXPECT_NEAR(map.approach, -rate * std::cos(theta), 1e-15);
    EXPECT_LE((map.qd_plus + rod.e * qd).norm(), 1e-15) << map.qd_plus.transpose();
    EXPECT_LE((map.jacobian.middleCols(2, 2) - expected).norm(), 1e-14)
        << (redundant ? "the rod twice\n" : "") << map.jacobian.middleCols(2, 2) << "\n\n" << expected;
  }
  const RodAgainstItsOwnLength own;
  const Vec<double, 2> far(0.0, -1.0), outward(0.0, -0.3);
  try {
    (void)lagrangian::impact_map(own, far, outward, 0.0, 0);
    FAIL() << "an impact of a gap the rod fixes was applied";
  } catch (const lagrangian::DynamicsError& e) {
    EXPECT_EQ(std::string(e.what()), "impact map: the gap of contact 0 does not change along the motions the holonomic "
                                     "and Pfaffian constraints allow here");
  }
}

// What is still refused for a model with rows and contacts: a contact
// coming to rest (the held gap would change the manifold the tangent
// vectors are kept on). The rod pendulum released at 0.6 rad beyond a wall
// at x = 0.3 m (φ = x − 0.3), which gravity presses it against, meets it
// with e = 0: a plain run lets it rest there.
struct RodPendulumAgainstNearWall : lagrangian::testing::RodPendulumAgainstWall {
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(q[0] - 0.3);
  }
};

TEST(ConstrainedImpact, ARestUnderRowsStopsTheRunWithItsReason) {
  RodPendulumAgainstNearWall pendulum;
  pendulum.e = 0.0;
  lagrangian::State<2> s;
  s.q << std::sin(0.6), -std::cos(0.6);
  try {
    (void)lagrangian::lyapunov_spectrum(pendulum, s, lagrangian_test::lyapunov_options(5.0));
    FAIL() << "a rest under a holonomic row was crossed";
  } catch (const lagrangian::SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("contact 'wall' comes to rest"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("a plastic impact"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is not derived for a model with holonomic or Pfaffian constraints"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
