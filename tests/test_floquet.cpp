// Floquet multipliers from the monodromy matrix (analysis/floquet.hpp):
// Kapitza's pendulum on either side of a²Ω² = 2gl, the transition curves of
// the Mathieu equation against their series, and closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <string>

#include <Eigen/LU>
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/tools/roots.hpp>

#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/models/pendulums.hpp"

#include "final_state.hpp"

namespace {

using lagrangian::Vec;
namespace lm = lagrangian::models;

/// The Mathieu equation y″ + (a − 2q cos 2t) y = 0 (period π) as a model:
/// L = ½ ẏ² − ½ (a − 2q cos 2t) y².
struct Mathieu {
  static constexpr int coordinate_count = 1;
  double a = 0, q = 0;
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& y, const S& t) const {
    using std::cos;
    return 0.5 * (a - 2 * q * cos(2.0 * t)) * y[0] * y[0];
  }
};

lagrangian::FloquetOptions over(double period, double rtol = 1e-12) {
  lagrangian::FloquetOptions o;
  o.period = period;
  o.run.rtol = rtol;
  o.run.atol = 1e-14;
  return o;
}

TEST(Floquet, HarmonicOscillatorReturnsEveryVectorAfterItsPeriod) {
  const lm::HarmonicOscillator osc(1.0, 4.0);  // ω = 2 rad/s, period π s
  lagrangian::State<1> s;
  s.q[0] = 0.1;
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(osc, s, over(M_PI));
  EXPECT_LE((r.monodromy - Eigen::MatrixXd::Identity(2, 2)).norm(), 1e-9) << r.monodromy;
  EXPECT_LE(r.closure, 1e-10);
  EXPECT_TRUE(r.stable);
}

TEST(Floquet, KapitzaPendulumIsUprightStableAboveTheCriterion) {
  // Pivot y_p = a cos Ωt: the upright position θ = π is stable when
  // a²Ω² > 2 g l (Kapitza); here 2 g l = 19.62 m²/s².
  lagrangian::State<1> upright;
  upright.q[0] = M_PI;
  const lm::DrivenPendulum fast(1.0, 1.0, 0.05, 200.0, 9.81);  // a²Ω² = 100
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(fast, upright, over(2 * M_PI / 200.0));
  EXPECT_TRUE(r.stable) << "largest |mu| = " << r.largest_modulus;
  // Hamiltonian with constant M: det Φ = 1, the multipliers on the unit circle.
  EXPECT_NEAR(r.monodromy.determinant(), 1.0, 1e-9);
  for (const std::complex<double>& mu : r.multipliers) EXPECT_NEAR(std::abs(mu), 1.0, 1e-8);
  EXPECT_LE(r.closure, 1e-12);  // the upright position is a motion of the driven pendulum
  const lm::DrivenPendulum slow(1.0, 1.0, 0.05, 60.0, 9.81);  // a²Ω² = 9
  const lagrangian::FloquetResult u = lagrangian::floquet_multipliers(slow, upright, over(2 * M_PI / 60.0));
  EXPECT_FALSE(u.stable);
  EXPECT_GT(u.largest_modulus, 1.01);
  EXPECT_NEAR(u.monodromy.determinant(), 1.0, 1e-9);
  // Hanging down it is stable at either rate.
  const lagrangian::State<1> down;
  EXPECT_TRUE(lagrangian::floquet_multipliers(slow, down, over(2 * M_PI / 60.0)).stable);
}

/// The a at which tr Φ(π) = target between lo and hi (Boost's bisection on
/// the sign change of tr Φ − target, to 40 bits).
double transition(double q, double target, double lo, double hi) {
  auto f = [&](double a) {
    const Mathieu m{a, q};
    lagrangian::State<1> s;
    return lagrangian::floquet_multipliers(m, s, over(M_PI)).monodromy.trace() - target;
  };
  EXPECT_LT(f(lo) * f(hi), 0.0) << "no sign change of tr - " << target << " on [" << lo << ", " << hi << "]";
  const auto [a, b] = boost::math::tools::bisect(f, lo, hi, boost::math::tools::eps_tolerance<double>(40));
  return 0.5 * (a + b);
}

TEST(Floquet, MathieuTransitionCurvesMatchTheirSeries) {
  // Abramowitz & Stegun 20.2.25, q = 0.1: the curves where a solution of
  // period π (tr Φ = 2: a0) or 2π (tr Φ = −2: b1, a1) exists. The series'
  // next terms are below 7e-8 here.
  const double q = 0.1;
  const double a0 = -q * q / 2 + 7 * std::pow(q, 4) / 128;
  const double a1 = 1 + q - q * q / 8 - std::pow(q, 3) / 64;
  const double b1 = 1 - q - q * q / 8 + std::pow(q, 3) / 64;
  const double found_a0 = transition(q, 2.0, a0 - 0.01, a0 + 0.01);
  const double found_b1 = transition(q, -2.0, b1 - 0.05, b1 + 0.05);
  const double found_a1 = transition(q, -2.0, a1 - 0.05, a1 + 0.05);
  EXPECT_NEAR(found_a0, a0, 1e-6);
  EXPECT_NEAR(found_b1, b1, 1e-6);
  EXPECT_NEAR(found_a1, a1, 1e-6);
  // With the series' next terms (−29q⁶/2304 for a0, −q⁴/1536 for a1 and
  // b1; the ones after are below 4e-9) the agreement is ten times closer.
  EXPECT_NEAR(found_a0, a0 - 29 * std::pow(q, 6) / 2304, 1e-8);
  EXPECT_NEAR(found_b1, b1 - std::pow(q, 4) / 1536, 1e-8);
  EXPECT_NEAR(found_a1, a1 - std::pow(q, 4) / 1536, 1e-8);
}

TEST(Floquet, RefusesABadPeriodByName) {
  const lm::SimplePendulum p;
  const lagrangian::State<1> s;
  try {
    lagrangian::floquet_multipliers(p, s, over(-1.0));
    FAIL() << "a negative period was accepted";
  } catch (const lagrangian::OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("period = -1"), std::string::npos) << e.what();
  }
}

}  // namespace

using lagrangian::testing::final_state;

// Over any time T, not only a period, the monodromy matrix is the state
// transition matrix Φ(T) = ∂x(T)/∂x(0): for the oscillator ẍ = −ω² x,
// Φ = [[cos ωT, sin ωT / ω], [−ω sin ωT, cos ωT]] (measured to 2.1e-13).
TEST(Floquet, OverAnyTimeTheMatrixIsTheOscillatorsTransitionMatrix) {
  const lm::HarmonicOscillator osc(1.0, 4.0);  // ω = 2 rad/s
  lagrangian::State<1> s;
  s.q[0] = 0.3;
  s.qd[0] = -0.2;
  const double w = 2, T = 1.3;
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(osc, s, over(T));
  Eigen::Matrix2d phi;
  phi << std::cos(w * T), std::sin(w * T) / w, -w * std::sin(w * T), std::cos(w * T);
  EXPECT_LE((r.monodromy - phi).cwiseAbs().maxCoeff(), 1e-10) << r.monodromy;
}

// The tangent vectors against the flow itself: Φ(1 s) of the double
// pendulum from a moving state against central differences of simulate()'s
// final state, each initial coordinate moved by ±h (h = 1e-5; the
// differences' truncation error ~h² and their integration noise ~1e-13/h
// both stay below 1e-7 of Φ's largest entry; measured 3.5e-10 of it, 6.57).
TEST(Floquet, TheDoublePendulumsTransitionMatrixIsTheDerivativeOfItsFlow) {
  const lm::DoublePendulum m;
  lagrangian::State<2> s;
  s.q << 1.2, -0.4;
  s.qd << 0.3, 0.8;
  const double T = 1.0, h = 1e-5;
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(m, s, over(T, 1e-13));
  Eigen::Matrix4d fd;
  for (int j = 0; j < 4; ++j) {
    lagrangian::State<2> up = s, down = s;
    (j < 2 ? up.q[j] : up.qd[j - 2]) += h;
    (j < 2 ? down.q[j] : down.qd[j - 2]) -= h;
    fd.col(j) = (final_state(m, up, T) - final_state(m, down, T)) / (2 * h);
  }
  const double scale = fd.cwiseAbs().maxCoeff();
  EXPECT_GT(scale, 1.0);  // a non-trivial map: the motion shears
  EXPECT_LE((r.monodromy - fd).cwiseAbs().maxCoeff(), 1e-6 * scale) << r.monodromy << "\n\n" << fd;
}

namespace {

/// ẍ + c ẋ + ω² x = F cos Ωt (per unit mass): L = ½ ẋ² − ½ ω² x², Q = −c ẋ + F cos Ωt.
struct ForcedDampedOscillator {
  static constexpr int coordinate_count = 1;
  double w = 2.0, c = 0.4, F = 1.0, drive = 3.0;  // 1/s, 1/s, m/s², 1/s
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    return 0.5 * w * w * q[0] * q[0];
  }
  template <class S>
  Vec<S, 1> generalized_forces(const Vec<S, 1>&, const Vec<S, 1>& qd, const S& t) const {
    using std::cos;
    return Vec<S, 1>(-c * qd[0] + F * cos(drive * t));
  }
};

lagrangian::FloquetOptions guessing(double period, double rtol = 1e-12) {
  lagrangian::FloquetOptions o;
  o.find_orbit = true;
  o.period = period;
  o.run.rtol = rtol;
  o.run.atol = 1e-14;
  o.closure_tolerance = 1e-10;
  return o;
}

}  // namespace

// Every orbit of the oscillator has the period 2π/ω: from a guess 5 % long
// Newton finds π s (ω = 2 rad/s) and the start stays an orbit's point.
TEST(PeriodicOrbit, HarmonicOscillatorsPeriodFromAGuess) {
  const lm::HarmonicOscillator osc(1.0, 4.0);
  lagrangian::State<1> s;
  s.q[0] = 0.3;
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(osc, s, guessing(1.05 * M_PI));
  std::printf("oscillator: period %.15f (pi %.15f) after %d iterations, closure %.1e\n", r.period, M_PI, r.iterations,
              r.closure);
  EXPECT_NEAR(r.period, M_PI, 1e-10);
  EXPECT_GT(r.iterations, 1);
  EXPECT_NEAR(std::hypot(r.q[0], r.qd[0] / 2.0), 0.3, 1e-3);  // near the start's orbit
}

// The pendulum's libration: Newton moves the start and the period to an
// orbit of the family, whose period is 4K(k)/ω0 at its own energy,
// k² = (θ̇0/2ω0)² + sin²(θ0/2); both multipliers are 1 (along the orbit and
// across the family).
TEST(PeriodicOrbit, PendulumLibrationHasItsEllipticPeriod) {
  const lm::SimplePendulum pendulum;  // l = 1 m, g = 9.81 m/s²
  const double w0 = std::sqrt(9.81), k1 = std::sin(0.5);
  const double t_one_radian = 4 * boost::math::ellint_1(k1) / w0;
  lagrangian::State<1> s;
  s.q[0] = 1.0;
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(pendulum, s, guessing(1.05 * t_one_radian));
  const double half = 0.5 * r.q[0], c = 0.5 * r.qd[0] / w0;
  const double k = std::sqrt(c * c + std::sin(half) * std::sin(half));
  const double expected = 4 * boost::math::ellint_1(k) / w0;
  std::printf("pendulum: period %.15f, 4K(k)/w0 %.15f at k = %.12f (start's k %.12f), %d iterations, "
              "multipliers %.8f%+.8fi, %.8f%+.8fi\n",
              r.period, expected, k, k1, r.iterations, r.multipliers[0].real(), r.multipliers[0].imag(),
              r.multipliers[1].real(), r.multipliers[1].imag());
  EXPECT_NEAR(r.period, expected, 1e-9 * expected);
  EXPECT_NEAR(k, k1, 0.02);  // the family's member near the start
  for (const auto& mu : r.multipliers) EXPECT_LE(std::abs(mu - 1.0), 1e-4);
  EXPECT_TRUE(r.stable);
}

// A drive of period T = 2π/Ω fixes the period: Newton finds the steady
// response x = A cos(Ωt − φ), A = F / √((ω² − Ω²)² + (cΩ)²),
// φ = atan2(cΩ, ω² − Ω²), in one step (the equation is linear), and the
// multipliers are e^(λT), λ = −c/2 ± i√(ω² − c²/4): |μ| = e^(−cT/2).
TEST(PeriodicOrbit, ForcedDampedOscillatorsSteadyResponse) {
  const ForcedDampedOscillator m;
  const double period = 2 * M_PI / m.drive;
  lagrangian::FloquetOptions o = guessing(period);
  o.fixed_period = true;
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(m, lagrangian::State<1>{}, o);
  const double a = m.F / std::hypot(m.w * m.w - m.drive * m.drive, m.c * m.drive);
  const double phi = std::atan2(m.c * m.drive, m.w * m.w - m.drive * m.drive);
  std::printf("forced oscillator: x0 %.15f (closed form %.15f), v0 %.15f (%.15f), %d iterations, |mu| %.12f (%.12f)\n",
              r.q[0], a * std::cos(phi), r.qd[0], a * m.drive * std::sin(phi), r.iterations,
              std::abs(r.multipliers[0]), std::exp(-0.5 * m.c * period));
  EXPECT_DOUBLE_EQ(r.period, period);
  EXPECT_NEAR(r.q[0], a * std::cos(phi), 1e-10);
  EXPECT_NEAR(r.qd[0], a * m.drive * std::sin(phi), 1e-10);
  EXPECT_EQ(r.iterations, 2);  // one Newton step, then the closure check
  for (const auto& mu : r.multipliers) EXPECT_NEAR(std::abs(mu), std::exp(-0.5 * m.c * period), 1e-9);
  EXPECT_TRUE(r.stable);
}

TEST(PeriodicOrbit, NoOrbitAndBadOptionsAreNamed) {
  const lm::SimplePendulum pendulum;
  lagrangian::State<1> s;
  s.q[0] = 1.0;
  lagrangian::FloquetOptions o = guessing(1.0);  // far from 2.1 s
  o.max_iterations = 1;
  try {
    lagrangian::floquet_multipliers(pendulum, s, o);
    FAIL() << "a start one second off its period was reported an orbit";
  } catch (const lagrangian::AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("floquet: no periodic orbit found: after 1 Newton iterations"),
              std::string::npos)
        << e.what();
  }
  o = guessing(0.0);
  try {
    lagrangian::floquet_multipliers(pendulum, s, o);
    FAIL() << "period = 0 was accepted";
  } catch (const lagrangian::OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "floquet: period = 0 s must be finite and > 0");
  }
}
