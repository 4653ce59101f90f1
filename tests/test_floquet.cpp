// Floquet multipliers from the monodromy matrix (analysis/floquet.hpp):
// Kapitza's pendulum on either side of a²Ω² = 2gl, the transition curves of
// the Mathieu equation against their series, and closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>

#include <Eigen/LU>
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
