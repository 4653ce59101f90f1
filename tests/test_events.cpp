// Located events in runs: impact times, the Zeno accumulation, a box of
// perfectly elastic spheres, Newton's cradle, an impact at t0. The edge
// cases are in test_events_edge.cpp.
#include <cmath>
#include <cstdio>
#include <string>

#include "event_helpers.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;
using lagrangian_test::dropped;
using lagrangian_test::kEventTime;

TEST(Events, ADroppedBallHitsAtTheFreeFallTimeWithEveryStepper) {
  const double g = 9.81, R = 0.1;
  const BallAndPlane ball(1.0, R, 1.0, g);
  for (const Method method : {Method::dopri5, Method::cash_karp54, Method::fehlberg78, Method::bulirsch_stoer, Method::gauss_radau15, Method::rk4, Method::rosenbrock4}) {
    for (double h : {0.05, 1.0, 20.0}) {
      SimulationOptions o;
      o.method = method;
      o.t_end = 1.5 * std::sqrt(2 * h / g);
      o.dt = 1e-2;
      o.output_interval = -1;
      const RunReport r = simulate(ball, dropped(h + R), o);
      ASSERT_GE(r.events.size(), 1u) << method << " h " << h;
      EXPECT_EQ(r.events[0].kind, EventKind::impact);
      EXPECT_EQ(r.events[0].name, "ball-plane");
      EXPECT_NEAR(r.events[0].t, ball.drop_time(h), kEventTime) << method << " h " << h;
      EXPECT_NEAR(r.events[0].approach_speed, std::sqrt(2 * g * h), 1e-9 * std::sqrt(2 * g * h)) << method;
      EXPECT_NEAR(r.events[0].separation_speed, r.events[0].approach_speed, 1e-9 * std::sqrt(2 * g * h)) << method;
      EXPECT_NEAR(r.events[0].impulse, 2 * std::sqrt(2 * g * h), 1e-9 * std::sqrt(2 * g * h)) << method;
    }
  }
}

TEST(Events, ABallThrownAtAWallBouncesOffItByNewtonsLaw) {
  // Wall x = 2 m (normal −x, through x = 2), ball of radius 0.1 m thrown from
  // x = 0 at (3, 0.5, 4) m/s: it touches at t = (2 − 0.1)/3 s; then the
  // normal component reverses with factor e, the others are kept.
  const double e = 0.7, g = 9.81, R = 0.1;
  const BallAndPlane wall(0.4, R, e, g, {-1.0, 0.0, 0.0}, -2.0);
  State<3> s;
  s.q << 0.0, 0.0, 1.0;
  s.qd << 3.0, 0.5, 4.0;
  SimulationOptions o;
  o.t_end = 1.0;
  o.output_interval = -1;
  Recorder<3> rec;
  const RunReport r = simulate(wall, s, o, rec);
  ASSERT_EQ(r.impacts, 1u);
  const double t_hit = (2.0 - R) / 3.0;
  EXPECT_NEAR(r.events[0].t, t_hit, kEventTime);
  const auto v = wall.bounce_velocity({3.0, 0.5, 4.0 - g * t_hit});
  const auto& end = rec.samples.back();
  EXPECT_NEAR(end.qd[0], v[0], 1e-12);
  EXPECT_NEAR(end.qd[0], -e * 3.0, 1e-12);
  EXPECT_NEAR(end.qd[1], v[1], 1e-12);
  EXPECT_NEAR(end.qd[2], v[2] - g * (1.0 - t_hit), 1e-9);
  EXPECT_NEAR(end.q[0], 2.0 - R - e * 3.0 * (1.0 - t_hit), 1e-9);
}

TEST(Events, ZenoBouncesFollowTheGeometricSeriesThenTheBallRests) {
  // e = 0.5 from h = 1 m: t_1 = √(2h/g), then each flight lasts 2 e^k v_1 / g.
  const double g = 9.81, R = 0.1, e = 0.5, h = 1.0, m = 1.0;
  const BallAndPlane ball(m, R, e, g);
  SimulationOptions o;
  o.t_end = 10.0;
  o.output_interval = 0.5;
  Recorder<3> rec;
  const RunReport r = simulate(ball, dropped(h + R), o, rec);
  double t_k = std::sqrt(2 * h / g), v_k = std::sqrt(2 * g * h);
  ASSERT_GE(r.events.size(), 21u);
  for (int k = 0; k < 20; ++k) {
    const EventRecord& ev = r.events[static_cast<std::size_t>(k)];
    EXPECT_EQ(ev.kind, EventKind::impact) << k;
    EXPECT_NEAR(ev.t, t_k, 1e-11) << "impact " << k;
    EXPECT_NEAR(ev.approach_speed, v_k, 1e-9 * std::sqrt(2 * g * h)) << "impact " << k;
    // Energy lost at each bounce: ½ m v² (1 − e²).
    EXPECT_NEAR(ev.kinetic_energy_before - ev.kinetic_energy_after, 0.5 * m * v_k * v_k * (1 - e * e), 1e-9) << k;
    v_k *= e;
    t_k += 2 * v_k / g;
  }
  // The accumulation point t∞ = t_1 + 2 v_1 e / (g (1 − e)) is passed with a rest event there.
  const double t_inf = std::sqrt(2 * h / g) + 2 * std::sqrt(2 * g * h) * e / (g * (1 - e));
  int rests = 0;
  for (const auto& ev : r.events) {
    if (ev.kind == EventKind::rest) {
      ++rests;
      EXPECT_NEAR(ev.t, t_inf, 1e-5);
      // The Zeno rule cut the series off at ev.t: the bounces left would take e Δ / (1 − e) more, Δ the
      // last flight, so the rest's time plus its cut-off is t∞ itself, and the summary shows the rest's
      // time only to the digits the cut-off leaves known.
      ASSERT_GT(ev.zeno_cutoff, 0.0);
      EXPECT_LT(t_inf - ev.t, 1.5 * ev.zeno_cutoff);
      EXPECT_NEAR(ev.t + ev.zeno_cutoff, t_inf, 1e-9);
      const int digits = static_cast<int>(std::ceil(std::log10(ev.t / ev.zeno_cutoff)));
      char shown[64];
      std::snprintf(shown, sizeof shown, "at t = %.*g s (the Zeno rule", digits, ev.t);
      const std::string text = r.summary();
      EXPECT_NE(text.find(shown), std::string::npos) << text;
      std::snprintf(shown, sizeof shown, "at t = %.15g s", ev.t);
      EXPECT_EQ(text.find(shown), std::string::npos) << text;
    }
  }
  EXPECT_EQ(rests, 1);
  EXPECT_EQ(r.t_final, 10.0);
  EXPECT_LT(r.steps, 10000u);
  // At rest on the floor, the floor carrying the weight; all the energy above the floor was lost.
  const auto& last = rec.samples.back();
  EXPECT_EQ(last.t, 10.0);
  EXPECT_NEAR(last.q[2], R, 1e-12);
  EXPECT_NEAR(last.qd[2], 0.0, 1e-12);
  EXPECT_NEAR(last.multipliers[0], m * g, 1e-9);
  EXPECT_NEAR(r.impact_energy_loss, m * g * h, 1e-9);
  // The integration error stays separate from the impacts' losses.
  EXPECT_LE(r.total_energy_drift_max, 1e-12);
}

TEST(Events, APlasticBallStopsAtTheFirstImpact) {
  const BallAndPlane ball(2.0, 0.1, 0.0, 9.81);
  SimulationOptions o;
  o.t_end = 3.0;
  o.output_interval = -1;
  Recorder<3> rec;
  const RunReport r = simulate(ball, dropped(0.6), o, rec);
  ASSERT_EQ(r.events.size(), 2u);
  EXPECT_EQ(r.events[0].kind, EventKind::impact);
  EXPECT_NEAR(r.events[0].separation_speed, 0.0, 1e-15);
  EXPECT_EQ(r.events[1].kind, EventKind::rest);
  EXPECT_NEAR(rec.samples.back().q[2], 0.1, 1e-12);
  EXPECT_NEAR(r.impact_energy_loss, 2.0 * 9.81 * 0.5, 1e-9);
}

TEST(Events, PerfectlyElasticSpheresInABoxKeepTheirKineticEnergyOver10000Impacts) {
  const SpheresInBox<3> box({1.0, 2.0, 0.5}, {0.1, 0.15, 0.08}, 2.0, 1.5, 1.0, 1.0);
  State<6> s;
  s.q << 0.3, 0.4, 1.0, 1.0, 1.6, 0.5;
  s.qd << 3.1, 1.7, -2.2, 0.9, 1.3, -2.9;
  const double t0 = 0.5 * (1.0 * (3.1 * 3.1 + 1.7 * 1.7) + 2.0 * (2.2 * 2.2 + 0.9 * 0.9) + 0.5 * (1.3 * 1.3 + 2.9 * 2.9));
  SimulationOptions o;
  o.t_end = 2000.0;
  o.output_interval = -1;
  Recorder<6> rec;
  const RunReport r = simulate(box, s, o, rec);
  EXPECT_GE(r.impacts, 10000u);
  int pair_impacts = 0;
  double worst = 0;
  for (const auto& ev : r.events) {
    ASSERT_EQ(ev.kind, EventKind::impact);
    worst = std::max(worst, std::abs(ev.kinetic_energy_after - t0));
    if (ev.name.find("left") == std::string::npos && ev.name.find("right") == std::string::npos &&
        ev.name.find("top") == std::string::npos && ev.name.find("bottom") == std::string::npos)
      ++pair_impacts;
  }
  EXPECT_GT(pair_impacts, 100);
  EXPECT_LE(worst / t0, 1e-10);
  EXPECT_LE(std::abs(rec.samples.back().total_energy - t0) / t0, 1e-10);
  std::printf("box: %llu impacts (%d between spheres), %llu steps, worst relative KE change %.2e\n",
              static_cast<unsigned long long>(r.impacts), pair_impacts, static_cast<unsigned long long>(r.steps),
              worst / t0);
  // Every sphere stays inside the box.
  for (int i = 0; i < 3; ++i) {
    EXPECT_GE(rec.samples.back().q[2 * i], box.r[static_cast<std::size_t>(i)] - 1e-9);
    EXPECT_LE(rec.samples.back().q[2 * i], box.W - box.r[static_cast<std::size_t>(i)] + 1e-9);
  }
}

template <int N>
State<N> cradle_state(double u, double r) {
  State<N> s;
  for (int i = 0; i < N; ++i) s.q[i] = 2 * r * i;
  s.q[0] -= 0.3;  // the first ball 0.3 m away from the row
  s.qd.setZero();
  s.qd[0] = u;
  return s;
}

TEST(Events, NewtonsCradlePassesTheMomentumDownTheRow) {
  const double u = 1.5, r = 0.05, m = 0.2;
  auto run = [&](double e) {
    const SpheresOnLine<5> cradle({m, m, m, m, m}, {r, r, r, r, r}, e);
    SimulationOptions o;
    o.t_end = 1.0;
    o.output_interval = -1;
    Recorder<5> rec;
    const RunReport report = simulate(cradle, cradle_state<5>(u, r), o, rec);
    return std::pair{report, rec.samples.back()};
  };
  {
    const auto [r5, end] = run(1.0);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(end.qd[i], 0.0, 1e-14) << i;
    EXPECT_NEAR(end.qd[4], u, 1e-14);
    EXPECT_EQ(r5.impacts, 4u);  // sequential pairwise: s1-s2, s2-s3, s3-s4, s4-s5
    for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(r5.events[k].t, 0.3 / u, 1e-12);
    EXPECT_NEAR(end.qd.sum() * m, m * u, 1e-14);
    EXPECT_NEAR(end.total_energy, 0.5 * m * u * u, 1e-14);
    // The report's momentum monitor: P = m u throughout, across the impacts.
    ASSERT_TRUE(r5.has_particles);
    EXPECT_NEAR(r5.linear_momentum_initial[0], m * u, 1e-15);
    EXPECT_LE(r5.linear_momentum_drift_max, 1e-15);
  }
  {
    // e < 1: momentum is kept, the energy lost is what the impacts logged.
    const auto [r5, end] = run(0.8);
    EXPECT_NEAR(m * end.qd.sum(), m * u, 1e-14);
    EXPECT_NEAR(0.5 * m * u * u - end.total_energy, r5.impact_energy_loss, 1e-14);
    EXPECT_GT(r5.impact_energy_loss, 0.01);
    for (int i = 0; i + 1 < 5; ++i) EXPECT_GE(end.qd[i + 1], end.qd[i] - 1e-14) << i;  // no ball overtakes the next
  }
}

TEST(Events, AnImpactAtTheStartIsResolvedBeforeTheFirstStep) {
  // Two touching equal spheres approaching at t0 exchange velocities at
  // once; the other three are far away.
  const SpheresOnLine<5> model({1.0, 1.0, 1.0, 1.0, 1.0}, {0.5, 0.5, 0.5, 0.5, 0.5}, 1.0);
  State<5> s;
  s.q << 0.0, 1.0, 10.0, 20.0, 30.0;
  s.qd << 1.0, 0.0, 0.0, 0.0, 0.0;
  SimulationOptions o;
  o.t_end = 1.0;
  o.output_interval = -1;
  Recorder<5> rec;
  const RunReport r = simulate(model, s, o, rec);
  ASSERT_EQ(r.impacts, 1u);
  EXPECT_EQ(r.events[0].t, 0.0);
  EXPECT_EQ(r.events[0].name, "s1-s2");
  EXPECT_NEAR(rec.samples.back().q[0], 0.0, 1e-14);
  EXPECT_NEAR(rec.samples.back().q[1], 2.0, 1e-12);
}

}  // namespace
