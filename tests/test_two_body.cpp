// The two-body problem: its relative motion equals the one-body problem of
// the reduced mass, the centre of mass moves uniformly, momentum, angular
// momentum and energy are conserved, and the orbit is Kepler's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/two_body.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;
using V3 = Eigen::Vector3d;

constexpr double kG = 1.0;  // units with G = 1: a = 1, m₁ + m₂ = 1 give period 2π

// Two bodies placed so that the relative coordinate starts at periapsis of
// the orbit (a, e) in the x-y plane, and the centre of mass starts at R0
// moving with V0.
State<6> pair_at_periapsis(double m1, double m2, const KeplerOrbit& orbit, const V3& R0, const V3& V0) {
  const auto s = orbit.state(orbit.tp);
  const V3 r(s[0], s[1], 0.0), v(s[2], s[3], 0.0);
  const double M = m1 + m2;
  State<6> x;
  x.q << R0 - m2 / M * r, R0 + m1 / M * r;
  x.qd << V0 - m2 / M * v, V0 + m1 / M * v;
  return x;
}

SimulationOptions tight(double t_end, double interval) {
  SimulationOptions o;
  o.method = Method::fehlberg78;
  o.t_end = t_end;
  o.rtol = 1e-14;
  o.atol = 1e-16;
  o.output_interval = interval;
  return o;
}

TEST(TwoBody, RelativeMotionEqualsTheReducedMassProblemOver100Orbits) {
  const double m1 = 0.75, m2 = 0.25, e = 0.5;
  const auto pair = gravitational_two_body<3>(m1, m2, kG);
  const auto reduced = gravitational_relative_motion<3>(m1, m2, kG);
  const KeplerOrbit orbit(1.0, e, kG * (m1 + m2));
  const V3 R0(0.3, -0.2, 0.1), V0(0.01, 0.02, -0.005);
  const State<6> x0 = pair_at_periapsis(m1, m2, orbit, R0, V0);
  State<3> r0;
  r0.q = x0.q.tail<3>() - x0.q.head<3>();
  r0.qd = x0.qd.tail<3>() - x0.qd.head<3>();
  const double t_end = 100 * orbit.period();
  Recorder<6> rp;
  Recorder<3> rr;
  const RunReport two = simulate(pair, x0, tight(t_end, orbit.period() / 8), rp);
  const RunReport one = simulate(reduced, r0, tight(t_end, orbit.period() / 8), rr);
  ASSERT_EQ(rp.samples.size(), rr.samples.size());
  double worst = 0, worst_com = 0, worst_p = 0, worst_l = 0;
  const double M = m1 + m2;
  const V3 L0 = m1 * V3(x0.q.head<3>()).cross(V3(x0.qd.head<3>())) + m2 * V3(x0.q.tail<3>()).cross(V3(x0.qd.tail<3>()));
  for (std::size_t k = 0; k < rp.samples.size(); ++k) {
    const auto& a = rp.samples[k];
    const auto& b = rr.samples[k];
    // A sample lands on the step end when that is within 1e-12 relative of
    // the grid time, so the two runs' times can differ by that much: carry
    // the reduced run to the two-body sample's time with its velocity.
    ASSERT_NEAR(a.t, b.t, 1e-12 * a.t);
    const V3 r1 = a.q.head<3>(), r2 = a.q.tail<3>(), v1 = a.qd.head<3>(), v2 = a.qd.tail<3>();
    worst = std::max(worst, (r2 - r1 - V3(b.q) - (a.t - b.t) * V3(b.qd)).norm());
    // Centre of mass: R(t) = R0 + V0 t.
    worst_com = std::max(worst_com, ((m1 * r1 + m2 * r2) / M - (R0 + V0 * a.t)).norm());
    // Total momentum M V0 and angular momentum about the origin.
    worst_p = std::max(worst_p, (m1 * v1 + m2 * v2 - M * V0).norm());
    worst_l = std::max(worst_l, (m1 * r1.cross(v1) + m2 * r2.cross(v2) - L0).norm());
  }
  std::printf("100 orbits, e = 0.5: |r(two-body) - r(reduced)| max %.2e a; centre of mass %.2e; "
              "momentum %.2e; angular momentum %.2e; energy drift %.2e / %.2e\n",
              worst, worst_com, worst_p, worst_l, two.total_energy_drift_max, one.total_energy_drift_max);
  // The formulations agree as closely as each agrees with the closed form
  // (asserted below): the two-body run's relative coordinate is off by at
  // most twice its largest position error per axis, the reduced run's by
  // its own (fehlberg78 at rtol 1e-14 leaves a few 1e-10 a either way).
  EXPECT_LE(worst, std::sqrt(3.0) * (2 * two.reference_error_max + one.reference_error_max));
  EXPECT_LE(worst_com, 1e-11);
  EXPECT_LE(worst_p, 1e-13);
  EXPECT_LE(worst_l, 1e-11);
  EXPECT_LE(two.total_energy_drift_max, 1e-11);
  // The run report says the same about P and L (from its own samples).
  ASSERT_TRUE(two.has_particles);
  EXPECT_NEAR(two.linear_momentum_initial[0], M * V0.x(), 1e-15);
  EXPECT_NEAR(two.angular_momentum_initial[2], L0.z(), 1e-15);
  EXPECT_LE(two.linear_momentum_drift_max, 1e-13);
  EXPECT_LE(two.angular_momentum_drift_max, 1e-11);
  EXPECT_NEAR(two.angular_momentum_drift_max, worst_l, 1e-16);
  EXPECT_FALSE(one.has_particles);
  // Both runs measure themselves against the closed form (centre of mass plus Kepler).
  ASSERT_TRUE(two.has_reference);
  ASSERT_TRUE(one.has_reference);
  EXPECT_LE(two.reference_error_max, 1e-9);
  EXPECT_LE(one.reference_error_max, 1e-9);
  std::printf("reference error over 100 orbits: two-body %.2e, reduced %.2e\n", two.reference_error_max,
              one.reference_error_max);
  EXPECT_LE(one.total_energy_drift_max, 1e-11);
}

TEST(TwoBody, OrbitsFollowKeplersEquationAndPeriod) {
  // The reduced problem against the closed-form orbit for e = 0, 0.5, 0.9,
  // 0.99 over 10 orbits, and the period from the logged periapsis passages.
  const double m1 = 1.0, m2 = 3e-6;  // a planet around a star
  const auto reduced = gravitational_relative_motion<3>(m1, m2, kG);
  for (double e : {0.0, 0.5, 0.9, 0.99}) {
    const KeplerOrbit orbit(1.0, e, kG * (m1 + m2));
    const auto s = orbit.state(0.0);
    State<3> x0;
    x0.q << s[0], s[1], 0.0;
    x0.qd << s[2], s[3], 0.0;
    Recorder<3> rec;
    const RunReport r = simulate(reduced, x0, tight(10 * orbit.period(), orbit.period() / 64), rec);
    double worst = 0;
    for (const auto& x : rec.samples) {
      const auto ref = orbit.state(x.t);
      worst = std::max(worst, std::hypot(x.q[0] - ref[0], x.q[1] - ref[1]));
      EXPECT_EQ(x.q[2], 0.0);
    }
    // Periapsis passages: one per period (e = 0 has no periapsis to find).
    std::vector<double> passages;
    for (const auto& ev : r.events) passages.push_back(ev.t);
    double period_error = 0;
    if (e > 0) {
      ASSERT_GE(passages.size(), 9u) << e;
      for (std::size_t k = 1; k < passages.size(); ++k)
        period_error = std::max(period_error, std::abs(passages[k] - passages[k - 1] - orbit.period()));
      EXPECT_LE(period_error, 1e-9 * orbit.period()) << e;
    }
    std::printf("e = %.2f: 10 orbits, %llu steps, max position error %.2e a, period error %.2e P\n", e,
                static_cast<unsigned long long>(r.steps), worst, period_error / orbit.period());
    EXPECT_LE(worst, e < 0.95 ? 1e-10 : 1e-8) << e;
  }
}

TEST(TwoBody, KeplerEquationSolverAndTheCircularOrbit) {
  // E − e sin E = M to rounding for many anomalies and eccentricities.
  for (double e : {0.0, 0.3, 0.9, 0.999}) {
    const KeplerOrbit orbit(2.0, e, 5.0);
    for (int k = 0; k < 100; ++k) {
      const double t = 0.013 * k * orbit.period();
      const double E = orbit.eccentric_anomaly(t);
      double m = std::fmod(orbit.mean_motion() * t, 2 * std::acos(-1.0));
      EXPECT_NEAR(E - e * std::sin(E), m, 1e-14) << e << " " << t;
      // Energy and angular momentum of the closed form are those of the orbit.
      const auto s = orbit.state(t);
      const double r = std::hypot(s[0], s[1]);
      const double kinetic = 0.5 * (s[2] * s[2] + s[3] * s[3]);
      EXPECT_NEAR(kinetic - 5.0 / r, -5.0 / (2 * 2.0), 1e-14 * (kinetic + 5.0 / r));
      EXPECT_NEAR(s[0] * s[3] - s[1] * s[2], std::sqrt(5.0 * 2.0 * (1 - e * e)),
                  1e-14 * (std::abs(s[0] * s[3]) + std::abs(s[1] * s[2])));
    }
  }
  // Kepler's third law for the two-body problem: P = 2π √(a³ / (G (m₁ + m₂))).
  const KeplerOrbit earth(1.495978707e11, 0.0167, 6.674e-11 * (1.98847e30 + 5.9722e24));
  EXPECT_NEAR(earth.period() / 86400.0, 365.25, 0.1);
}

TEST(TwoBody, KeplerFromAnyStateMatchesTheOrbitClosedForm) {
  // kepler_propagate (elements from a state vector) against KeplerOrbit
  // (from elements), on orbits tilted out of the x-y plane.
  for (double e : {0.0, 0.3, 0.95}) {
    const KeplerOrbit orbit(1.7, e, 2.5, 0.4);
    const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(0.7, V3::UnitX()) * Eigen::AngleAxisd(-0.3, V3::UnitZ())).toRotationMatrix();
    const auto s0 = orbit.state(0.0);
    const V3 r0 = tilt * V3(s0[0], s0[1], 0), v0 = tilt * V3(s0[2], s0[3], 0);
    for (double t : {0.0, 0.3, 1.7, 5.0, 23.0}) {
      const auto [r, v] = kepler_propagate(2.5, r0, v0, t);
      const auto s = orbit.state(t);
      EXPECT_LE((r - tilt * V3(s[0], s[1], 0)).norm(), 1e-12) << e << " " << t;
      EXPECT_LE((v - tilt * V3(s[2], s[3], 0)).norm(), 1e-11 * V3(s[2], s[3], 0).norm()) << e << " " << t;
    }
  }
  EXPECT_THROW(elliptic_kepler_propagate(1.0, V3(1, 0, 0), V3(0, 2, 0), 1.0), ParameterError);  // escape speed exceeded
  EXPECT_THROW(kepler_propagate(1.0, V3(1, 0, 0), V3(0.5, 0, 0), 1.0), ParameterError);  // radial
}

// Any central force given by its potential, F(r) = −dU/dr: a spring between
// the bodies, U = ½ κ (r − r_n)² with natural length r_n = 0 (isotropic
// oscillator): the relative motion has period 2π √(μ/κ) in every direction.
struct Spring {
  double kappa;
  template <class S>
  S operator()(const S& r) const {
    return 0.5 * kappa * r * r;
  }
};

TEST(TwoBody, AnyCentralForceReducesTheSameWay) {
  const double m1 = 2.0, m2 = 0.5, kappa = 3.0;
  const TwoBody<2, Spring> pair(m1, m2, Spring{kappa});
  const RelativeMotion<2, Spring> reduced(reduced_mass(m1, m2), Spring{kappa});
  State<4> x0;
  x0.q << 0.0, 0.0, 1.0, 0.0;
  x0.qd << 0.0, 0.1, 0.3, 0.7;
  State<2> r0;
  r0.q << 1.0, 0.0;
  r0.qd << 0.3, 0.6;
  const double period = 2 * std::acos(-1.0) * std::sqrt(reduced.mu / kappa);
  Recorder<4> rp;
  Recorder<2> rr;
  simulate(pair, x0, tight(10 * period, period / 4), rp);
  simulate(reduced, r0, tight(10 * period, period / 4), rr);
  ASSERT_EQ(rp.samples.size(), rr.samples.size());
  for (std::size_t k = 0; k < rp.samples.size(); ++k) {
    const auto& a = rp.samples[k];
    const auto& b = rr.samples[k];
    EXPECT_NEAR(a.q[2] - a.q[0], b.q[0] + (a.t - b.t) * b.qd[0], 1e-11);
    EXPECT_NEAR(a.q[3] - a.q[1], b.q[1] + (a.t - b.t) * b.qd[1], 1e-11);
    if (k % 4 == 0) {  // whole periods: back at the start
      EXPECT_NEAR(b.q[0], 1.0, 1e-10) << b.t;
      EXPECT_NEAR(b.q[1], 0.0, 1e-10) << b.t;
    }
  }
}

// Gravity given as a force law F(r) = −k/r² (the notes' form) moves the
// bodies exactly as gravity given as the potential −k/r.
struct InverseSquare {
  double k;
  template <class S>
  S operator()(const S& r) const {
    return -k / (r * r);
  }
};

TEST(TwoBody, AForceLawAndItsPotentialGiveTheSameMotion) {
  const double m1 = 0.6, m2 = 0.4;
  const auto by_potential = gravitational_two_body<3>(m1, m2, kG);
  const TwoBodyForce<3, InverseSquare> by_force(m1, m2, InverseSquare{kG * m1 * m2});
  const State<6> x0 = by_potential.default_state();
  const double period = KeplerOrbit(1.0, 0.5, kG * (m1 + m2)).period();
  Recorder<6> a, b;
  const RunReport ra = simulate(by_potential, x0, tight(5 * period, period / 10), a);
  const RunReport rb = simulate(by_force, x0, tight(5 * period, period / 10), b);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  for (std::size_t k = 0; k < a.samples.size(); ++k)
    EXPECT_LE((a.samples[k].q - b.samples[k].q - (a.samples[k].t - b.samples[k].t) * b.samples[k].qd)
                  .lpNorm<Eigen::Infinity>(),
              1e-10)
        << a.samples[k].t;
  EXPECT_TRUE(ra.conservative);
  EXPECT_FALSE(rb.conservative);  // a force law is not declared conservative
  EXPECT_LE(rb.linear_momentum_drift_max, 1e-13);  // internal forces: momentum still conserved
}

TEST(TwoBody, TheAngularMomentumMonitorFlagsADriftAndRungeKuttaKeepsLinearMomentum) {
  // Two bodies on an eccentric orbit (e = 0.9) with rk4 steps too long for
  // the periapsis: L = Σ m r × v, quadratic in the state, drifts far beyond
  // 1 % of Σ m |r| |v|; P = Σ m v is a linear invariant, which every
  // Runge–Kutta method keeps to rounding whatever its step.
  const double m1 = 1.0, m2 = 1.0;
  const TwoBody<2> pair(m1, m2, NewtonianGravity{1.0});
  State<4> x0;
  x0.q << -0.05, 0.0, 0.05, 0.0;
  const double v = 0.5 * std::sqrt(1.9 / 0.1 * 2.0);  // each body's speed at periapsis, relative speed √(G M (1 + e)/r_p)
  x0.qd << 0.0, -v, 0.0, v;
  SimulationOptions o;
  o.method = Method::rk4;
  o.dt = 0.03;
  o.t_end = 6.0;
  o.output_interval = 0.05;
  const RunReport coarse = simulate(pair, x0, o);
  ASSERT_TRUE(coarse.has_particles);
  auto verdict = [](const RunReport& r, const char* name) {
    const auto it = std::find_if(r.monitors.begin(), r.monitors.end(),
                                 [&](const MonitorVerdict& m) { return m.name == name; });
    return it == r.monitors.end() ? nullptr : &*it;
  };
  const MonitorVerdict* L = verdict(coarse, "angular momentum");
  const MonitorVerdict* P = verdict(coarse, "linear momentum");
  ASSERT_NE(L, nullptr);
  ASSERT_NE(P, nullptr);
  EXPECT_TRUE(L->exceeded) << L->figure;
  EXPECT_LT(P->figure, 1e-13);
  EXPECT_FALSE(P->exceeded);
  EXPECT_TRUE(coarse.drift_exceeded);

  o.method = Method::dopri5;
  const RunReport fine = simulate(pair, x0, o);
  EXPECT_LT(verdict(fine, "angular momentum")->figure, 1e-7);
  EXPECT_FALSE(fine.drift_exceeded);
}

TEST(TwoBody, HydrogenReducedMass) {
  // μ = m_e m_p / (m_e + m_p) ≈ m_e (1 − m_e/m_p); the approximation's
  // relative error is (m_e/m_p)² / (1 + m_e/m_p) ≈ 2.97e-7.
  const double me = electron_mass, mp = proton_mass;
  const double mu = reduced_mass(me, mp);
  EXPECT_NEAR(mu, me * mp / (me + mp), 1e-16 * mu);
  EXPECT_NEAR(mu / me, 0.99945568, 1e-8);  // μ/m_e = 1/(1 + m_e/m_p)
  const double approx = me * (1 - me / mp);
  const double ratio = me / mp;
  EXPECT_NEAR((mu - approx) / mu, ratio * ratio, 1e-12);
  EXPECT_NEAR((mu - approx) / mu, 2.97e-7, 0.01e-7);
  // Reduced mass of equal masses is half; of a tiny and a huge mass, the tiny one.
  EXPECT_EQ(reduced_mass(2.0, 2.0), 1.0);
  EXPECT_NEAR(reduced_mass(1.0, 1e30), 1.0, 1e-15);
}

TEST(TwoBody, BadInputIsAClearError) {
  EXPECT_THROW(gravitational_two_body<3>(-1.0, 1.0, kG), ParameterError);
  EXPECT_THROW(gravitational_relative_motion<2>(1.0, 1.0, 0.0), ParameterError);
  try {
    KeplerOrbit(1.0, 1.0, 1.0);
    FAIL() << "no error";
  } catch (const ParameterError& err) {
    EXPECT_NE(std::string(err.what()).find("KeplerOrbit: parameter 'e' must be in [0, 1) (a bound orbit), got 1"),
              std::string::npos)
        << err.what();
  }
  EXPECT_THROW(KeplerOrbit(-1.0, 0.5, 1.0), ParameterError);
  EXPECT_THROW(reduced_mass(0.0, 1.0), ParameterError);
  // Coincident bodies: the potential is singular; the run stops with a clear error, not NaN output.
  const auto pair = gravitational_two_body<3>(1.0, 1.0, kG);
  State<6> x0;
  x0.q.setZero();
  x0.qd.setZero();
  EXPECT_THROW(simulate(pair, x0, SimulationOptions{}), Error);
}

}  // namespace
