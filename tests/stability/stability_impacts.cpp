// Impacts run long: mass ratios 1e-9 … 1e9 with e = 1 and e = 0 over 10⁴
// impacts, grazing impacts at extreme mass ratios, Zeno bouncing with
// e = 0.999 (≈ 1.4e4 impacts before rest) and Newton's cradle between two
// walls over 10⁴ impacts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/impacts.hpp"
#include "stability_helpers.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

/// Largest |T_after − T_before| / T_before over the impacts of a run.
double worst_impact_energy_change(const RunReport& r) {
  double worst = 0;
  for (const auto& e : r.events)
    if (e.kind == EventKind::impact && e.kinetic_energy_before > 0)
      worst = std::max(worst, std::abs(e.kinetic_energy_after - e.kinetic_energy_before) / e.kinetic_energy_before);
  return worst;
}

std::string ratio_name(double ratio) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0e", ratio);
  return buf;
}

// Two spheres in a box, e = 1 on walls and between them, no gravity.
TEST(StabilityImpacts, MassRatiosElasticTenThousandImpacts) {
  const auto target = static_cast<std::uint64_t>(1e4 * stability::length_factor());
  for (double ratio : {1e-9, 1e-6, 1e-3, 1.0, 1e3, 1e6, 1e9}) {
    const SpheresInBox<2> box({1.0, ratio}, {0.1, 0.07}, 1.0, 1.0, 1.0, 1.0);
    State<4> x0;
    x0.q << 0.3, 0.4, 0.7, 0.6;
    x0.qd << 1.0, 0.37, -0.8, 0.55;
    SimulationOptions o;
    o.t_end = 1e5;
    o.output_interval = -1;
    o.max_steps = 10'000'000;
    // Stop at the target number of impacts: a watched count is not part of
    // the model, so run in chunks of simulated time until reached.
    RunReport r;
    Sample<4> last;
    double t_end = 100.0;
    for (;;) {
      o.t_end = t_end;
      r = simulate(box, x0, o, [&](const Sample<4>& s) { last = s; });
      if (r.impacts >= target) break;
      t_end *= 1.2 * static_cast<double>(target) / static_cast<double>(std::max<std::uint64_t>(r.impacts, 1));
    }
    const double worst = worst_impact_energy_change(r);
    // Kinetic energy at the end against the start, without any bookkeeping.
    const double ke_end = box.kinetic(last.q, last.qd, last.t), ke0 = box.kinetic(x0.q, x0.qd, 0.0);
    stability::record("2 spheres in a box, e = 1, mass ratio " + ratio_name(ratio) + ", " + std::to_string(r.impacts) +
                          " impacts: worst relative KE change per impact",
                      "dopri5", worst, 1e-12);
    stability::record("2 spheres in a box, e = 1, mass ratio " + ratio_name(ratio) + ": |T_end - T_0| / T_0",
                      "dopri5", std::abs(ke_end - ke0) / ke0, 1e-10);
    EXPECT_LE(worst, 1e-12) << ratio;
    EXPECT_LE(std::abs(ke_end - ke0) / ke0, 1e-10) << ratio;
  }
}

// e = 0: a plastic impact on a line at every mass ratio — one impact, the
// spheres leave together with the common velocity m1 u / (m1 + m2),
// momentum conserved, kinetic energy reduced by the factor m1 / (m1 + m2).
TEST(StabilityImpacts, PlasticAtEveryMassRatio) {
  double worst_p = 0, worst_v = 0;
  for (double ratio : {1e-9, 1e-6, 1e-3, 1.0, 1e3, 1e6, 1e9}) {
    const SpheresOnLine<2> line({1.0, ratio}, {0.1, 0.1}, 0.0);
    State<2> x0;
    x0.q << 0.0, 1.0;
    x0.qd << 1.0, 0.0;
    SimulationOptions o;
    o.t_end = 2.0;
    o.output_interval = -1;
    Sample<2> last;
    const RunReport r = simulate(line, x0, o, [&](const Sample<2>& s) { last = s; });
    const double v = 1.0 / (1.0 + ratio);
    EXPECT_FALSE(r.events.empty()) << ratio;
    worst_v = std::max({worst_v, std::abs(last.qd[0] - v) / v, std::abs(last.qd[1] - v) / v});
    worst_p = std::max(worst_p, std::abs(last.qd[0] + ratio * last.qd[1] - 1.0));
  }
  stability::record("plastic impact on a line, e = 0, mass ratios 1e-9..1e9: relative error of the common velocity",
                    "dopri5", worst_v, 1e-12);
  stability::record("plastic impact on a line: relative momentum error", "dopri5", worst_p, 1e-12);
  EXPECT_LE(worst_v, 1e-12);
  EXPECT_LE(worst_p, 1e-12);
}

// e = 0 between two spheres in a box with elastic walls, 200 s. At mass
// ratios 1e-9 and 1e9 the light sphere ends up pinned between the heavy one
// and a wall (or two): the sequential rule then needs ~ M/m pairwise impacts
// to settle, and the cycling impacts are replaced by their limit
// (integrate/detail/impact_cycle.hpp). Every run finishes, and the energy the impacts
// took is exactly what the system lost (free flight between impacts keeps
// the rest).
TEST(StabilityImpacts, PlasticPairInABoxFinishesAtEveryMassRatio) {
  double worst = 0;
  for (double ratio : {1e-9, 1.0, 1e9}) {
    const SpheresInBox<2> box({1.0, ratio}, {0.1, 0.07}, 1.0, 1.0, 1.0, 0.0);
    State<4> x0;
    x0.q << 0.3, 0.4, 0.7, 0.6;
    x0.qd << 1.0, 0.37, -0.8, 0.55;
    SimulationOptions o;
    o.t_end = 200.0;
    o.output_interval = -1;
    const RunReport r = simulate(box, x0, o);
    EXPECT_EQ(r.t_final, o.t_end) << "ratio " << ratio;
    EXPECT_GT(r.impacts, 10u) << "ratio " << ratio;
    EXPECT_LE(r.energy_final, r.energy_initial) << "ratio " << ratio;
    const double balance = std::abs(r.energy_initial - r.impact_energy_loss - r.energy_final) / r.energy_initial;
    EXPECT_LE(balance, 1e-9) << "ratio " << ratio;
    worst = std::max(worst, balance);
    std::printf("  e_pair = 0, ratio %g: finished, %llu impacts, E %.6g -> %.6g J\n", ratio,
                static_cast<unsigned long long>(r.impacts), r.energy_initial, r.energy_final);
  }
  stability::record("plastic pair in an elastic box, mass ratios 1e-9..1e9, 200 s: |E0 - loss - E| / E0", "dopri5",
                    worst, 1e-9);
}

// Grazing oblique impacts at extreme mass ratios: sphere 2 at rest, sphere 1
// passing at an offset (1 − δ)(r1 + r2) from its centre line.
TEST(StabilityImpacts, GrazingAtExtremeMassRatios) {
  double worst_p = 0, worst_e = 0;
  for (double ratio : {1e-9, 1.0, 1e9}) {
    for (double delta : {1e-2, 1e-6, 1e-10}) {
      const TwoSpheres<2> model(1.0, ratio, 0.5, 0.5, 1.0);
      State<4> x0;
      x0.q << -2.0, (1.0 - delta) * 1.0, 0.0, 0.0;
      x0.qd << 1.0, 0.0, 0.0, 0.0;
      SimulationOptions o;
      o.t_end = 4.0;
      o.output_interval = -1;
      Sample<4> last;
      const RunReport r = simulate(model, x0, o, [&](const Sample<4>& s) { last = s; });
      EXPECT_EQ(r.impacts, 1u) << ratio << " " << delta;
      const double p0 = 1.0;  // m1 u
      const double px = model.m1 * last.qd[0] + model.m2 * last.qd[2], py = model.m1 * last.qd[1] + model.m2 * last.qd[3];
      worst_p = std::max(worst_p, std::hypot(px - p0, py) / p0);
      worst_e = std::max(worst_e, r.total_energy_drift_max);
    }
  }
  stability::record("grazing impacts, offsets 1 - {1e-2, 1e-6, 1e-10}, mass ratios 1e-9..1e9: relative momentum error",
                    "dopri5", worst_p, 1e-12);
  stability::record("grazing impacts, same: relative energy error", "dopri5", worst_e, 1e-12);
  EXPECT_LE(worst_p, 1e-12);
  EXPECT_LE(worst_e, 1e-12);
}

// Zeno: a ball dropped from h = 1 m with e = 0.999 bounces about 1.4e4 times
// and comes to rest at t∞ = √(2h/g) (1 + e)/(1 − e).
TEST(StabilityImpacts, ZenoBouncingLong) {
  const double e = 0.999, h = 1.0, g = 9.81, R = 0.1;
  const BallAndPlane model(1.0, R, e, g);
  State<3> x0;
  x0.q << 0.0, 0.0, R + h;
  SimulationOptions o;
  const double t_inf = std::sqrt(2 * h / g) * (1 + e) / (1 - e);
  // The Zeno rule (SimulationOptions::zeno_speed_ratio = 1e-6) ends the
  // series at the first impact j whose approach speed e^(j-1) v0 is at most
  // 1e-6 v0: t_j = t_1 + Σ_{k=1}^{j-1} 2 e^k v0 / g, which falls short of
  // t∞ by the (cut-off) rest of the series.
  const double v0 = std::sqrt(2 * g * h);
  double t_expected = std::sqrt(2 * h / g), speed = v0;
  while (speed > o.zeno_speed_ratio * v0) {
    speed *= e;
    t_expected += 2 * speed / g;
  }
  o.t_end = t_inf + 1.0;
  o.output_interval = -1;
  o.max_steps = 10'000'000;
  const RunReport r = simulate(model, x0, o);
  double t_rest = -1;
  for (const auto& ev : r.events)
    if (ev.kind == EventKind::rest) t_rest = ev.t;
  // Each impact is located to event_time_tolerance · |t| (1e-12 relative),
  // so after N impacts the rest time is good to N · 1e-12 relative.
  const double bound = static_cast<double>(r.impacts) * event_time_tolerance;
  stability::record("Zeno bouncing e = 0.999, " + std::to_string(r.impacts) +
                        " impacts: |t_rest - t_series| / t_series (series cut by the Zeno rule)",
                    "dopri5", std::abs(t_rest - t_expected) / t_expected, bound);
  EXPECT_GE(r.impacts, 10000u);
  EXPECT_NEAR(t_rest, t_expected, bound * t_expected);
  EXPECT_NEAR(t_rest, t_inf, 2e-6 * t_inf);  // and t∞ itself to the cut-off
  EXPECT_TRUE(std::isfinite(r.energy_final));
}

// Newton's cradle between two walls: 5 equal touching balls in a box of
// height 2 r (y pinned by the floor and the ceiling), the first moving
// right; each crossing is 4 pairwise impacts and a wall impact.
TEST(StabilityImpacts, NewtonsCradleTenThousandImpacts) {
  constexpr int N = 5;
  const double r = 0.1;
  std::array<double, N> m, rad;
  m.fill(1.0);
  rad.fill(r);
  const SpheresInBox<N> box(m, rad, 2.0, 2 * r + 1e-3, 1.0, 1.0);
  State<2 * N> x0;
  for (int i = 0; i < N; ++i) {
    x0.q[2 * i] = 0.5 + 2 * r * i;
    x0.q[2 * i + 1] = r + 0.5e-3;
  }
  x0.q[0] = 0.3;  // the first ball apart, moving towards the others
  x0.qd[0] = 1.0;
  SimulationOptions o;
  o.t_end = 2100.0 * stability::length_factor();
  o.output_interval = -1;
  o.max_steps = 10'000'000;
  Sample<2 * N> last;
  const RunReport rep = simulate(box, x0, o, [&](const Sample<2 * N>& s) { last = s; });
  const double worst = worst_impact_energy_change(rep);
  // At the end exactly one ball moves, at speed 1 (the others at rest).
  std::vector<double> speeds;
  for (int i = 0; i < N; ++i) speeds.push_back(std::hypot(last.qd[2 * i], last.qd[2 * i + 1]));
  std::sort(speeds.begin(), speeds.end());
  stability::record("Newton's cradle between walls, " + std::to_string(rep.impacts) +
                        " impacts: worst relative KE change per impact",
                    "dopri5", worst, 1e-12);
  stability::record("Newton's cradle: speed of the fastest resting ball at the end (m/s)", "dopri5", speeds[N - 2], 1e-9);
  EXPECT_GE(rep.impacts, static_cast<std::uint64_t>(1e4 * stability::length_factor()));
  EXPECT_LE(worst, 1e-12);
  EXPECT_NEAR(speeds[N - 1], 1.0, 1e-9);
  EXPECT_LE(speeds[N - 2], 1e-9);
}

}  // namespace
