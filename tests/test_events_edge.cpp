// Located events in runs, the edge cases: grazing and tangential contacts,
// watched events, the event log and bad input. (Split from test_events.cpp
// so the two translation units compile in parallel.)
#include <fstream>

#include "event_helpers.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;
using lagrangian_test::dropped;
using lagrangian_test::kEventTime;

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
  for (const Method method : {Method::dopri5, Method::rk4, Method::cash_karp54}) {
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
  EXPECT_EQ(line, "t [s],kind,bodies,impulse,approach_speed,separation_speed,ke_before [J],ke_after [J]");
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
  // With the gaps' unit given, the impulse and the speeds carry theirs:
  // Λ in J*s per unit of φ, N*s for a distance.
  r.write_events_csv(path, "m");
  const auto first_line = [&] {
    std::ifstream f(path);
    std::string header;
    std::getline(f, header);
    return header;
  };
  EXPECT_EQ(first_line(),
            "t [s],kind,bodies,impulse [N*s],approach_speed [m/s],separation_speed [m/s],ke_before [J],ke_after [J]");
  r.write_events_csv(path, "rad");
  EXPECT_EQ(first_line(), "t [s],kind,bodies,impulse [J*s/rad],approach_speed [rad/s],separation_speed [rad/s],"
                  "ke_before [J],ke_after [J]");
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
  const TwoSpheres<2> spheres(1.0, 1.0, 0.5, 0.5, 0.9);
  State<4> overlap;
  overlap.q << 0, 0, 0.9, 0;
  overlap.qd.setZero();
  try {
    simulate(spheres, overlap, SimulationOptions{});
    FAIL() << "no error";
  } catch (const ConstraintError& err) {
    EXPECT_NE(std::string(err.what()).find("s1-s2 is violated at t0: g = -0.09"), std::string::npos) << err.what();
    EXPECT_NE(std::string(err.what()).find("overlap"), std::string::npos) << err.what();
  }
  // NaN in the state, and invalid event options.
  State<4> nan_state = overlap;
  nan_state.q[2] = std::nan("");
  EXPECT_THROW(simulate(spheres, nan_state, SimulationOptions{}), OptionError);
  SimulationOptions o;
  o.zeno_speed_ratio = 1.0;
  State<4> apart = overlap;
  apart.q[2] = 2.0;
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

}  // namespace
