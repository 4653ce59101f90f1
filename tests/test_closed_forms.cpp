// Closed forms of the harmonic oscillator, of the plane pendulum at any
// amplitude (Jacobi elliptic functions) and of a relativistic particle in a
// uniform field (a Lagrangian not quadratic in the velocities), checked
// against tight numerical runs of the equations of motion the framework
// derives, against conservation of energy, against the small-angle limit and
// the known period series.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;
const double kPi = std::acos(-1.0);

SimulationOptions tight(Method method, double t_end, double rtol, double dt_out) {
  SimulationOptions o;
  o.method = method;
  o.t_end = t_end;
  o.rtol = rtol;
  o.atol = rtol;
  o.output_interval = dt_out;
  return o;
}

State<1> state(double q, double qd) {
  State<1> s;
  s.q[0] = q;
  s.qd[0] = qd;
  return s;
}

/// Largest difference in q and in q̇ between the samples of a run and the
/// model's closed form.
template <class M>
std::pair<double, double> worst_difference(const M& model, const State<1>& x0, const Recorder<1>& rec) {
  double dq = 0, dqd = 0;
  for (const auto& s : rec.samples) {
    const State<1> ref = model.reference(x0, s.t);
    dq = std::max(dq, std::abs(s.q[0] - ref.q[0]));
    dqd = std::max(dqd, std::abs(s.qd[0] - ref.qd[0]));
  }
  return {dq, dqd};
}

// -- harmonic oscillator ------------------------------------------------------------

TEST(HarmonicOscillator, ClosedFormAgreesWithTheDerivedEquationsOfMotion) {
  const HarmonicOscillator osc(2.0, 5.0);  // ω = √2.5 rad/s
  const State<1> x0 = state(0.1, -0.3);
  Recorder<1> rec;
  const RunReport r = simulate(osc, x0, tight(Method::dopri5, 20.0, 1e-12, 0.05), rec);
  ASSERT_EQ(rec.samples.size(), 401u);
  const auto [dq, dqd] = worst_difference(osc, x0, rec);
  std::printf("oscillator closed form vs dopri5 1e-12: %.1e m, %.1e m/s\n", dq, dqd);
  EXPECT_LT(dq, 1e-10);
  EXPECT_LT(dqd, 1e-10);
  EXPECT_GT(dq, 0.0);  // a numerical run, not the closed form itself
  // The run reports its true error against the same closed form.
  EXPECT_TRUE(r.has_reference);
  EXPECT_NEAR(r.reference_error_max, dq, 1e-16);
}

TEST(HarmonicOscillator, PeriodAndEnergy) {
  const HarmonicOscillator osc(0.5, 8.0);  // ω = 4 rad/s, period π/2 s
  EXPECT_DOUBLE_EQ(osc.omega(), 4.0);
  const State<1> x0 = state(0.2, 0.6);
  const double period = 2 * kPi / 4.0;
  // The numerical run, not the closed form, returns to its start after 2π/ω.
  Recorder<1> rec;
  simulate(osc, x0, tight(Method::fehlberg78, period, 1e-13, -1), rec);
  EXPECT_NEAR(rec.samples.back().q[0], 0.2, 1e-11);
  EXPECT_NEAR(rec.samples.back().qd[0], 0.6, 1e-11);
  // A quarter period: x = ẋ0/ω, ẋ = −ω x0.
  const State<1> quarter = osc.reference(x0, period / 4);
  EXPECT_NEAR(quarter.q[0], 0.6 / 4.0, 1e-15);
  EXPECT_NEAR(quarter.qd[0], -4.0 * 0.2, 1e-15);
  // E = ½ m ẋ² + ½ k x² is constant along the closed form.
  const double e0 = 0.5 * 0.5 * 0.36 + 0.5 * 8.0 * 0.04;
  for (double t = 0; t < 10; t += 0.37) {
    const State<1> s = osc.reference(x0, t);
    EXPECT_NEAR(0.5 * 0.5 * s.qd[0] * s.qd[0] + 0.5 * 8.0 * s.q[0] * s.q[0], e0, 1e-15) << t;
  }
}

TEST(HarmonicOscillator, RejectsBadParametersNamingThem) {
  const auto message = [](double m, double k) {
    try {
      HarmonicOscillator osc(m, k);
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string zero_mass = message(0.0, 1.0);
  EXPECT_NE(zero_mass.find("HarmonicOscillator"), std::string::npos) << zero_mass;
  EXPECT_NE(zero_mass.find("m"), std::string::npos) << zero_mass;
  EXPECT_NE(zero_mass.find("0"), std::string::npos) << zero_mass;
  const std::string negative_k = message(1.0, -3.5);
  EXPECT_NE(negative_k.find("k"), std::string::npos) << negative_k;
  EXPECT_NE(negative_k.find("-3.5"), std::string::npos) << negative_k;
  EXPECT_NE(message(1.0, std::nan("")).find("k"), std::string::npos);
  EXPECT_NE(message(INFINITY, 1.0), "no error");
}

// -- plane pendulum at any amplitude --------------------------------------------------

/// h/(m l²) = ½ θ̇² − ω0² cos θ of a state.
double energy(const SimplePendulum& p, const State<1>& s) {
  return 0.5 * s.qd[0] * s.qd[0] - p.g / p.l * std::cos(s.q[0]);
}

struct PendulumCase {
  double theta0, rate0;
  const char* what;
};

TEST(SimplePendulum, ClosedFormAgreesWithATightRunAtEveryAmplitude) {
  const SimplePendulum p(1.0, 0.8, 9.81);  // ω0 = 3.50 rad/s; over the top needs |θ̇| > 2ω0 = 7.0 rad/s at θ = 0
  const PendulumCase cases[] = {
      {0.1, 0.0, "small amplitude, at rest"},
      {2.5, 0.0, "large amplitude, at rest"},
      {-3.0, 0.0, "near the top, at rest, negative side"},
      {1.0, -2.0, "moving towards the bottom"},
      {-0.4, 3.0, "moving up from the negative side"},
      {2 * kPi + 0.4, 1.5, "one turn added to the angle"},
      {0.3, 8.0, "rotating, positive direction"},
      {-1.0, -7.5, "rotating, negative direction"},
      {5.0, 12.0, "fast rotation from beyond pi"},
  };
  for (const auto& c : cases) {
    const State<1> x0 = state(c.theta0, c.rate0);
    Recorder<1> rec;
    const RunReport r = simulate(p, x0, tight(Method::fehlberg78, 12.0, 1e-13, 0.03), rec);
    ASSERT_NEAR(r.t_final, 12.0, 1e-12) << c.what;
    const auto [dq, dqd] = worst_difference(p, x0, rec);
    std::printf("pendulum %-40s closed form vs fehlberg78 1e-13: %.1e rad, %.1e rad/s\n", c.what, dq, dqd);
    EXPECT_LT(dq, 2e-9) << c.what;
    EXPECT_LT(dqd, 2e-8) << c.what;
    // The closed form conserves the energy exactly (to round-off).
    const double e0 = energy(p, x0);
    for (const auto& s : rec.samples)
      EXPECT_NEAR(energy(p, p.reference(x0, s.t)), e0, 1e-12 * (std::abs(e0) + p.g / p.l)) << c.what << " " << s.t;
  }
}

TEST(SimplePendulum, ClosedFormPeriodMatchesTheAmplitudeSeriesAndTheSmallAngleLimit) {
  const SimplePendulum p(1.0, 2.0, 9.81);
  const double w0 = std::sqrt(p.g / p.l);
  // Released at rest from θ0: back at θ0, at rest, after T = 4 K(sin(θ0/2)) / ω0,
  // which the series T = (2π/ω0)(1 + θ0²/16 + 11 θ0⁴/3072 + …) approximates.
  for (double theta0 : {0.05, 0.2}) {
    const double series = 2 * kPi / w0 * (1 + theta0 * theta0 / 16 + 11 * std::pow(theta0, 4) / 3072);
    const State<1> x0 = state(theta0, 0.0);
    const State<1> back = p.reference(x0, series);
    // The series' remainder is O(θ0⁶): the state at the series period is at rest
    // at θ0 to within |θ̈| δT ~ ω0² θ0 · θ0⁶ T.
    EXPECT_NEAR(back.q[0], theta0, 1e-9) << theta0;
    EXPECT_NEAR(back.qd[0], 0.0, 50 * w0 * w0 * theta0 * std::pow(theta0, 6) * series) << theta0;
    // Half a period: at −θ0.
    EXPECT_NEAR(p.reference(x0, series / 2).q[0], -theta0, 1e-9) << theta0;
  }
  // Small angle: θ → θ0 cos ω0 t + (θ̇0/ω0) sin ω0 t, the phase slipping by θ0²/16 per radian.
  const double a = 1e-3;
  const State<1> x0 = state(a, 0.5 * a * w0);
  for (double t = 0; t < 2 * kPi / w0; t += 0.05) {
    const double linear = a * std::cos(w0 * t) + 0.5 * a * std::sin(w0 * t);
    EXPECT_NEAR(p.reference(x0, t).q[0], linear, 2e-9) << t;
  }
  // The direction of motion: released at rest from θ0 > 0, the bob first swings down.
  EXPECT_LT(p.reference(state(2.5, 0.0), 0.01).qd[0], 0.0);
  EXPECT_LT(p.reference(state(2.5, 0.0), 0.01).q[0], 2.5);
}

TEST(SimplePendulum, ClosedFormOnTheSeparatrixAndWithoutGravity) {
  const SimplePendulum p(1.0, 1.0, 9.81);
  const double w0 = std::sqrt(p.g / p.l);
  // From the bottom with θ̇ = 2ω0: the energy of the top; θ creeps up to π.
  const State<1> x0 = state(0.0, 2 * w0);
  double last = 0;
  for (double t = 0.1; t < 6; t += 0.1) {
    const State<1> s = p.reference(x0, t);
    EXPECT_GT(s.q[0], last) << t;
    EXPECT_LT(s.q[0], kPi) << t;
    EXPECT_NEAR(energy(p, s), w0 * w0, 1e-12 * w0 * w0) << t;
    last = s.q[0];
  }
  EXPECT_NEAR(last, kPi, 1e-3);
  // The same against a tight run, over a time short enough for the unstable
  // motion not to amplify the run's error beyond 1e-8.
  Recorder<1> rec;
  simulate(p, x0, tight(Method::fehlberg78, 2.0, 1e-13, 0.02), rec);
  const auto [dq, dqd] = worst_difference(p, x0, rec);
  EXPECT_LT(dq, 1e-8);
  EXPECT_LT(dqd, 1e-7);
  // Mirror image: θ̇0 = −2ω0 creeps to −π.
  EXPECT_NEAR(p.reference(state(0.0, -2 * w0), 6.0).q[0], -kPi, 1e-3);
  // At rest on the top it stays there.
  EXPECT_EQ(p.reference(state(kPi, 0.0), 3.0).q[0], kPi);
  // Without gravity: uniform rotation.
  const SimplePendulum free(1.0, 1.0, 0.0);
  EXPECT_DOUBLE_EQ(free.reference(state(0.5, 2.0), 3.0).q[0], 6.5);
}

// A relativistic particle in a uniform field g along −z (SI units, with a
// small c so that the motion is strongly relativistic):
//   L = −m c² √(1 − |v|²/c²) − m g z,
// not quadratic in v, so M = ∂²L/∂v² = γ m (I + γ² v vᵀ/c²) depends on the
// velocity. With p = γ m v: p_x is conserved, p_z = p_z0 − m g t, and with
// k² = m²c² + p_x², E = c √(k² + p_z²) (conserved, with the potential: h),
// dx/dt = p_x c / √(k² + p_z²) and dz/dt = p_z c / √(k² + p_z²) integrate to
//   x(t) = x0 + (p_x c / (m g)) (asinh(p_z0 / k) − asinh(p_z / k)),
//   z(t) = z0 + (c / (m g)) (√(k² + p_z0²) − √(k² + p_z²)).
struct RelativisticParticle {
  static constexpr int coordinate_count = 2;  // x, z (m)
  double m = 1.0, c = 2.0, g = 9.81;
  template <class S>
  S lagrangian(const Vec<S, 2>& q, const Vec<S, 2>& qd, const S&) const {
    using std::sqrt;
    return -m * c * c * sqrt(1.0 - (qd[0] * qd[0] + qd[1] * qd[1]) / (c * c)) - m * g * q[1];
  }
};

TEST(RelativisticParticle, NonQuadraticLagrangianFollowsItsClosedForm) {
  const RelativisticParticle model;
  const double m = model.m, c = model.c, g = model.g;
  State<2> s0;
  s0.q << 0.0, 0.0;
  s0.qd << 1.2, 1.5;  // |v| = 1.92 m/s: γ = 3.6
  // The velocity-dependent mass matrix: M(v) = γ m (I + γ² v vᵀ / c²).
  const double v2 = s0.qd.squaredNorm(), gamma = 1.0 / std::sqrt(1.0 - v2 / (c * c));
  const Mat<double, 2> m_exact =
      gamma * m * (Mat<double, 2>::Identity() + gamma * gamma * s0.qd * s0.qd.transpose() / (c * c));
  EXPECT_LE((mass_matrix(model, s0.q, s0.qd) - m_exact).norm(), 1e-13 * m_exact.norm());
  const Vec<double, 2> p0 = gamma * m * s0.qd;
  EXPECT_LE((momenta(model, s0.q, s0.qd) - p0).norm(), 1e-14 * p0.norm());

  const double k = std::sqrt(m * m * c * c + p0[0] * p0[0]);
  Recorder<2> rec;
  const RunReport r = simulate(model, s0, tight(Method::dopri5, 1.0, 1e-12, 0.25), rec);
  ASSERT_EQ(rec.samples.size(), 5u);
  double worst = 0;
  for (const auto& s : rec.samples) {
    const double pz = p0[1] - m * g * s.t;
    const double x = (p0[0] * c / (m * g)) * (std::asinh(p0[1] / k) - std::asinh(pz / k));
    const double z = (c / (m * g)) * (std::sqrt(k * k + p0[1] * p0[1]) - std::sqrt(k * k + pz * pz));
    const double root = std::sqrt(k * k + pz * pz);
    worst = std::max({worst, std::abs(s.q[0] - x), std::abs(s.q[1] - z), std::abs(s.qd[0] - p0[0] * c / root),
                      std::abs(s.qd[1] - pz * c / root)});
  }
  EXPECT_LE(worst, 1e-9);
  // By t = 1 s the particle moves at 0.95 c, downwards.
  EXPECT_GT(rec.samples.back().qd.norm(), 0.95 * c);
  EXPECT_LT(rec.samples.back().qd[1], 0.0);
  // h = γ m c² + m g z is conserved.
  EXPECT_LE(r.energy_drift_max, 1e-10);
}

}  // namespace
