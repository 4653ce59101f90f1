// Double pendulum at high energy for 100 s (adaptive: drift ≤ 1e-9;
// variational: bounded) and the Cartesian pendulum on a rod for 10⁴
// periods (residual ≤ 1e-10 with projection and with the constrained
// variational integrator).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "stability_helpers.hpp"

namespace {

using namespace lagrangian;

/// θ1 = θ2 = 3 rad with θ̇2 = 4 rad/s: above the energy needed to turn over.
State<2> high_energy() {
  State<2> x0;
  x0.q << 3.0, 3.0;
  x0.qd << 0.0, 4.0;
  return x0;
}

TEST(StabilityDoublePendulum, AdaptiveDriftBelow1e9) {
  const models::DoublePendulum model;
  for (const Method method : {Method::dopri5, Method::fehlberg78}) {
    SimulationOptions o;
    o.method = method;
    o.t_end = 100.0;
    o.rtol = 1e-12;
    o.atol = 1e-14;
    const RunReport r = simulate(model, high_energy(), o);
    stability::record("double pendulum, high energy, t = 100 s, relative energy drift",
                      std::string(to_string(method)) + " rtol 1e-12", r.energy_drift_max, 1e-9);
    EXPECT_LE(r.energy_drift_max, 1e-9) << method;
  }
}

TEST(StabilityDoublePendulum, VariationalBounded) {
  const models::DoublePendulum model;
  SimulationOptions o;
  o.method = Method::variational;
  o.dt = 1e-3;
  o.t_end = 100.0;
  stability::WindowedEnergy<2> energy{10.0};
  const RunReport r = simulate(model, high_energy(), o, energy);
  const double first = energy.max_over(0, 1), last = energy.max_over(9, 10);
  stability::record("double pendulum, high energy, t = 100 s, max energy error last 10 s / first 10 s",
                    "variational midpoint dt 1e-3", last / first, 2.0);
  stability::record("double pendulum, high energy, t = 100 s, max relative energy error", "variational midpoint dt 1e-3",
                    r.energy_drift_max, 1e-3);
  EXPECT_LE(last, 2.0 * first);
  EXPECT_LE(r.energy_drift_max, 1e-3);
}

/// The rod at 60° from the downward vertical, at rest.
State<2> on_the_rod() {
  State<2> x0;
  x0.q << std::sin(1.0), -std::cos(1.0);
  return x0;
}
constexpr double kPeriodSmall = 2 * std::numbers::pi * 0.31927542840705496;  // 2π √(l/g), l = 1, g = 9.81

TEST(StabilityCartesianPendulum, ProjectionResidualBelow1e10) {
  const models::CartesianPendulum model;
  SimulationOptions o;
  o.method = Method::dopri5;
  o.t_end = 1e4 * kPeriodSmall * stability::length_factor(0.05);  // 500 periods under the sanitizers
  o.rtol = 1e-10;
  o.atol = 1e-12;
  o.stabilization = Stabilization::projection;
  o.output_interval = -1;
  const RunReport r = simulate(model, on_the_rod(), o);
  stability::record("Cartesian pendulum on a rod, 1e4 periods, max |g|", "dopri5 + projection",
                    r.constraints.max_position_residual, 1e-10);
  EXPECT_LE(r.constraints.max_position_residual, 1e-10);
  EXPECT_LE(r.constraints.max_velocity_residual, 1e-10);
}

TEST(StabilityCartesianPendulum, ConstrainedVariationalResidualBelow1e10) {
  const models::CartesianPendulum model;
  SimulationOptions o;
  o.method = Method::variational;
  o.dt = 1e-2;
  o.t_end = 1e4 * kPeriodSmall * stability::length_factor(0.05);  // 500 periods under the sanitizers
  o.output_interval = 1.0;  // energy sampled every second
  const RunReport r = simulate(model, on_the_rod(), o);
  stability::record("Cartesian pendulum on a rod, 1e4 periods, max |g|", "constrained variational dt 1e-2",
                    r.constraints.max_position_residual, 1e-10);
  stability::record("Cartesian pendulum on a rod, 1e4 periods, relative energy error", "constrained variational dt 1e-2",
                    r.energy_drift_max, 1e-3);
  EXPECT_LE(r.constraints.max_position_residual, 1e-10);
  EXPECT_LE(r.constraints.max_velocity_residual, 1e-10);
  EXPECT_LE(r.energy_drift_max, 1e-3);
  EXPECT_EQ(r.constraints.projections, 0u);  // the integrator holds the rod itself
}

}  // namespace
