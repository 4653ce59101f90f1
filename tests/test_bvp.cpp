// Boundary-value problems by stationary discrete action (analysis.hpp):
// the free particle's straight line, the parabola of uniform gravity and the
// launch velocity it implies (against the projectile model's closed form),
// the harmonic oscillator below and beyond half a period (Morse index of the
// discrete action's Hessian), second-order convergence, the singular case at
// exactly half a period, and refused input.

#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "lagrangian/analysis/analysis.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/projectile.hpp"

using namespace lagrangian;
namespace lm = lagrangian::models;

namespace {

constexpr double kPi = 3.141592653589793;

auto free_particle(double m) {
  return make_model<2>(
      "free particle", {"x", "y"},
      [m](const auto&, const auto& qd, const auto&) { return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]); },
      [](const auto& q, const auto&) { return 0.0 * q[0]; });
}

/// Largest node error of the harmonic oscillator's BVP against
/// q(t) = [a sin ω(t1 − t) + b sin ω(t − t0)] / sin ωT.
/// With w the discrete frequency Ω = (2/h) atan(ωh/2) instead, the formula is
/// the exact solution of the midpoint discrete Euler–Lagrange equations
///   m (q_{k+1} − 2q_k + q_{k−1})/h² + (k/4)(q_{k+1} + 2q_k + q_{k−1}) = 0
/// (q_k = sin(Ω t_k) solves them when tan²(Ωh/2) = ω²h²/4).
double oscillator_error(const BvpResult& r, double w, double a, double b, double t0, double t1) {
  double err = 0;
  for (std::size_t k = 0; k < r.t.size(); ++k) {
    const double t = r.t[k];
    const double exact = (a * std::sin(w * (t1 - t)) + b * std::sin(w * (t - t0))) / std::sin(w * (t1 - t0));
    err = std::max(err, std::abs(r.q(static_cast<int>(k), 0) - exact));
  }
  return err;
}

}  // namespace

TEST(StationaryAction, FreeParticleGoesStraight) {
  const auto fp = free_particle(2.5);
  const Eigen::Vector2d a(1.0, -2.0), b(4.0, 3.0);
  BvpOptions opt;
  opt.steps = 50;
  const BvpResult r = solve_bvp(fp, a, b, 0.5, 2.5, opt);
  const Eigen::Vector2d v = (b - a) / 2.0;
  for (int k = 0; k <= 50; ++k) {
    const double s = (r.t[static_cast<std::size_t>(k)] - 0.5) / 2.0;
    EXPECT_NEAR((r.q.row(k).transpose() - (a + s * (b - a))).norm(), 0.0, 1e-12);
    EXPECT_NEAR((r.qd.row(k).transpose() - v).norm(), 0.0, 1e-12);
  }
  EXPECT_EQ(r.negative_eigenvalues, 0);
  EXPECT_TRUE(r.minimum());
  EXPECT_NEAR(r.action, 0.5 * 2.5 * (b - a).squaredNorm() / 2.0, 1e-12);  // S = ½ m |b − a|² / T
  EXPECT_LE(r.iterations, 2);  // linear equations: one Newton step, one to confirm
  EXPECT_LT(r.residual, 1e-12);
}

TEST(StationaryAction, UniformGravityParabolaAndLaunchVelocity) {
  const double m = 0.8, g = 9.81, T = 1.7;
  const lm::Projectile<> proj(m, g);
  const Eigen::Vector2d a(0.0, 1.0), b(12.0, 3.0);
  for (DiscreteRule rule : {DiscreteRule::midpoint, DiscreteRule::trapezoidal}) {
    BvpOptions opt;
    opt.steps = 40;
    opt.rule = rule;
    const BvpResult r = solve_bvp(proj, a, b, 0.0, T, opt);
    // By hand: y = a_y + v0y t − g t²/2 through b at T gives v0 = (b − a)/T + (0, g T / 2).
    const Eigen::Vector2d v0 = (b - a) / T + Eigen::Vector2d(0.0, 0.5 * g * T);
    EXPECT_NEAR((r.qd.row(0).transpose() - v0).norm(), 0.0, 1e-10) << to_string(rule);
    for (int k = 0; k <= 40; ++k) {
      const double t = r.t[static_cast<std::size_t>(k)];
      const Eigen::Vector2d exact = a + v0 * t + Eigen::Vector2d(0.0, -0.5 * g * t * t);
      EXPECT_NEAR((r.q.row(k).transpose() - exact).norm(), 0.0, 1e-11) << to_string(rule) << " node " << k;
    }
    // The projectile model's own closed form, launched with that velocity, lands on b at T.
    State<2> launch;
    launch.q = a;
    launch.qd = r.qd.row(0).transpose();
    const State<2> end = proj.reference(launch, T);
    EXPECT_NEAR((end.q - b).norm(), 0.0, 1e-10);
    EXPECT_NEAR((end.qd - r.qd.row(40).transpose()).norm(), 0.0, 1e-10);
    EXPECT_TRUE(r.minimum());
    // h = T + V is conserved along the path.
    for (double e : r.energy) EXPECT_NEAR(e, r.energy[0], 1e-10 * std::abs(r.energy[0]));
  }
}

TEST(StationaryAction, OscillatorBelowHalfPeriodIsAMinimum) {
  const lm::HarmonicOscillator ho(1.5, 6.0);  // ω = 2 rad/s, half period π/2 s
  const double w = 2.0, T = 0.8 * kPi / w, a = 0.3, b = -0.1;
  BvpOptions opt;
  opt.steps = 100;
  const BvpResult r1 = solve_bvp(ho, Vec<double, 1>(a), Vec<double, 1>(b), 0.0, T, opt);
  opt.steps = 200;
  const BvpResult r2 = solve_bvp(ho, Vec<double, 1>(a), Vec<double, 1>(b), 0.0, T, opt);
  EXPECT_EQ(r1.negative_eigenvalues, 0);
  EXPECT_EQ(r2.negative_eigenvalues, 0);
  const double e1 = oscillator_error(r1, w, a, b, 0.0, T), e2 = oscillator_error(r2, w, a, b, 0.0, T);
  const double wd = 2 * 200 / T * std::atan(w * T / 200 / 2);  // discrete frequency for K = 200
  EXPECT_LT(oscillator_error(r2, wd, a, b, 0.0, T), 1e-13);
  EXPECT_LT(e2, 2e-5);
  EXPECT_NEAR(std::log2(e1 / e2), 2.0, 0.05) << e1 << " " << e2;
  std::printf("T = 0.8 half periods: error %.3g (K = 100), %.3g (K = 200), order %.3f\n", e1, e2, std::log2(e1 / e2));
  // Energy ½ m ẋ² + ½ k x² at the nodes: constant to O(h²).
  double spread = 0;
  for (double e : r2.energy) spread = std::max(spread, std::abs(e - r2.energy[0]));
  EXPECT_LT(spread, 1e-4 * std::abs(r2.energy[0]));
}

TEST(StationaryAction, OscillatorBeyondHalfPeriodIsASaddle) {
  // Beyond half a period the action is stationary but not a minimum: Newton
  // converges all the same; the Hessian has one negative eigenvalue per half
  // period passed (Jacobi's conjugate points).
  const lm::HarmonicOscillator ho(1.0, 4.0);  // ω = 2
  const double w = 2.0, a = 0.2, b = 0.5;
  for (double frac : {1.6, 2.5, 3.3}) {
    const double T = frac * kPi / w;
    BvpOptions opt;
    opt.steps = 200;
    const BvpResult r = solve_bvp(ho, Vec<double, 1>(a), Vec<double, 1>(b), 0.0, T, opt);
    EXPECT_EQ(r.negative_eigenvalues, static_cast<int>(std::floor(frac))) << frac;
    EXPECT_FALSE(r.minimum());
    EXPECT_TRUE(r.eigenvalues_computed);
    EXPECT_LT(r.lowest_eigenvalue, 0.0);
    const double wd = 2 * 200 / T * std::atan(w * T / 200 / 2);
    EXPECT_LT(oscillator_error(r, wd, a, b, 0.0, T), 1e-11) << frac;
    opt.steps = 400;
    const BvpResult r2 = solve_bvp(ho, Vec<double, 1>(a), Vec<double, 1>(b), 0.0, T, opt);
    const double ea = oscillator_error(r, w, a, b, 0.0, T), eb = oscillator_error(r2, w, a, b, 0.0, T);
    EXPECT_NEAR(std::log2(ea / eb), 2.0, 0.05);
    std::printf("T = %.1f half periods: Morse index %d, lowest eigenvalue %.4g, error %.3g (K = 200), %.3g (K = 400), "
                "order %.3f\n", frac, r.negative_eigenvalues, r.lowest_eigenvalue, ea, eb, std::log2(ea / eb));
  }
}

TEST(StationaryAction, ExactlyHalfAPeriodIsSingular) {
  const lm::HarmonicOscillator ho(1.0, 4.0);
  BvpOptions opt;
  opt.steps = 200;
  try {
    solve_bvp(ho, Vec<double, 1>(0.2), Vec<double, 1>(0.5), 0.0, kPi / 2.0, opt);
    FAIL() << "no error at half a period";
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
  }
  // Also from the other side of the discrete conjugate point, and with a few steps.
  opt.steps = 20;
  EXPECT_THROW(solve_bvp(ho, Vec<double, 1>(0.2), Vec<double, 1>(0.5), 0.0, kPi / 2.0, opt), AnalysisError);
  // 5 % away it is well posed.
  EXPECT_NO_THROW(solve_bvp(ho, Vec<double, 1>(0.2), Vec<double, 1>(0.5), 0.0, 1.05 * kPi / 2.0, opt));
}

TEST(StationaryAction, NonlinearPendulumConvergesAtSecondOrder) {
  // No closed form: the error against a fine solution halves twice per halving of h.
  const lm::SimplePendulum p(1.0, 1.0, 9.81);
  const Vec<double, 1> a(0.1), b(2.0);
  const double T = 1.0;
  auto solve = [&](int K) {
    BvpOptions opt;
    opt.steps = K;
    return solve_bvp(p, a, b, 0.0, T, opt);
  };
  const BvpResult fine = solve(1600), r1 = solve(50), r2 = solve(100);
  auto err = [&](const BvpResult& r) {
    const int stride = 1600 / (static_cast<int>(r.t.size()) - 1);
    double e = 0;
    for (int k = 0; k < static_cast<int>(r.t.size()); ++k) e = std::max(e, std::abs(r.q(k, 0) - fine.q(k * stride, 0)));
    return e;
  };
  EXPECT_NEAR(std::log2(err(r1) / err(r2)), 2.0, 0.1) << err(r1) << " " << err(r2);
  std::printf("pendulum 0.1 -> 2 rad in 1 s: error %.3g (K = 50), %.3g (K = 100), order %.3f\n", err(r1), err(r2),
              std::log2(err(r1) / err(r2)));
  EXPECT_EQ(fine.negative_eigenvalues, 0);
  for (double e : fine.energy) EXPECT_NEAR(e, fine.energy[0], 1e-4 * std::abs(fine.energy[0]));
}

TEST(StationaryAction, BadInputAndUnsuitedModelsAreRefused) {
  const lm::HarmonicOscillator ho;
  const Vec<double, 1> a(0.0), b(1.0);
  BvpOptions opt;
  EXPECT_THROW(solve_bvp(ho, a, b, 1.0, 1.0, opt), OptionError);
  EXPECT_THROW(solve_bvp(ho, a, b, 0.0, std::nan(""), opt), OptionError);
  EXPECT_THROW(solve_bvp(ho, Vec<double, 1>(INFINITY), b, 0.0, 1.0, opt), OptionError);
  opt.steps = 1;
  EXPECT_THROW(solve_bvp(ho, a, b, 0.0, 1.0, opt), OptionError);
  opt.steps = 20;
  const lm::CartesianPendulum cp;
  try {
    solve_bvp(cp, Eigen::Vector2d(0, -1), Eigen::Vector2d(1, 0), 0.0, 1.0, opt);
    FAIL();
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("constraints"), std::string::npos);
  }
  const lm::Projectile<lm::Drag::linear> drag(1.0, 9.81, 0.0, 0.3);
  try {
    solve_bvp(drag, Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), 0.0, 1.0, opt);
    FAIL();
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("dissipation"), std::string::npos);
  }
}

TEST(StationaryAction, MinimiserAgreesBelowHalfPeriodAndRunsAwayBeyond) {
  // L-BFGS on S_d finds the same path where the action is a minimum; beyond
  // half a period S_d is unbounded below and the minimiser does not stop at
  // the stationary path that Newton's method finds.
  const lm::HarmonicOscillator ho(1.0, 4.0);  // ω = 2, half period π/2
  BvpOptions opt;
  opt.steps = 100;
  const Vec<double, 1> a(0.2), b(0.5);
  const double below = 0.8 * kPi / 2, beyond = 1.6 * kPi / 2;
  const BvpResult r1 = solve_bvp(ho, a, b, 0.0, below, opt);
  const ActionMinimum m1 = minimise_action(ho, a, b, 0.0, below, opt);
  EXPECT_TRUE(m1.converged) << m1.nlopt_result << " residual " << m1.residual;
  EXPECT_LT((m1.q - r1.q).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_NEAR(m1.action, r1.action, 1e-12 * (1 + std::abs(r1.action)));
  const BvpResult r2 = solve_bvp(ho, a, b, 0.0, beyond, opt);
  const ActionMinimum m2 = minimise_action(ho, a, b, 0.0, beyond, opt);
  EXPECT_FALSE(m2.converged);
  EXPECT_TRUE(!std::isfinite(m2.action) || m2.action < r2.action - 1.0) << m2.action << " vs " << r2.action;
  std::printf("L-BFGS below half a period: %d evaluations, max difference %.2e; beyond: result %d after %d "
              "evaluations, action %.4g (stationary %.4g), residual %.3g\n",
              m1.evaluations, (m1.q - r1.q).cwiseAbs().maxCoeff(), m2.nlopt_result, m2.evaluations, m2.action,
              r2.action, m2.residual);
  // The projectile: the minimiser's parabola is Newton's.
  const lm::Projectile<> proj(1.0, 9.81);
  const Eigen::Vector2d p0(0, 0), p1(30, 5);
  const BvpResult rp = solve_bvp(proj, p0, p1, 0.0, 2.5, opt);
  const ActionMinimum mp = minimise_action(proj, p0, p1, 0.0, 2.5, opt);
  EXPECT_TRUE(mp.converged);
  EXPECT_LT((mp.q - rp.q).cwiseAbs().maxCoeff(), 1e-7);
}

TEST(StationaryAction, SingularMassMatrixOnThePathIsAnErrorNotNaN) {
  // The spherical pendulum at θ = 0: M = diag(m l², 0), φ̇ cannot be recovered.
  const lm::SphericalPendulum sp;
  BvpOptions opt;
  opt.steps = 20;
  try {
    solve_bvp(sp, Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.5, 0.0), 0.0, 1.0, opt);
    FAIL() << "no error";
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("mass matrix is singular at node 0"), std::string::npos) << e.what();
  }
}
