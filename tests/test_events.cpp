// Located events in runs: impact times, the Zeno accumulation, a box of
// perfectly elastic spheres, Newton's cradle, grazing and tangential
// contacts, watched events, the event log and bad input.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/impacts.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

constexpr double kEventTime = 1e-12;  // located event times against closed forms (s)

State<3> dropped(double z) {
  State<3> s;
  s.q << 0.0, 0.0, z;
  s.qd.setZero();
  return s;
}

TEST(Events, ADroppedBallHitsAtTheFreeFallTimeWithEveryStepper) {
  const double g = 9.81, R = 0.1;
  const BallAndPlane ball(1.0, R, 1.0, g);
  for (const std::string method : {"dopri5", "cash_karp54", "fehlberg78", "bulirsch_stoer", "rk4", "rosenbrock4"}) {
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
  {
    const SpheresOnLine<5> cradle({m, m, m, m, m}, {r, r, r, r, r}, 1.0);
    SimulationOptions o;
    o.t_end = 1.0;
    o.output_interval = -1;
    Recorder<5> rec;
    const RunReport r5 = simulate(cradle, cradle_state<5>(u, r), o, rec);
    const auto& end = rec.samples.back();
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(end.qd[i], 0.0, 1e-14) << i;
    EXPECT_NEAR(end.qd[4], u, 1e-14);
    EXPECT_EQ(r5.impacts, 4u);  // sequential pairwise: s1-s2, s2-s3, s3-s4, s4-s5
    for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(r5.events[k].t, 0.3 / u, 1e-12);
    EXPECT_NEAR(end.qd.sum() * m, m * u, 1e-14);
    EXPECT_NEAR(end.total_energy, 0.5 * m * u * u, 1e-14);
  }
  {
    // e < 1: momentum is kept, the energy lost is what the impacts logged.
    const SpheresOnLine<3> cradle({m, m, m}, {r, r, r}, 0.8);
    SimulationOptions o;
    o.t_end = 1.0;
    o.output_interval = -1;
    Recorder<3> rec;
    const RunReport r3 = simulate(cradle, cradle_state<3>(u, r), o, rec);
    const auto& end = rec.samples.back();
    EXPECT_NEAR(m * end.qd.sum(), m * u, 1e-14);
    EXPECT_NEAR(0.5 * m * u * u - end.total_energy, r3.impact_energy_loss, 1e-14);
    EXPECT_GT(r3.impact_energy_loss, 0.01);
    EXPECT_GE(end.qd[2], end.qd[1] - 1e-14);  // no overlap: each ball no faster than the one ahead
    EXPECT_GE(end.qd[1], end.qd[0] - 1e-14);
  }
}

TEST(Events, GrazingImpactsAndTangentialTouchesNeitherCrashNorInventImpacts) {
  // Sphere 1 moves along +x past sphere 2 at rest; offset b of the lines of
  // centres; contact distance D = r1 + r2. b → D is a grazing impact.
  const double r1 = 0.2, r2 = 0.3, D = r1 + r2, u = 2.0, m1 = 1.0, m2 = 3.0;
  const TwoSpheres<2> model(m1, m2, r1, r2, 1.0);
  auto run = [&](double b) {
    State<4> s;
    s.q << -2.0, b, 0.0, 0.0;
    s.qd << u, 0.0, 0.0, 0.0;
    SimulationOptions o;
    o.t_end = 2.0;
    o.output_interval = -1;
    Recorder<4> rec;
    const RunReport r = simulate(model, s, o, rec);
    return std::pair{r, rec.samples.back()};
  };
  for (double delta : {1e-2, 1e-6, 1e-10}) {
    const double b = D * (1 - delta);
    const auto [r, end] = run(b);
    ASSERT_EQ(r.impacts, 1u) << delta;
    // Normal speed at contact u cos α with sin α = b / D.
    const double un = u * std::sqrt(1 - (b / D) * (b / D));
    EXPECT_NEAR(r.events[0].approach_speed, un, 1e-6 * un + 1e-12) << delta;
    EXPECT_NEAR(m1 * end.qd[0] + m2 * end.qd[2], m1 * u, 1e-13) << delta;
    EXPECT_NEAR(m1 * end.qd[1] + m2 * end.qd[3], 0.0, 1e-13) << delta;
    EXPECT_NEAR(end.total_energy, 0.5 * m1 * u * u, 1e-13) << delta;
  }
  for (double b : {D, D * (1 + 1e-12), D * (1 + 1e-3)}) {  // a tangential touch, and near misses
    const auto [r, end] = run(b);
    EXPECT_EQ(r.events.size(), 0u) << b;
    EXPECT_EQ(end.qd[0], u);
    EXPECT_EQ(end.qd[2], 0.0);
  }
}

// A projectile (x, y) with two watched events: the apex (ẏ falls through 0)
// and y falling through the height y_stop, which ends the run.
struct WatchedProjectile {
  static constexpr int dof = 2;
  double m = 1.0, g = 9.81, y_stop = -0.5;
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return m * g * q[1];
  }
  template <class S>
  Vec<S, 2> events(const Vec<S, 2>& q, const Vec<S, 2>& qd, const S&) const {
    return Vec<S, 2>(qd[1], q[1] - y_stop);
  }
  std::array<EventSpec, 2> event_specs() const {
    return {EventSpec{"apex", Direction::falling, EventAction::record},
            EventSpec{"below", Direction::falling, EventAction::stop}};
  }
};

TEST(Events, WatchedEventsAreLocatedLoggedAndCanStopTheRun) {
  const WatchedProjectile p;
  State<2> s;
  s.q << 0.0, 0.0;
  s.qd << 3.0, 4.0;
  for (const std::string method : {"dopri5", "rk4", "cash_karp54"}) {
    SimulationOptions o;
    o.method = method;
    o.t_end = 10.0;
    o.dt = 1e-2;
    o.output_interval = 0.1;
    Recorder<2> rec;
    const RunReport r = simulate(p, s, o, rec);
    const double t_apex = 4.0 / p.g;
    const double t_stop = (4.0 + std::sqrt(16.0 + 2 * p.g * 0.5)) / p.g;  // y(t) = 4t − g t²/2 = −0.5
    ASSERT_EQ(r.events.size(), 3u) << method;
    EXPECT_EQ(r.events[0].name, "apex");
    EXPECT_EQ(r.events[0].kind, EventKind::watched);
    EXPECT_NEAR(r.events[0].t, t_apex, kEventTime) << method;
    EXPECT_EQ(r.events[1].name, "below");
    EXPECT_EQ(r.events[2].kind, EventKind::stop);
    EXPECT_NEAR(r.events[2].t, t_stop, kEventTime) << method;
    EXPECT_EQ(r.stopped_by, "below");
    EXPECT_NEAR(r.stopped_at, t_stop, kEventTime);
    EXPECT_EQ(r.t_final, r.stopped_at);
    // The last sample is the stop, nothing after it.
    EXPECT_EQ(rec.samples.back().t, r.stopped_at) << method;
    EXPECT_NEAR(rec.samples.back().q[1], p.y_stop, 1e-10);
    EXPECT_NEAR(rec.samples.back().q[0], 3.0 * t_stop, 1e-10);
  }
}

TEST(Events, TheEventLogIsWrittenAsCsv) {
  const BallAndPlane ball(1.0, 0.1, 0.5, 9.81);
  SimulationOptions o;
  o.t_end = 3.0;
  o.output_interval = -1;
  const RunReport r = simulate(ball, dropped(1.1), o);
  const std::string path = ::testing::TempDir() + "events_test.csv";
  r.write_events_csv(path);
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,kind,name,impulse,approach_speed,separation_speed,ke_before,ke_after");
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    ++rows;
    if (rows == 1) {
      EXPECT_EQ(line.rfind("0.45152364098", 0), 0u) << line;
      EXPECT_NE(line.find(",impact,ball-plane,"), std::string::npos) << line;
    }
  }
  EXPECT_EQ(rows, r.events.size());
  EXPECT_FALSE(std::ifstream(path + ".partial").good());
  EXPECT_THROW(r.write_events_csv("/nonexistent-dir/events.csv"), OptionError);
  const std::string json = r.to_json();
  EXPECT_NE(json.find("\"impact\": 20"), std::string::npos) << json;
  EXPECT_NE(json.find("\"rest\": 1"), std::string::npos);
}

struct BadRestitution {
  static constexpr int dof = 1;
  double e;
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    return 9.81 * q[0];
  }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 1>& q, const S&) const {
    return Vec<S, 1>(q[0]);
  }
  std::array<std::string, 1> unilateral_names() const { return {"floor"}; }
  std::array<double, 1> restitution() const { return {e}; }
  std::string name() const { return "bad_restitution"; }
};

TEST(Events, BadInputIsAClearError) {
  State<1> s;
  s.q << 1.0;
  s.qd << 0.0;
  for (double e : {-0.5, 1.01, std::nan("")}) {
    try {
      simulate(BadRestitution{e}, s, SimulationOptions{});
      FAIL() << "no error for e = " << e;
    } catch (const ParameterError& err) {
      EXPECT_NE(std::string(err.what()).find("bad_restitution: restitution of contact floor must be in [0, 1], got"),
                std::string::npos)
          << err.what();
    }
  }
  // Overlapping spheres at t0.
  const TwoSpheres<3> spheres(1.0, 1.0, 0.5, 0.5, 0.9);
  State<6> overlap;
  overlap.q << 0, 0, 0, 0.9, 0, 0;
  overlap.qd.setZero();
  try {
    simulate(spheres, overlap, SimulationOptions{});
    FAIL() << "no error";
  } catch (const ConstraintError& err) {
    EXPECT_NE(std::string(err.what()).find("s1-s2 is violated at t0: g = -0.09"), std::string::npos) << err.what();
    EXPECT_NE(std::string(err.what()).find("overlap"), std::string::npos) << err.what();
  }
  // NaN in the state, and invalid event options.
  State<6> nan_state = overlap;
  nan_state.q[3] = std::nan("");
  EXPECT_THROW(simulate(spheres, nan_state, SimulationOptions{}), OptionError);
  SimulationOptions o;
  o.zeno_speed_ratio = 1.0;
  State<6> apart = overlap;
  apart.q[3] = 2.0;
  try {
    simulate(spheres, apart, o);
    FAIL() << "no error";
  } catch (const OptionError& err) {
    EXPECT_NE(std::string(err.what()).find("'zeno_speed_ratio' must be in [0, 1), got 1"), std::string::npos)
        << err.what();
  }
  o = SimulationOptions{};
  o.contact_touch_speed = -1;
  EXPECT_THROW(simulate(spheres, apart, o), OptionError);
}

TEST(Events, AnImpactAtTheStartIsResolvedBeforeTheFirstStep) {
  // Two touching spheres approaching at t0 bounce apart at once.
  const SpheresOnLine<2> model({1.0, 1.0}, {0.5, 0.5}, 1.0);
  State<2> s;
  s.q << 0.0, 1.0;
  s.qd << 1.0, 0.0;
  SimulationOptions o;
  o.t_end = 1.0;
  o.output_interval = -1;
  Recorder<2> rec;
  const RunReport r = simulate(model, s, o, rec);
  ASSERT_EQ(r.impacts, 1u);
  EXPECT_EQ(r.events[0].t, 0.0);
  EXPECT_NEAR(rec.samples.back().q[0], 0.0, 1e-14);
  EXPECT_NEAR(rec.samples.back().q[1], 2.0, 1e-12);
}

}  // namespace
