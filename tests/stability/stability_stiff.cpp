// A stiff spring (k/m = 1e8 1/s²) coupled to a soft one: rosenbrock4
// finishes in few steps with the energy bounded; an explicit stepper is
// reported as inefficient (its step count and a stiffness warning), not
// silently slow. The symplectic steppers run the same separable model.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "stability_helpers.hpp"

namespace {

using namespace lagrangian;

/// Two unit masses on a line (kg): x1 held to the wall by a stiff spring
/// k_s, x2 joined to x1 by a soft spring k (N/m).
///   T = ½ (ẋ1² + ẋ2²),  V = ½ k_s x1² + ½ k (x2 − x1)².
struct StiffSprings {
  static constexpr int dof = 2;
  static constexpr bool structure_preserving = true;  // runs with the symplectic steppers
  double ks = 1e8, k = 1.0;
  std::string name() const { return "stiff_springs"; }
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return 0.5 * ks * q[0] * q[0] + 0.5 * k * (q[1] - q[0]) * (q[1] - q[0]);
  }
};

/// The soft spring stretched by 1 m, the stiff one at its quasi-static
/// position x1 = k x2 / (k_s + k), all at rest.
State<2> start() {
  State<2> x0;
  x0.q << 1.0 / (1e8 + 1.0), 1.0;
  return x0;
}

SimulationOptions run(const std::string& method) {
  SimulationOptions o;
  o.method = method;
  o.t_end = 20.0;  // about three periods of the soft mode (2π s)
  o.rtol = 1e-6;
  o.atol = 1e-9;
  o.dt = 1e-3;
  o.output_interval = 0.5;  // samples do not cut the stiff stepper's steps short
  return o;
}

/// A hundredth of the ≈ 6e4 steps an explicit method needs for stability.
constexpr std::uint64_t kStiffStepBound = 600;

TEST(StabilityStiff, Rosenbrock4FinishesInFewStepsEnergyBounded) {
  const RunReport r = simulate(StiffSprings{}, start(), run("rosenbrock4"));
  stability::record("stiff springs k/m = 1e8, t = 20 s, accepted steps", "rosenbrock4 rtol 1e-6",
                    static_cast<double>(r.steps), static_cast<double>(kStiffStepBound));
  stability::record("stiff springs k/m = 1e8, t = 20 s, relative energy error", "rosenbrock4 rtol 1e-6",
                    r.energy_drift_max, 1e-3);
  EXPECT_LE(r.steps, kStiffStepBound);
  EXPECT_LE(r.energy_drift_max, 1e-3);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(StabilityStiff, ExplicitStepperReportedInefficient) {
  const RunReport stiff = simulate(StiffSprings{}, start(), run("rosenbrock4"));
  const RunReport r = simulate(StiffSprings{}, start(), run("dopri5"));
  stability::record("stiff springs k/m = 1e8, t = 20 s, accepted steps (warned as stiff)", "dopri5 rtol 1e-6",
                    static_cast<double>(r.steps), 0);
  // Stability bound of dopri5: h ω ≲ 3.3 with ω = 1e4 1/s, so at least
  // 20 s · 1e4 / 3.3 ≈ 6e4 steps, whatever the tolerance.
  EXPECT_GE(r.steps, 50000u);
  EXPECT_GE(r.steps, 20 * stiff.steps);
  EXPECT_NEAR(r.stiffness_rho, 1e4, 1e2);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("stiff problem"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.summary().find("rosenbrock4"), std::string::npos);
  EXPECT_NE(r.to_json().find("stiff problem"), std::string::npos);
  // The warning's test of stability-limited steps holds: a thousand times
  // tighter, the step count barely moves (accuracy-limited, it would grow
  // about 1000^(1/5) = 4 times).
  SimulationOptions tight = run("dopri5");
  tight.rtol = 1e-9;
  tight.atol = 1e-12;
  const RunReport t = simulate(StiffSprings{}, start(), tight);
  EXPECT_LT(static_cast<double>(t.steps), 1.1 * static_cast<double>(r.steps));
}

TEST(StabilityStiff, NonStiffRunIsNotWarned) {
  StiffSprings soft;
  soft.ks = 1.0;
  const RunReport r = simulate(soft, start(), run("dopri5"));
  EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
  EXPECT_GT(r.stiffness_rho, 0.5);
  EXPECT_LT(r.stiffness_rho, 3.0);  // ω² = (3 ± √5)/2 for k_s = k = 1
}

TEST(StabilityStiff, SymplecticStepsBoundedEnergy) {
  // Separable (constant M): both symplectic steppers run it; at h ω = 0.5
  // the energy error stays bounded over 4e5 steps.
  for (const char* method : {"velocity_verlet", "symplectic_rkn_sb3a_mclachlan"}) {
    SimulationOptions o;
    o.method = method;
    o.dt = 5e-5;
    o.t_end = 20.0 * stability::length_factor();
    o.output_interval = 0.01;
    State<2> x0 = start();
    x0.q[0] = 1e-4;  // the stiff mode excited
    stability::WindowedEnergy<2> energy{o.t_end / 10};
    const RunReport r = simulate(StiffSprings{}, x0, o, energy);
    const double first = energy.max_over(0, 1), last = energy.max_over(9, 10);
    stability::record("stiff springs, stiff mode excited, max energy error last / first tenth", method, last / first, 2.0);
    EXPECT_LE(last, 2.0 * first) << method;
    EXPECT_LE(r.energy_drift_max, 0.1) << method;
  }
}

}  // namespace
