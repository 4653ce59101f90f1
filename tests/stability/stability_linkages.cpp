// Singular and redundant constraint configurations: a four-bar linkage
// (a parallelogram) that passes through the collinear pose where its two
// assembly branches cross, and a pendulum whose rod is declared twice.
// Detected, reported, and the run finishes — never a NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"
#include "stability_helpers.hpp"

namespace {

using namespace lagrangian;

/// Planar four-bar linkage in a horizontal plane (no gravity): ground pivots
/// A = (0, 0) and B = (d, 0); crank AC (length l1, angle θ1), coupler CD
/// (l2, θ2), rocker BD (l3, θ3), each a uniform rod of mass m (kg).
///   T = ½ (m l1²/3) θ̇1² + ½ m |v_mid,CD|² + ½ (m l2²/12) θ̇2² + ½ (m l3²/3) θ̇3²,  V = 0,
///   loop closure: l1 cos θ1 + l2 cos θ2 − l3 cos θ3 − d = 0,
///                 l1 sin θ1 + l2 sin θ2 − l3 sin θ3 = 0.
/// With l1 = l3 and l2 = d (a parallelogram) the Jacobian drops to rank 1
/// when all links are collinear (θ1 = θ2 = θ3 = 0 or the crank at π).
struct FourBar {
  static constexpr int dof = 3;
  static constexpr bool structure_preserving = true;  // runs with method variational
  double m = 1.0, l1 = 1.0, l2 = 2.0, l3 = 1.0, d = 2.0;
  std::string name() const { return "four_bar"; }
  std::array<std::string, 2> holonomic_names() const { return {"loop_x", "loop_y"}; }
  template <class S>
  S kinetic(const Vec<S, 3>& q, const Vec<S, 3>& qd, const S&) const {
    using std::cos;
    using std::sin;
    const S vx = -l1 * sin(q[0]) * qd[0] - 0.5 * l2 * sin(q[1]) * qd[1];
    const S vy = l1 * cos(q[0]) * qd[0] + 0.5 * l2 * cos(q[1]) * qd[1];
    return 0.5 * m * l1 * l1 / 3.0 * qd[0] * qd[0] + 0.5 * m * (vx * vx + vy * vy) +
           0.5 * m * l2 * l2 / 12.0 * qd[1] * qd[1] + 0.5 * m * l3 * l3 / 3.0 * qd[2] * qd[2];
  }
  template <class S>
  S potential(const Vec<S, 3>&, const S&) const {
    return S(0);
  }
  template <class S>
  Vec<S, 2> holonomic(const Vec<S, 3>& q, const S&) const {
    using std::cos;
    using std::sin;
    return Vec<S, 2>(l1 * cos(q[0]) + l2 * cos(q[1]) - l3 * cos(q[2]) - d,
                     l1 * sin(q[0]) + l2 * sin(q[1]) - l3 * sin(q[2]));
  }
};

/// The parallelogram a little before the collinear pose, crank turning at
/// 1 rad/s: θ1 = θ3 = −0.30037, θ2 = 0, θ̇1 = θ̇3 = 1, θ̇2 = 0 (no step or
/// sample lands on the pose itself).
State<3> before_collinear() {
  State<3> x0;
  x0.q << -0.30037, 0.0, -0.30037;
  x0.qd << 1.0, 0.0, 1.0;
  return x0;
}

// The run goes through the singular pose and finishes: the pose is seen and
// reported, the constraints hold, nothing is NaN.
void expect_detected_and_finished(const RunReport& r, Method method) {
  EXPECT_LT(r.constraints.min_conditioning, 1e-3) << method;
  bool warned = false;
  for (const auto& w : r.constraints.warnings) warned = warned || w.find("near-singular") != std::string::npos;
  EXPECT_TRUE(warned) << method << "\n" << r.summary();
  EXPECT_TRUE(std::isfinite(r.energy_final)) << method;
  EXPECT_LE(r.constraints.max_position_residual, 1e-8) << method;
  stability::record("four-bar parallelogram through the collinear pose: min sigma_r/sigma_1 (detected)", method,
                    r.constraints.min_conditioning, 1e-3);
  stability::record("four-bar parallelogram through the collinear pose: max |g|", method,
                    r.constraints.max_position_residual, 1e-8);
}

TEST(StabilityLinkages, FourBarThroughTheSingularPose) {
  const FourBar model;
  for (const Method method : {Method::dopri5, Method::variational}) {
    SimulationOptions o;
    o.method = method;
    o.t_end = 2.0;  // θ1 passes 0 at t ≈ 0.3 s
    o.dt = 1e-3;
    o.output_interval = 1e-3;
    expect_detected_and_finished(simulate(model, before_collinear(), o), method);
  }
}

/// The Cartesian pendulum with its rod declared twice.
struct DoubledRod : models::CartesianPendulum {
  static constexpr bool structure_preserving = true;  // runs with method variational
  std::array<std::string, 2> holonomic_names() const { return {"rod", "rod_again"}; }
  std::array<std::string, 2> constraint_units() const { return {"m", "m"}; }  // the base class declares one
  template <class S>
  Vec<S, 2> holonomic(const Vec<S, 2>& q, const S& t) const {
    const S g = models::CartesianPendulum::holonomic(q, t)[0];
    return Vec<S, 2>(g, g);
  }
};

TEST(StabilityLinkages, DuplicatedConstraintReportedAndHarmless) {
  const DoubledRod model;
  State<2> x0;
  x0.q << std::sin(1.0), -std::cos(1.0);
  for (const Method method : {Method::dopri5, Method::variational}) {
    SimulationOptions o;
    o.method = method;
    o.t_end = 200.0;
    o.dt = 1e-2;
    o.output_interval = 0.1;
    double tension_error = 0;
    const RunReport r = simulate(model, x0, o, [&](const Sample<2>& s) {
      // The two equal rows share the rod's force: λ1 = λ2 (minimum norm).
      tension_error = std::max(tension_error, std::abs(s.multipliers[0] - s.multipliers[1]));
    });
    bool redundant = false;
    for (const auto& w : r.constraints.warnings) redundant = redundant || w.find("rod_again is redundant") != std::string::npos;
    EXPECT_TRUE(redundant) << method << "\n" << r.summary();
    EXPECT_LE(r.constraints.max_position_residual, 1e-10) << method;
    EXPECT_LE(tension_error, 1e-9) << method;
    EXPECT_TRUE(std::isfinite(r.energy_final));
    stability::record("pendulum with its rod declared twice, 200 s: max |g| (redundancy reported)", method,
                      r.constraints.max_position_residual, 1e-10);
  }
}

}  // namespace
