// The discrete Lagrangian, the variational integrator and the symplectic
// steppers: closed forms, convergence order, exact momentum conservation,
// refusals with clear messages.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "lagrangian/integrate/discrete.hpp"
#include "lagrangian/fpe.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

/// m ẍ = −k x, without the opt-in to the structure-preserving methods.
auto plain_oscillator(double m, double k) {
  return make_model<1>(
      "oscillator", {"x"}, [m](const auto&, const auto& qd, const auto&) { return 0.5 * m * qd[0] * qd[0]; },
      [k](const auto& q, const auto&) { return 0.5 * k * q[0] * q[0]; });
}

/// m ẍ = −k x, opted in to the structure-preserving methods.
auto oscillator(double m, double k) { return with_structure_preserving(plain_oscillator(m, k)); }

// L_d of the oscillator by hand. Midpoint: v = (x1 − x0)/h, x̄ = (x0 + x1)/2,
// L_d = h (½ m v² − ½ k x̄²); D1 = −m v − (h k/2) x̄, D2 = m v − (h k/2) x̄,
// D12 = −m/h − h k/4.
TEST(Discrete, MidpointOscillatorByHand) {
  const double m = 2.0, k = 3.0, h = 0.1, x0 = 0.3, x1 = 0.35;
  const auto model = oscillator(m, k);
  const Vec<double, 1> a(x0), b(x1);
  const auto d = discrete_lagrangian_derivatives(model, a, b, 0.0, h);
  const double v = (x1 - x0) / h, xm = 0.5 * (x0 + x1);
  EXPECT_NEAR(d.value, h * (0.5 * m * v * v - 0.5 * k * xm * xm), 1e-15);
  EXPECT_NEAR(d.d1[0], -m * v - 0.5 * h * k * xm, 1e-14);
  EXPECT_NEAR(d.d2[0], m * v - 0.5 * h * k * xm, 1e-14);
  EXPECT_NEAR(d.d12(0, 0), -m / h - 0.25 * h * k, 1e-12);
  EXPECT_NEAR(d.d11(0, 0), m / h - 0.25 * h * k, 1e-12);
  EXPECT_NEAR(d.d22(0, 0), m / h - 0.25 * h * k, 1e-12);
  EXPECT_NEAR(discrete_lagrangian(model, a, b, 0.0, h), d.value, 1e-15);
}

// Trapezoidal: L_d = h (½ m v² − ¼ k (x0² + x1²)); D1 = −m v − (h k/2) x0.
TEST(Discrete, TrapezoidalOscillatorByHand) {
  const double m = 2.0, k = 3.0, h = 0.1, x0 = 0.3, x1 = 0.35;
  const auto model = oscillator(m, k);
  const auto d = discrete_lagrangian_derivatives(model, Vec<double, 1>(x0), Vec<double, 1>(x1), 0.0, h,
                                                 DiscreteRule::trapezoidal);
  const double v = (x1 - x0) / h;
  EXPECT_NEAR(d.value, h * (0.5 * m * v * v - 0.25 * k * (x0 * x0 + x1 * x1)), 1e-15);
  EXPECT_NEAR(d.d1[0], -m * v - 0.5 * h * k * x0, 1e-14);
  EXPECT_NEAR(d.d2[0], m * v - 0.5 * h * k * x1, 1e-14);
  EXPECT_NEAR(d.d12(0, 0), -m / h, 1e-12);
}

// Non-separable L: slot derivatives against central differences of L_d.
TEST(Discrete, DoublePendulumDerivativesAgainstDifferences) {
  const DoublePendulum model;
  Vec<double, 2> a, b;
  a << 0.4, -1.1;
  b << 0.43, -1.05;
  const double h = 0.02, t = 0.0, eps = 1e-6;
  for (auto rule : {DiscreteRule::midpoint, DiscreteRule::trapezoidal}) {
    const auto d = discrete_lagrangian_derivatives(model, a, b, t, h, rule);
    for (int i = 0; i < 2; ++i) {
      Vec<double, 2> ap = a, am = a, bp = b, bm = b;
      ap[i] += eps;
      am[i] -= eps;
      bp[i] += eps;
      bm[i] -= eps;
      const double fd1 =
          (discrete_lagrangian(model, ap, b, t, h, rule) - discrete_lagrangian(model, am, b, t, h, rule)) / (2 * eps);
      const double fd2 =
          (discrete_lagrangian(model, a, bp, t, h, rule) - discrete_lagrangian(model, a, bm, t, h, rule)) / (2 * eps);
      EXPECT_NEAR(d.d1[i], fd1, 1e-6 * (1 + std::abs(fd1))) << to_string(rule);
      EXPECT_NEAR(d.d2[i], fd2, 1e-6 * (1 + std::abs(fd2))) << to_string(rule);
      for (int j = 0; j < 2; ++j) {
        // ∂(D1_j)/∂q1_i by differences of the AD D1.
        const double fd12 = (discrete_lagrangian_derivatives(model, a, bp, t, h, rule).d1[j] -
                             discrete_lagrangian_derivatives(model, a, bm, t, h, rule).d1[j]) /
                            (2 * eps);
        EXPECT_NEAR(d.d12(j, i), fd12, 1e-4 * (1 + std::abs(fd12))) << to_string(rule);
      }
    }
  }
}

SimulationOptions fixed(Method method, double dt, double t_end) {
  SimulationOptions o;
  o.method = method;
  o.dt = dt;
  o.t_end = t_end;
  return o;
}

/// Final-position error of the oscillator x(0) = 1, v(0) = 0 at t = 2 (ω = 1).
double oscillator_error(Method method, double dt, const std::string& rule = "midpoint") {
  const auto model = oscillator(1.0, 1.0);
  State<1> x0;
  x0.q[0] = 1.0;
  SimulationOptions o = fixed(method, dt, 2.0);
  o.discrete_rule = rule;
  double x_end = 0;
  simulate(model, x0, o, [&](const Sample<1>& s) { x_end = s.q[0]; });
  return std::abs(x_end - std::cos(2.0));
}

TEST(Variational, SecondOrderOnTheOscillator) {
  for (const std::string rule : {"midpoint", "trapezoidal"}) {
    const double e1 = oscillator_error(Method::variational, 0.02, rule), e2 = oscillator_error(Method::variational, 0.01, rule);
    EXPECT_NEAR(std::log2(e1 / e2), 2.0, 0.1) << rule;
    EXPECT_LT(e2, 1e-4) << rule;
  }
}

TEST(Symplectic, OrdersOnTheOscillator) {
  const double v1 = oscillator_error(Method::velocity_verlet, 0.02), v2 = oscillator_error(Method::velocity_verlet, 0.01);
  EXPECT_NEAR(std::log2(v1 / v2), 2.0, 0.1);
  const double m1 = oscillator_error(Method::symplectic_rkn_sb3a_mclachlan, 0.1),
               m2 = oscillator_error(Method::symplectic_rkn_sb3a_mclachlan, 0.05);
  EXPECT_NEAR(std::log2(m1 / m2), 4.0, 0.2);
}

// p_φ of the Kepler problem in polar coordinates is conserved by the
// variational step exactly up to the Newton residual, while dopri5 at the
// same cost lets it drift; energy is bounded.
TEST(Variational, CyclicMomentumConservedExactly) {
  const KeplerPolar model(1.0, 1.0);
  State<2> x0;
  x0.q << 1.0, 0.0;
  x0.qd << 0.0, 1.2;  // an ellipse
  SimulationOptions o = fixed(Method::variational, 1e-2, 200.0);
  const RunReport r = simulate(model, x0, o);
  ASSERT_EQ(r.conserved_momenta.size(), 1u);
  EXPECT_EQ(r.conserved_momenta[0].coordinate, "phi");
  EXPECT_LE(r.conserved_momenta[0].max_abs_drift, 1e-13);
  EXPECT_LE(r.energy_drift_max, 1e-3);
  EXPECT_EQ(r.steps, 20000u);
  EXPECT_GE(r.newton_iterations, 2 * r.steps);
  EXPECT_NE(r.to_json().find("\"newton_iterations\""), std::string::npos);
  EXPECT_NE(r.summary().find("Newton iterations"), std::string::npos);
}

TEST(Variational, SamplesBetweenStepsAndAShortLastStep) {
  const auto model = oscillator(1.0, 1.0);
  State<1> x0;
  x0.q[0] = 1.0;
  SimulationOptions o = fixed(Method::variational, 0.003, 1.0);
  o.output_interval = 0.1;
  std::vector<Sample<1>> samples;
  const RunReport r = simulate(model, x0, o, [&](const Sample<1>& s) { samples.push_back(s); });
  ASSERT_EQ(samples.size(), 11u);
  EXPECT_DOUBLE_EQ(samples.back().t, 1.0);
  for (const auto& s : samples) EXPECT_NEAR(s.q[0], std::cos(s.t), 1e-5) << s.t;
  EXPECT_EQ(r.steps, 334u);  // 333 steps of 0.003 s and one of 0.001 s
  EXPECT_FALSE(r.adaptive);
}

TEST(Symplectic, RefusedForANonSeparableModel) {
  const DoublePendulum model;
  State<2> x0;
  x0.q << 1.0, 1.0;
  for (const Method m : {Method::velocity_verlet, Method::symplectic_rkn_sb3a_mclachlan}) {
    try {
      simulate(model, x0, fixed(m, 1e-3, 1.0));
      FAIL() << m << " ran a double pendulum";
    } catch (const OptionError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("needs a separable model"), std::string::npos) << what;
      EXPECT_NE(what.find("mass matrix"), std::string::npos) << what;
    }
  }
}

/// An oscillator that declares itself not separable (declarations are trusted).
struct Declared {
  static constexpr int dof = 1;
  static constexpr bool separable = false;
  static constexpr bool structure_preserving = true;
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    return 0.5 * q[0] * q[0];
  }
};

TEST(Symplectic, DeclaredSeparableIsTrustedAndDeclaredFalseRefused) {
  State<1> x0;
  x0.q[0] = 1.0;
  try {
    simulate(Declared{}, x0, fixed(Method::velocity_verlet, 1e-2, 1.0));
    FAIL() << "velocity_verlet ran a model declared not separable";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("declares separable = false"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(separability_problem(oscillator(1.0, 2.0), x0).empty());
  const SphericalPendulum sp;
  State<2> s2;
  s2.q << 1.0, 0.0;
  EXPECT_FALSE(separability_problem(sp, s2).empty());
}

TEST(Variational, NewtonFailureIsAClearErrorNotANaN) {
  // A stiff oscillator with a step far beyond its period: the midpoint rule
  // stays solvable (it is linear), so use a strongly nonlinear potential.
  auto model = with_structure_preserving(make_model<1>(
      "quartic", {"x"}, [](const auto&, const auto& qd, const auto&) { return 0.5 * qd[0] * qd[0]; },
      [](const auto& q, const auto&) { return 1e6 * q[0] * q[0] * q[0] * q[0]; }));
  State<1> x0;
  x0.q[0] = 1.0;
  SimulationOptions o = fixed(Method::variational, 1.0, 10.0);
  o.newton_max_iterations = 5;
  try {
    simulate(model, x0, o);
    FAIL() << "no error";
  } catch (const SimulationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("variational step"), std::string::npos) << what;
    EXPECT_NE(what.find("t = "), std::string::npos) << what;
    EXPECT_EQ(what.find("nan"), std::string::npos) << what;
  }
}

TEST(StructurePreserving, AModelThatDidNotOptInIsToldHow) {
  // Without the opt-in the variational integrator (compiled per model) is
  // refused with the way to opt in; the symplectic steppers run in the
  // driver and need none, nor do the adaptive methods. Each method that
  // runs keeps the oscillator's energy (the fixed-step ones to O(h²) here).
  const auto plain = plain_oscillator(1.0, 1.0);
  static_assert(!structure_preserving_v<decltype(plain)>);
  static_assert(structure_preserving_v<decltype(oscillator(1.0, 1.0))>);
  State<1> x0;
  x0.q[0] = 1.0;
  try {
    simulate(plain, x0, fixed(Method::variational, 1e-2, 1.0));
    FAIL() << "variational ran a model that did not opt in";
  } catch (const OptionError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("static constexpr bool structure_preserving = true;"), std::string::npos) << what;
    EXPECT_NE(what.find("with_structure_preserving"), std::string::npos) << what;
    EXPECT_NE(what.find("'variational'"), std::string::npos) << what;
  }
  EXPECT_LE(simulate(oscillator(1.0, 1.0), x0, fixed(Method::variational, 1e-2, 1.0)).energy_drift_max, 1e-4);
  for (const Method m : {Method::symplectic_rkn_sb3a_mclachlan, Method::velocity_verlet}) {
    const RunReport r = simulate(plain, x0, fixed(m, 1e-2, 1.0));
    EXPECT_LE(r.energy_drift_max, 1e-4) << m;
    EXPECT_GT(r.energy_drift_max, 0.0) << m;  // a real run: the fixed step leaves an O(h²) error
  }
  SimulationOptions o = fixed(Method::dopri5, 1e-2, 1.0);
  EXPECT_LE(simulate(plain, x0, o).energy_drift_max, 1e-9);
}

TEST(Variational, OptionsAreChecked) {
  const auto model = oscillator(1.0, 1.0);
  State<1> x0;
  SimulationOptions o = fixed(Method::variational, 1e-2, 1.0);
  o.discrete_rule = "simpson";
  EXPECT_THROW(simulate(model, x0, o), OptionError);
  o.discrete_rule = "midpoint";
  o.newton_tolerance = 0;
  EXPECT_THROW(simulate(model, x0, o), OptionError);
  o.newton_tolerance = 1e-12;
  o.newton_max_iterations = 0;
  EXPECT_THROW(simulate(model, x0, o), OptionError);
}

}  // namespace

namespace {

// The FE_INVALID trap stops the program where the first NaN is made.
TEST(FloatingPointTrapDeathTest, FirstNaNRaisesSigfpe) {
  if (!lagrangian::FloatingPointTrap::supported) GTEST_SKIP() << "no feenableexcept";
  volatile double zero = 0.0;
  EXPECT_DEATH(
      {
        const lagrangian::FloatingPointTrap trap;
        volatile double nan = zero / zero;
        (void)nan;
      },
      "");
  // Outside the scope the same operation is quiet.
  volatile double quiet = zero / zero;
  EXPECT_TRUE(std::isnan(quiet));
}

}  // namespace
