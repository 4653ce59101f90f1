// Integration: conservation laws, closed forms, convergence order, sampling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

constexpr double kPi = std::numbers::pi;

/// Harmonic oscillator m ẍ = −k x with the closed form x = A cos ωt + (v0/ω) sin ωt.
auto harmonic_oscillator(double m, double k) {
  return make_model<1>(
      "harmonic_oscillator", {"x"}, [m](const auto&, const auto& qd, const auto&) { return 0.5 * m * qd[0] * qd[0]; },
      [k](const auto& q, const auto&) { return 0.5 * k * q[0] * q[0]; });
}

SimulationOptions options(Method method, double t_end, double rtol = 1e-10) {
  SimulationOptions o;
  o.method = method;
  o.t_end = t_end;
  o.rtol = rtol;
  o.atol = rtol * 1e-2;
  return o;
}

// -- energy conservation: dopri5, rtol 1e-10, 20 periods: drift ≤ 1e-8 ------------

template <class M>
void expect_energy_conserved(const M& model, const State<lagrangian::coordinate_count_v<M>>& x0, double period) {
  const RunReport r = simulate(model, x0, options(Method::dopri5, 20 * period));
  EXPECT_TRUE(r.conservative) << r.model;
  EXPECT_LE(r.energy_drift_max, 1e-8) << r.model;
  EXPECT_LE(r.total_energy_drift_max, 1e-8) << r.model;
  EXPECT_GT(r.steps, 100u) << r.model;  // the run did real work
}

TEST(Simulate, EnergyConservedSimplePendulum) {
  const SimplePendulum m(1.0, 1.0, 9.81);
  State<1> x0;
  x0.q[0] = 2.5;  // large amplitude
  expect_energy_conserved(m, x0, 2 * kPi * std::sqrt(m.l / m.g));
}

TEST(Simulate, EnergyConservedDoublePendulum) {
  const DoublePendulum m;
  State<2> x0;
  x0.q << 2.0, 2.0;
  expect_energy_conserved(m, x0, 2 * kPi * std::sqrt(m.l1 / m.g));
}

TEST(Simulate, EnergyConservedSphericalPendulum) {
  const SphericalPendulum m;
  State<2> x0;
  x0.q << 1.0, 0.0;
  x0.qd << 0.0, 2.0;
  expect_energy_conserved(m, x0, 2 * kPi * std::sqrt(m.l / m.g));
}

TEST(Simulate, EnergyConservedElasticPendulum) {
  const ElasticPendulum m;
  State<2> x0;
  x0.q << 1.3, 0.5;
  expect_energy_conserved(m, x0, 2 * kPi * std::sqrt(m.l0 / m.g));
}

TEST(Simulate, EnergyConservedCartPendulum) {
  const CartPendulum m;
  State<2> x0;
  x0.q << 0.3, 1.2;
  expect_energy_conserved(m, x0, 2 * kPi * std::sqrt(m.l / m.g));
}

// -- Kepler: p_φ conserved (φ cyclic), energy conserved, period -----------------------

TEST(Simulate, KeplerAngularMomentumConservedAndPeriodMatches) {
  const KeplerPolar m(1.0, 1.0);  // μ = k/m = 1
  // Start at perihelion of an orbit with a = 1, e = 0.5: r_p = a(1−e),
  // v_p = √(μ(1+e)/(a(1−e))).
  const double a = 1.0, e = 0.5, mu = 1.0;
  State<2> x0;
  x0.q << a * (1 - e), 0.0;
  x0.qd << 0.0, std::sqrt(mu * (1 + e) / (a * (1 - e))) / (a * (1 - e));
  const double period = 2 * kPi * std::sqrt(a * a * a / mu);
  SimulationOptions o = options(Method::dopri5, 20 * period, 1e-11);
  o.output_interval = period / 8;  // samples land on whole periods
  Recorder<2> rec;
  const RunReport r = simulate(m, x0, o, rec);
  ASSERT_EQ(r.conserved_momenta.size(), 1u);
  EXPECT_EQ(r.conserved_momenta[0].coordinate, "phi");
  const double p_phi = m.m * x0.q[0] * x0.q[0] * x0.qd[1];
  EXPECT_NEAR(r.conserved_momenta[0].initial, p_phi, 1e-15);
  EXPECT_LE(r.conserved_momenta[0].max_abs_drift, 1e-9 * p_phi);
  EXPECT_LE(r.energy_drift_max, 1e-8);
  // After each whole period the particle is back at perihelion: r = a(1−e), φ = 2πk.
  for (const auto& s : rec.samples) {
    const double k = s.t / period;
    if (std::abs(k - std::round(k)) > 1e-9) continue;
    EXPECT_NEAR(s.q[0], a * (1 - e), 1e-7) << "t = " << s.t;
    EXPECT_NEAR(s.q[1], 2 * kPi * std::round(k), 1e-6) << "t = " << s.t;
  }
}

TEST(Simulate, SphericalPendulumAzimuthalMomentumConserved) {
  const SphericalPendulum m;
  State<2> x0;
  x0.q << 1.2, 0.3;
  x0.qd << 0.4, 1.5;
  const RunReport r = simulate(m, x0, options(Method::dopri5, 10.0));
  ASSERT_EQ(r.conserved_momenta.size(), 1u);
  EXPECT_EQ(r.conserved_momenta[0].coordinate, "phi");
  EXPECT_LE(r.conserved_momenta[0].max_abs_drift, 1e-8 * std::abs(r.conserved_momenta[0].initial));
}

TEST(Simulate, NoCyclicCoordinateWhereLDependsOnIt) {
  const DoublePendulum m;
  State<2> x0;
  x0.q << 0.1, 0.2;
  EXPECT_TRUE(cyclic_coordinates(m, x0).empty());
  const KeplerPolar k;
  State<2> y0;
  y0.q << 1.0, 0.0;
  y0.qd << 0.0, 1.0;
  EXPECT_EQ(cyclic_coordinates(k, y0), std::vector<int>{1});
}

// -- the Jacobi integral of the rotating hoop ---------------------------------------

TEST(Simulate, RotatingHoopConservesJacobiIntegralNotTotalEnergy) {
  const BeadOnRotatingHoop m(0.1, 0.5, 6.0, 9.81);
  State<1> x0;
  x0.q[0] = 0.05;
  const RunReport r = simulate(m, x0, options(Method::dopri5, 20.0));
  EXPECT_TRUE(r.conservative);
  EXPECT_LE(r.energy_drift_max, 1e-8);
  EXPECT_GT(r.total_energy_drift_max, 1e-2);  // the motor feeds energy in and out
}

TEST(Simulate, ExplicitTimeDependenceIsNotConservative) {
  const DrivenPendulum m;
  State<1> x0;
  x0.q[0] = 0.3;
  EXPECT_FALSE(is_autonomous(m, x0));
  const RunReport r = simulate(m, x0, options(Method::dopri5, 2.0));
  EXPECT_FALSE(r.conservative);
}

// -- closed forms -------------------------------------------------------------------

TEST(Simulate, HarmonicOscillatorMatchesClosedFormWithEveryStepper) {
  const double m = 0.5, k = 2.0, w = std::sqrt(k / m);
  const auto osc = with_structure_preserving(harmonic_oscillator(m, k));  // every stepper
  State<1> x0;
  x0.q[0] = 0.7;
  x0.qd[0] = -0.3;
  for (const MethodInfo& row : method_table()) {
    const Method method = row.method;
    SimulationOptions o = options(method, 10.0);
    o.dt = 1e-3;
    o.output_interval = 0.25;
    Recorder<1> rec;
    const RunReport r = simulate(osc, x0, o, rec);
    ASSERT_EQ(rec.samples.size(), 41u) << method;  // t = 0, 0.25, …, 10
    double worst = 0;
    for (const auto& s : rec.samples) {
      const double exact = x0.q[0] * std::cos(w * s.t) + x0.qd[0] / w * std::sin(w * s.t);
      worst = std::max(worst, std::abs(s.q[0] - exact));
    }
    // rk4 at dt = 1e-3 has a global error ~ (w dt)⁴ t ≈ 1e-11; the adaptive
    // steppers run at rtol 1e-10; rosenbrock4 is only order 4 with a
    // finite-difference Jacobian; the second-order variational and velocity
    // Verlet steps have a phase error (w dt)² w t / 24 · |x| ≈ 6e-6 here.
    const bool second_order = method == Method::variational || method == Method::velocity_verlet;
    const double bound = method == Method::rosenbrock4 ? 1e-6 : second_order ? 2e-5 : 1e-7;
    EXPECT_LE(worst, bound) << method;
    EXPECT_DOUBLE_EQ(rec.samples.back().t, 10.0) << method;
    EXPECT_EQ(r.samples, rec.samples.size()) << method;
    EXPECT_GE(r.rhs_evaluations, r.steps) << method;
  }
}

TEST(Simulate, DampedForcedOscillatorMatchesClosedForm) {
  // m ẍ + c ẋ + k x = F: x(t) = F/k + e^{−γt}(A cos ω_d t + B sin ω_d t).
  const double m = 1.0, k = 4.0, c = 0.4, F = 0.8;
  auto model = with_forces(
      with_dissipation(harmonic_oscillator(m, k), [c](const auto&, const auto& qd) { return 0.5 * c * qd[0] * qd[0]; }),
      [F](const auto& q, const auto&, const auto&) {
        using S = typename std::decay_t<decltype(q)>::Scalar;
        return Vec<S, 1>(S(F));
      });
  const double gamma = c / (2 * m), wd = std::sqrt(k / m - gamma * gamma);
  State<1> x0;
  x0.q[0] = 1.0;
  const double A = x0.q[0] - F / k, B = (x0.qd[0] + gamma * A) / wd;
  SimulationOptions o = options(Method::dopri5, 15.0);
  o.output_interval = 0.5;
  Recorder<1> rec;
  const RunReport r = simulate(model, x0, o, rec);
  EXPECT_FALSE(r.conservative);
  for (const auto& s : rec.samples) {
    const double exact = F / k + std::exp(-gamma * s.t) * (A * std::cos(wd * s.t) + B * std::sin(wd * s.t));
    EXPECT_NEAR(s.q[0], exact, 1e-8) << "t = " << s.t;
  }
}

// -- convergence order of rk4 ---------------------------------------------------------

TEST(Simulate, Rk4GlobalErrorFallsSixteenfoldWhenStepHalves) {
  const double w = 3.0;
  const auto osc = harmonic_oscillator(1.0, w * w);
  State<1> x0;
  x0.q[0] = 1.0;
  auto error = [&](double dt) {
    SimulationOptions o = options(Method::rk4, 5.0);
    o.dt = dt;
    o.output_interval = -1;  // initial and final state only
    Recorder<1> rec;
    simulate(osc, x0, o, rec);
    return std::abs(rec.samples.back().q[0] - std::cos(w * 5.0));
  };
  const double e1 = error(0.02), e2 = error(0.01), e3 = error(0.005);
  const double order12 = std::log2(e1 / e2), order23 = std::log2(e2 / e3);
  EXPECT_NEAR(order12, 4.0, 0.2) << e1 << " " << e2;
  EXPECT_NEAR(order23, 4.0, 0.2) << e2 << " " << e3;
}

TEST(Simulate, Rk4ConvergesOnDoublePendulumAgainstTightReference) {
  const DoublePendulum m;
  State<2> x0;
  x0.q << 1.0, 0.5;
  SimulationOptions ref_opt = options(Method::fehlberg78, 3.0, 1e-13);
  ref_opt.atol = 1e-15;
  ref_opt.output_interval = -1;
  Recorder<2> ref;
  simulate(m, x0, ref_opt, ref);
  auto error = [&](double dt) {
    SimulationOptions o = options(Method::rk4, 3.0);
    o.dt = dt;
    o.output_interval = -1;
    Recorder<2> rec;
    simulate(m, x0, o, rec);
    return (rec.samples.back().q - ref.samples.back().q).norm();
  };
  const double e1 = error(4e-3), e2 = error(2e-3);
  EXPECT_NEAR(std::log2(e1 / e2), 4.0, 0.2) << e1 << " " << e2;
}

// -- adaptive steppers: tighter tolerance, smaller error, more work -------------------

TEST(Simulate, AdaptiveSteppersTightenWithTolerance) {
  const auto osc = harmonic_oscillator(1.0, 1.0);
  State<1> x0;
  x0.q[0] = 1.0;
  for (const Method method : {Method::dopri5, Method::cash_karp54, Method::fehlberg78, Method::bulirsch_stoer}) {
    double prev_err = 1e300;
    std::uint64_t prev_evals = 0;
    for (double tol : {1e-6, 1e-9, 1e-12}) {
      SimulationOptions o = options(method, 20.0, tol);
      o.output_interval = -1;
      Recorder<1> rec;
      const RunReport r = simulate(osc, x0, o, rec);
      const double err = std::abs(rec.samples.back().q[0] - std::cos(20.0));
      EXPECT_LT(err, prev_err) << method << " tol " << tol;
      EXPECT_GT(r.rhs_evaluations, prev_evals) << method << " tol " << tol;
      prev_err = err;
      prev_evals = r.rhs_evaluations;
    }
  }
}

TEST(Simulate, StiffStepperHandlesStiffOscillator) {
  // ẍ = −k x with heavy damping c: an overdamped, stiff linear system whose
  // slow mode decays like e^{−(k/c) t}. rosenbrock4 takes few steps.
  const double k = 1.0, c = 1e4;
  auto model = with_dissipation(harmonic_oscillator(1.0, k),
                                [c](const auto&, const auto& qd) { return 0.5 * c * qd[0] * qd[0]; });
  State<1> x0;
  x0.q[0] = 1.0;
  SimulationOptions o = options(Method::rosenbrock4, 100.0, 1e-8);
  o.output_interval = -1;
  Recorder<1> rec;
  const RunReport r = simulate(model, x0, o, rec);
  // Slow root of s² + c s + k = 0: s = (−c + √(c² − 4k))/2; the fast mode has decayed.
  const double s_slow = (-c + std::sqrt(c * c - 4 * k)) / 2;
  const double s_fast = (-c - std::sqrt(c * c - 4 * k)) / 2;
  const double A = x0.q[0] * s_fast / (s_fast - s_slow);  // from x(0) = 1, ẋ(0) = 0
  EXPECT_NEAR(rec.samples.back().q[0], A * std::exp(s_slow * 100.0), 1e-6);
  EXPECT_LT(r.steps, 2000u);
  // An explicit stepper needs orders of magnitude more steps on the same problem.
  o.method = Method::dopri5;
  const RunReport explicit_run = simulate(model, x0, o);
  EXPECT_GT(explicit_run.steps, 20 * r.steps);
}

/// rosenbrock4 on a Lagrangian that depends on time: the driven oscillator
/// L = ½ m ẋ² − ½ k x² + F x cos Ωt, whose closed form is
/// x = A cos ωt + B sin ωt + C cos Ωt, C = F / (m (ω² − Ω²)). At rtol 1e-8 it
/// must be as accurate and take about as many steps as on the same
/// oscillator undriven (F = 0), whose solution has the same smoothness.
TEST(Simulate, Rosenbrock4IsAccurateWhenTheLagrangianDependsOnTime) {
  const double m = 1.0, k = 4.0, F = 0.5, Omega = 1.3;
  auto driven = [&](double force) {
    return make_model<1>(
        "driven_oscillator", {"x"},
        [m](const auto&, const auto& qd, const auto&) { return 0.5 * m * qd[0] * qd[0]; },
        [k, force, Omega](const auto& q, const auto& t) {
          using std::cos;
          return 0.5 * k * q[0] * q[0] - force * q[0] * cos(Omega * t);
        });
  };
  const double w = std::sqrt(k / m);
  State<1> x0;
  x0.q[0] = 0.3;
  x0.qd[0] = -0.2;
  SimulationOptions o = options(Method::rosenbrock4, 20.0, 1e-8);
  o.output_interval = 1.0;
  auto worst_error = [&](double force, const RunReport& r, const Recorder<1>& rec) {
    const double C = force / (m * (w * w - Omega * Omega)), A = x0.q[0] - C, B = x0.qd[0] / w;
    double worst = 0;
    for (const auto& smp : rec.samples)
      worst = std::max(worst, std::abs(smp.q[0] - (A * std::cos(w * smp.t) + B * std::sin(w * smp.t) +
                                                   C * std::cos(Omega * smp.t))));
    EXPECT_EQ(rec.samples.back().t, 20.0);
    (void)r;
    return worst;
  };
  Recorder<1> with_drive, without;
  const RunReport rd = simulate(driven(F), x0, o, with_drive);
  const RunReport ru = simulate(driven(0.0), x0, o, without);
  const double err_driven = worst_error(F, rd, with_drive), err_free = worst_error(0.0, ru, without);
  EXPECT_LT(err_free, 1e-6);
  EXPECT_LT(err_driven, 1e-6);
  EXPECT_LT(rd.steps, 3 * ru.steps) << "driven " << rd.steps << " steps, undriven " << ru.steps;
}

/// The sanity monitor on both sides of its bound, max(1e-2, 100 rtol): an
/// eccentric orbit (e = 0.9, from periapsis r = 0.1, k = m = 1) over 3
/// orbits drifts far beyond it with rk4 at dt = 0.03 s (the periapsis
/// passage takes a few steps) and stays far below it with dopri5 at rtol
/// 1e-10; a run that is not conservative is never flagged.
TEST(Simulate, TheSanityMonitorFlagsAnEnergyDriftNoToleranceExcuses) {
  const KeplerPolar kepler;
  State<2> x0;
  const double e = 0.9, rp = 0.1;
  x0.q << rp, 0.0;
  x0.qd << 0.0, std::sqrt((1 + e) / rp) / rp;  // φ̇ = v_p / r_p, v_p = √(k (1 + e) / (m r_p))
  const double a = rp / (1 - e), period = 2 * kPi * std::pow(a, 1.5);
  SimulationOptions o = options(Method::rk4, 3 * period);
  o.dt = 0.03;
  o.output_interval = 0.05;
  const RunReport coarse = simulate(kepler, x0, o);
  EXPECT_TRUE(coarse.conservative);
  EXPECT_EQ(coarse.drift_bound, 1e-2);
  EXPECT_GT(coarse.energy_drift_max, 1e-2);
  EXPECT_TRUE(coarse.drift_exceeded);
  // rk4 at this step breaks both invariants of the orbit, and the report says which.
  ASSERT_EQ(coarse.monitors.size(), 2u);
  EXPECT_EQ(coarse.monitors[0].name, "energy");
  EXPECT_TRUE(coarse.monitors[0].exceeded);
  EXPECT_EQ(coarse.monitors[1].name, "momentum p_phi");
  EXPECT_TRUE(coarse.monitors[1].exceeded);
  ASSERT_EQ(coarse.warnings.size(), 2u);
  EXPECT_NE(coarse.warnings[0].find("energy drift"), std::string::npos) << coarse.warnings[0];
  EXPECT_NE(coarse.warnings[1].find("p_phi"), std::string::npos) << coarse.warnings[1];
  EXPECT_NE(coarse.to_json().find("\"drift_exceeded\": true"), std::string::npos);

  o.method = Method::dopri5;
  const RunReport fine = simulate(kepler, x0, o);
  EXPECT_LT(fine.energy_drift_max, 1e-7);
  EXPECT_FALSE(fine.drift_exceeded);
  EXPECT_NE(fine.to_json().find("\"drift_exceeded\": false"), std::string::npos);

  // A loose tolerance excuses more: rtol = 1e-3 puts the bound at 0.1.
  o.rtol = 1e-3;
  o.atol = 1e-5;
  EXPECT_DOUBLE_EQ(simulate(kepler, x0, o).drift_bound, 0.1);

  // Damping removes most of the energy: physics, not drift.
  auto damped = with_dissipation(harmonic_oscillator(1.0, 4.0),
                                 [](const auto&, const auto& qd) { return 0.25 * qd[0] * qd[0]; });
  State<1> s0;
  s0.q[0] = 1.0;
  const RunReport decayed = simulate(damped, s0, options(Method::dopri5, 10.0));
  EXPECT_FALSE(decayed.conservative);
  EXPECT_GT(decayed.energy_drift_max, 0.9);
  EXPECT_FALSE(decayed.drift_exceeded);
}

TEST(Simulate, TheMomentumMonitorFlagsADriftWhereTheEnergyIsNotConserved) {
  // An orbit under a radial drag D = ½ c ṙ²: the drag takes energy (no
  // energy monitor) but has no moment, so φ stays cyclic and p_φ = m r² φ̇
  // is conserved. rk4 with steps too long for the periapsis breaks it;
  // dopri5 at its tolerance holds it.
  const double m = 1.0, k = 1.0, c = 0.05;
  const auto orbit = with_dissipation(
      make_model<2>(
          "dragged_orbit", {"r", "phi"},
          [m](const auto& q, const auto& qd, const auto&) { return 0.5 * m * (qd[0] * qd[0] + q[0] * q[0] * qd[1] * qd[1]); },
          [k](const auto& q, const auto&) { return -k / q[0]; }),
      [c](const auto&, const auto& qd) { return 0.5 * c * qd[0] * qd[0]; });
  State<2> x0;
  x0.q << 0.1, 0.0;
  x0.qd << 0.0, std::sqrt(1.9 / 0.1) / 0.1;  // periapsis of an e = 0.9 orbit
  SimulationOptions o = options(Method::rk4, 6.0);
  o.dt = 0.03;
  o.output_interval = 0.05;
  const RunReport coarse = simulate(orbit, x0, o);
  EXPECT_FALSE(coarse.conservative);
  ASSERT_EQ(coarse.conserved_momenta.size(), 1u);
  ASSERT_EQ(coarse.monitors.size(), 1u);  // no energy monitor: the drag does work
  EXPECT_EQ(coarse.monitors[0].name, "momentum p_phi");
  EXPECT_GT(coarse.monitors[0].figure, 1e-2);
  EXPECT_TRUE(coarse.drift_exceeded);
  ASSERT_EQ(coarse.warnings.size(), 1u);
  EXPECT_NE(coarse.warnings[0].find("drift of the conserved momentum p_phi"), std::string::npos) << coarse.warnings[0];

  o.method = Method::dopri5;
  const RunReport fine = simulate(orbit, x0, o);
  ASSERT_EQ(fine.monitors.size(), 1u);
  EXPECT_LT(fine.monitors[0].figure, 1e-7);
  EXPECT_FALSE(fine.drift_exceeded);
}

TEST(Simulate, TheClosedFormMonitorFlagsAnErrorNoToleranceExcuses) {
  // A pendulum at 2 rad with rk4 steps of a fifth of a second: its phase
  // runs away from the exact (Jacobi elliptic) motion; dopri5 follows it.
  const models::SimplePendulum pendulum(1.0, 1.0, 9.81);
  State<1> s;
  s.q << 2.0;
  SimulationOptions o = options(Method::rk4, 20.0);
  o.dt = 0.2;
  o.output_interval = 0.1;
  const RunReport coarse = simulate(pendulum, s, o);
  ASSERT_TRUE(coarse.has_reference);
  const auto closed_form = std::find_if(coarse.monitors.begin(), coarse.monitors.end(),
                                        [](const MonitorVerdict& v) { return v.name == "closed-form error"; });
  ASSERT_NE(closed_form, coarse.monitors.end());
  EXPECT_DOUBLE_EQ(closed_form->figure, coarse.reference_error_max / (1 + coarse.coordinate_scale));
  EXPECT_TRUE(closed_form->exceeded);
  EXPECT_TRUE(coarse.drift_exceeded);

  o.method = Method::dopri5;
  const RunReport fine = simulate(pendulum, s, o);
  EXPECT_LT(fine.reference_error_max, 1e-6);
  EXPECT_FALSE(fine.drift_exceeded);
  for (const MonitorVerdict& v : fine.monitors) EXPECT_FALSE(v.exceeded) << v.name;
}

TEST(Simulate, TheEnergyScaleIsTheEnergyTheMotionMovesAround) {
  // A pendulum let go from the horizontal: T = 0 and V = −m g l cos θ = 0,
  // so h = 0 and the start alone gives no scale (it used to fall back to
  // 1 J, a thousand times the 1e-3 J this pendulum moves between T and V,
  // hiding drift). The scale is the largest |T| + |V| met: 2 m g l at the
  // bottom, where T = m g l and V = −m g l.
  const double m = 1e-3, l = 0.1, g = 9.81, mgl = m * g * l;
  const models::SimplePendulum pendulum(m, l, g);
  State<1> s;
  s.q << kPi / 2;
  SimulationOptions o = options(Method::dopri5, 2.0);
  o.output_interval = 1e-3;
  Recorder<1> rec;
  const RunReport r = simulate(pendulum, s, o, rec);
  EXPECT_NEAR(r.energy_scale, 2 * mgl, 1e-4 * mgl);  // the samples pass within 7e-3 rad of the bottom
  double worst = 0;
  for (const auto& x : rec.samples) worst = std::max(worst, std::abs(x.energy - rec.samples.front().energy));
  EXPECT_GT(worst, 0.0);
  EXPECT_DOUBLE_EQ(r.energy_drift_max, worst / r.energy_scale);
  EXPECT_LT(r.energy_drift_max, 1e-6);
  EXPECT_FALSE(r.drift_exceeded);
}

TEST(Simulate, TheEnergyMonitorMovesItsReferencesByAnImpactFromTheImpactsTimeOn) {
  // The one energy monitor of models, particle scenes and hard spheres. An
  // impact at t = 1 s takes 2 J of T from h0 = E0 = 10 J; a sample the
  // dense output interpolates before it (t = 0.9 s, from the step cut there)
  // still holds the old energy and must show no drift, nor the samples after
  // it that hold 8 J; only the 0.5 J gained after the impact is drift,
  // 0.05 of the scale 10 J (the largest |h| and |T| + |V| met).
  RunReport r;
  lagrangian::detail::EnergyMonitor monitor;
  monitor.start(r, 10.0, 6.0, 4.0);
  monitor.shift(1.0, -2.0, -2.0);
  monitor.sample(r, 0.9, 10.0, 6.0, 4.0);
  EXPECT_EQ(r.energy_drift_max, 0.0);
  monitor.sample(r, 1.0, 8.0, 4.0, 4.0);
  monitor.sample(r, 1.5, 8.0, 4.0, 4.0);
  EXPECT_EQ(r.energy_drift_max, 0.0);
  EXPECT_EQ(r.total_energy_drift_max, 0.0);
  monitor.sample(r, 2.0, 8.5, 4.5, 4.0);
  monitor.finish(r, 2.0);
  EXPECT_DOUBLE_EQ(r.energy_scale, 10.0);
  EXPECT_DOUBLE_EQ(r.energy_drift_max, 0.05);
  EXPECT_DOUBLE_EQ(r.total_energy_drift_max, 0.05);
  EXPECT_DOUBLE_EQ(r.energy_drift_final, 0.05);
  EXPECT_DOUBLE_EQ(r.energy_initial, 10.0);
  EXPECT_DOUBLE_EQ(r.energy_final, 8.5);
  EXPECT_TRUE(r.total_energy_is_h);
  // Without the shift the same samples are 2 J of drift: the test above
  // is not passing for want of a check.
  RunReport unshifted;
  lagrangian::detail::EnergyMonitor plain;
  plain.start(unshifted, 10.0, 6.0, 4.0);
  plain.sample(unshifted, 1.5, 8.0, 4.0, 4.0);
  EXPECT_DOUBLE_EQ(unshifted.energy_drift_max, 0.2);
}

TEST(Simulate, Rosenbrock4HoldsTheKapitzaPendulumUpAsDopri5Does) {
  // Kapitza: a pendulum whose pivot is driven vertically, y_p = a cos Ωt, is stable upside down when
  // a²Ω² > 2 g l (here 16 > 3.9 m²/s²), oscillating about θ = π at √(a²Ω²/(2l²) − g/l) = 12.3 rad/s
  // with the drive's fast ripple on top. rosenbrock4 (its Jacobian by AD, ∂f/∂t included) agrees with
  // dopri5 at a tight tolerance; without the drive the same start falls.
  const DrivenPendulum kapitza(1.0, 0.2, 0.02, 200.0, 9.81);
  State<1> x0;
  x0.q[0] = kPi - 0.1;
  SimulationOptions o = options(Method::rosenbrock4, 2.0, 1e-9);
  o.output_interval = 0.01;
  Recorder<1> stiff, reference;
  simulate(kapitza, x0, o, stiff);
  SimulationOptions ref = options(Method::dopri5, 2.0, 1e-12);
  ref.output_interval = 0.01;
  simulate(kapitza, x0, ref, reference);
  ASSERT_EQ(stiff.samples.size(), reference.samples.size());
  double apart = 0, farthest = 0;
  for (std::size_t k = 0; k < stiff.samples.size(); ++k) {
    apart = std::max(apart, std::abs(stiff.samples[k].q[0] - reference.samples[k].q[0]));
    farthest = std::max(farthest, std::abs(reference.samples[k].q[0] - kPi));
  }
  EXPECT_LT(apart, 1e-5);
  EXPECT_LT(farthest, 0.13);  // it stays up: 0.1 rad plus the ripple
  const DrivenPendulum still(1.0, 0.2, 0.0, 200.0, 9.81);
  Recorder<1> falls;
  simulate(still, x0, o, falls);
  double fallen = 0;
  for (const auto& x : falls.samples) fallen = std::max(fallen, std::abs(x.q[0] - kPi));
  EXPECT_GT(fallen, 1.0);
}

// -- the figures users quote: relative to the initial energy, and what is drift -------------

TEST(Simulate, EnergyDriftIsReportedRelativeToTheInitialEnergy) {
  // A pendulum let go 1.4 rad from the bottom: h0 = −m g l cos 1.4 is 0.17 m g l, while the scale, the
  // largest |T| + |V| met, is m g l (1 + ...) near the bottom: a drift over the scale reads six times
  // smaller than |Δh/h0|, the figure celestial mechanics quotes. A loose tolerance makes the drift real.
  const models::SimplePendulum pendulum(1.0, 1.0, 9.81);
  State<1> s;
  s.q << 1.4;
  SimulationOptions o = options(Method::dopri5, 20.0, 1e-6);
  o.output_interval = 0.01;
  Recorder<1> rec;
  const RunReport r = simulate(pendulum, s, o, rec);
  const double h0 = rec.samples.front().energy, h1 = rec.samples.back().energy;
  double worst = 0;
  for (const auto& x : rec.samples) worst = std::max(worst, std::abs(x.energy - h0));
  ASSERT_GT(std::abs(h1 - h0), 0.0);
  EXPECT_NEAR(r.energy_drift_relative_to_initial(), std::abs(h1 - h0) / std::abs(h0), 1e-12 * std::abs(h1 - h0) / std::abs(h0));
  EXPECT_NEAR(r.energy_drift_relative_to_initial_max(), worst / std::abs(h0), 1e-12 * worst / std::abs(h0));
  EXPECT_GT(r.energy_drift_relative_to_initial(), 5 * r.energy_drift_final);  // not the scale's figure
  // T + V is h here (T quadratic in θ̇, a fixed pivot): the same figure.
  EXPECT_TRUE(r.total_energy_is_h);
  EXPECT_NEAR(r.total_energy_drift_relative_to_initial(), r.energy_drift_relative_to_initial(),
              1e-9 * r.energy_drift_relative_to_initial());
  // The summary says what the figure is relative to, and gives it.
  const std::string text = r.summary();
  char want[96];
  std::snprintf(want, sizeof want, "drift |E - E0|/|E0| max %.2e, final %.2e", worst / std::abs(h0),
                std::abs(h1 - h0) / std::abs(h0));
  EXPECT_NE(text.find(std::string("energy function h: ")), std::string::npos) << text;
  EXPECT_NE(text.find(want), std::string::npos) << text;
  const std::string json = r.to_json();
  EXPECT_NE(json.find("\"energy_drift_relative_to_initial\": "), std::string::npos);
}

TEST(Simulate, AnEnergyTheSystemChangesIsReportedAsAChangeNotADrift) {
  // The driven pendulum: h is not conserved (L depends on t); the summary gives h's change, not a drift.
  const DrivenPendulum driven;
  State<1> x0;
  x0.q[0] = 0.3;
  const RunReport d = simulate(driven, x0, options(Method::dopri5, 2.0));
  ASSERT_FALSE(d.conservative);
  const std::string dt = d.summary();
  EXPECT_EQ(dt.find("drift |E - E0|"), std::string::npos) << dt;
  char change[64];
  std::snprintf(change, sizeof change, "change %+.6g J", d.energy_final - d.energy_initial);
  EXPECT_NE(dt.find(std::string("energy function h: ")), std::string::npos) << dt;
  EXPECT_NE(dt.find(change), std::string::npos) << dt;
  EXPECT_NE(dt.find("not conserved"), std::string::npos) << dt;
  // The rotating hoop conserves h while the motor feeds T + V: T + V is a change, h a drift.
  const BeadOnRotatingHoop hoop(0.1, 0.5, 6.0, 9.81);
  State<1> y0;
  y0.q[0] = 0.05;
  Recorder<1> rec;
  const RunReport h = simulate(hoop, y0, options(Method::dopri5, 5.0), rec);
  ASSERT_TRUE(h.conservative);
  EXPECT_FALSE(h.total_energy_is_h);
  const std::string ht = h.summary();
  EXPECT_NE(ht.find("energy function h: "), std::string::npos) << ht;
  EXPECT_NE(ht.find("drift |E - E0|/|E0|"), std::string::npos) << ht;
  std::snprintf(change, sizeof change, "change %+.6g J",
                rec.samples.back().total_energy - rec.samples.front().total_energy);
  EXPECT_NE(ht.find(std::string("total energy T+V: ")), std::string::npos) << ht;
  EXPECT_NE(ht.find(change), std::string::npos) << ht;
  EXPECT_DOUBLE_EQ(h.total_energy_final, rec.samples.back().total_energy);
}

// -- sampling -------------------------------------------------------------------------

TEST(Simulate, DenseOutputSamplesAreAccurateBetweenSteps) {
  const double w = 2.0;
  const auto osc = harmonic_oscillator(1.0, w * w);
  State<1> x0;
  x0.q[0] = 1.0;
  SimulationOptions o = options(Method::dopri5, 10.0, 1e-12);
  o.output_interval = 1e-3;  // much finer than the steps
  Recorder<1> rec;
  const RunReport r = simulate(osc, x0, o, rec);
  EXPECT_LT(r.steps, rec.samples.size());  // samples between steps came from dense output
  for (const auto& s : rec.samples) EXPECT_NEAR(s.q[0], std::cos(w * s.t), 1e-9) << s.t;
}

/// rk4 takes the step it is given whatever the output grid: dt = 0.05 s over
/// 10 s is 200 steps with samples every 0.01 s (between the steps) and every
/// 0.07 s (off the step grid), and the states on the step grid are those of
/// the run sampled on the steps themselves, bit for bit. Samples between
/// steps are accurate to rk4's own error against x = cos ωt.
TEST(Simulate, Rk4TakesTheStepItWasGivenWhateverTheOutputGrid) {
  const double w = 2.0;
  const auto osc = harmonic_oscillator(1.0, w * w);
  State<1> x0;
  x0.q[0] = 1.0;
  SimulationOptions o = options(Method::rk4, 10.0);
  o.dt = 0.05;
  o.output_interval = 0.05;
  Recorder<1> on_steps;
  const RunReport base = simulate(osc, x0, o, on_steps);
  ASSERT_EQ(base.steps, 200u);
  // rk4's error here is a phase lag of (ω dt)⁵ / 120 per step: (ω dt)⁴ ω t / 120
  // ≈ 1.7e-5 rad at t = 10 s.
  double worst_on_steps = 0;
  for (const auto& smp : on_steps.samples)
    worst_on_steps = std::max(worst_on_steps, std::abs(smp.q[0] - std::cos(w * smp.t)));
  EXPECT_LT(worst_on_steps, 2e-5);
  for (const double interval : {0.01, 0.07}) {
    o.output_interval = interval;
    Recorder<1> rec;
    const RunReport r = simulate(osc, x0, o, rec);
    EXPECT_EQ(r.steps, 200u) << interval;
    EXPECT_EQ(r.samples, rec.samples.size()) << interval;
    const double k_last = std::floor(10.0 / interval + 1e-9);  // the last grid time k Δt ≤ t_end
    const std::size_t expected = static_cast<std::size_t>(k_last) + 1 + (k_last * interval < 10.0 - 1e-9 ? 1 : 0);
    EXPECT_EQ(rec.samples.size(), expected) << interval;  // the grid, and t_end when off it
    EXPECT_EQ(rec.samples.back().q[0], on_steps.samples.back().q[0]) << interval;  // the same steps
    for (const auto& smp : rec.samples) {
      EXPECT_NEAR(smp.q[0], std::cos(w * smp.t), 2 * worst_on_steps) << interval << " at t = " << smp.t;
      EXPECT_NEAR(smp.qd[0], -w * std::sin(w * smp.t), 4 * worst_on_steps) << interval << " at t = " << smp.t;
    }
  }
}

TEST(Simulate, EverySampleOnAcceptedStepsByDefault) {
  const SimplePendulum m;
  State<1> x0;
  x0.q[0] = 0.5;
  Recorder<1> rec;
  const RunReport r = simulate(m, x0, options(Method::cash_karp54, 2.0), rec);
  EXPECT_EQ(rec.samples.size(), r.steps + 1);
  EXPECT_EQ(rec.samples.front().t, 0.0);
  EXPECT_EQ(rec.samples.back().t, 2.0);
  for (std::size_t i = 1; i < rec.samples.size(); ++i) EXPECT_GT(rec.samples[i].t, rec.samples[i - 1].t);
}

TEST(Simulate, ReportJsonNamesItsFields) {
  const KeplerPolar m;
  State<2> x0;
  x0.q << 1.0, 0.0;
  x0.qd << 0.0, 1.0;
  const RunReport r = simulate(m, x0, options(Method::dopri5, 1.0));
  const std::string json = r.to_json();
  for (const char* key : {"\"model\": \"kepler_polar\"", "\"method\": \"dopri5\"", "\"steps\": ", "\"rejected_steps\": ",
                          "\"rhs_evaluations\": ", "\"wall_time_s\": ", "\"energy_drift_max\": ",
                          "\"total_energy_drift_final\": ", "\"conserved_momenta\": [{\"coordinate\": \"phi\""})
    EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
  EXPECT_NE(r.summary().find("momentum of cyclic phi"), std::string::npos);
}

}  // namespace

namespace {

// A model that also supplies its hand-derived q̈: simulate integrates that,
// and the trajectory must agree with the AD-derived one.
struct HandSpherical : lagrangian::models::SphericalPendulum {
  void accelerations(const lagrangian::Vec<double, 2>& q, const lagrangian::Vec<double, 2>& qd, double,
                     lagrangian::Vec<double, 2>& qdd) const {
    const double s = std::sin(q[0]), c = std::cos(q[0]);
    qdd[0] = s * c * qd[1] * qd[1] - (g / l) * s;
    qdd[1] = -2.0 * (c / s) * qd[0] * qd[1];
  }
};

TEST(Simulate, ModelSuppliedAccelerationsAgreeWithAD) {
  static_assert(lagrangian::has_explicit_accelerations_v<HandSpherical>);
  static_assert(!lagrangian::has_explicit_accelerations_v<lagrangian::models::SphericalPendulum>);
  lagrangian::State<2> x0;
  x0.q << 1.0, 0.0;
  x0.qd << 0.0, 2.0;
  lagrangian::SimulationOptions o;
  o.t_end = 5.0;
  o.rtol = 1e-12;
  o.atol = 1e-14;
  o.output_interval = -1;
  lagrangian::Recorder<2> hand, ad;
  const HandSpherical hand_model;
  lagrangian::simulate(hand_model, x0, o, hand);
  lagrangian::simulate(lagrangian::models::SphericalPendulum{}, x0, o, ad);
  EXPECT_LE((hand.samples.back().q - ad.samples.back().q).norm(), 1e-9);
}

/// The harmonic oscillator with its q̈ = −(k/m) x supplied by the model (the
/// right-hand side then skips the AD passes).
struct HandOscillator : lagrangian::models::HarmonicOscillator {
  static constexpr bool structure_preserving = true;  // a derived type is a model of its own: it opts in itself
  using HarmonicOscillator::HarmonicOscillator;
  void accelerations(const lagrangian::Vec<double, 1>& q, const lagrangian::Vec<double, 1>&, double,
                     lagrangian::Vec<double, 1>& qdd) const {
    qdd[0] = -(k / m) * q[0];
  }
};

/// Samples land on t0 + k Δt, on the ends only, or on every step, for every
/// stepper, for both kinds of right-hand side (AD q̈, and a model that
/// supplies q̈), each against x = x0 cos ωt + (v0/ω) sin ωt.
template <class Model>
void expect_samples_on_the_grid(const Model& model) {
  const double w = model.omega(), t0 = 0.3, t_end = 5.3;
  State<1> x0;
  x0.q[0] = 0.7;
  x0.qd[0] = -0.3;
  const auto exact = [&](double t) {
    return x0.q[0] * std::cos(w * (t - t0)) + x0.qd[0] / w * std::sin(w * (t - t0));
  };
  for (const MethodInfo& row : method_table()) {
    const Method method = row.method;
    const bool second_order = method == Method::variational || method == Method::velocity_verlet;
    const double bound = method == Method::rosenbrock4 ? 1e-6 : second_order ? 2e-5 : 1e-7;
    SimulationOptions o = options(method, t_end);
    o.t0 = t0;
    o.dt = 1e-3;
    o.output_interval = 0.25;
    Recorder<1> grid;
    RunReport r = simulate(model, x0, o, grid);
    ASSERT_EQ(grid.samples.size(), 21u) << method;  // t0, t0 + 0.25, …, t_end
    for (std::size_t i = 0; i < grid.samples.size(); ++i) {
      const double t = t0 + 0.25 * static_cast<double>(i);
      EXPECT_NEAR(grid.samples[i].t, t, 1e-12 * (1 + t)) << method << " sample " << i;
      EXPECT_NEAR(grid.samples[i].q[0], exact(grid.samples[i].t), bound) << method << " sample " << i;
    }
    EXPECT_EQ(r.samples, 21u) << method;

    o.output_interval = -1;  // the two ends only
    Recorder<1> ends;
    r = simulate(model, x0, o, ends);
    ASSERT_EQ(ends.samples.size(), 2u) << method;
    EXPECT_EQ(ends.samples.front().t, t0) << method;
    EXPECT_EQ(ends.samples.back().t, t_end) << method;
    EXPECT_NEAR(ends.samples.back().q[0], exact(t_end), bound) << method;

    o.output_interval = 0;  // every accepted step
    Recorder<1> every;
    r = simulate(model, x0, o, every);
    EXPECT_EQ(every.samples.size(), r.steps + 1) << method;
    EXPECT_EQ(every.samples.back().t, t_end) << method;
  }
}

TEST(Simulate, SamplesOnTheOutputGridWithEveryStepperAndBothRightHandSides) {
  static_assert(!lagrangian::has_explicit_accelerations_v<lagrangian::models::HarmonicOscillator>);
  static_assert(lagrangian::has_explicit_accelerations_v<HandOscillator>);
  expect_samples_on_the_grid(lagrangian::models::HarmonicOscillator(0.5, 2.0));
  expect_samples_on_the_grid(HandOscillator(0.5, 2.0));
}

}  // namespace
