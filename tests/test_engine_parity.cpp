// The one driver runs both kinds of system: a Model (simulate()) and a
// particle scene (scene::run). The same physical scene stated both ways must
// give the same events and states, and both follow the one Zeno rule
// (integrate/detail/contact_rules.hpp).

#include <array>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "lagrangian/models/impacts.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/run.hpp"
#include "lagrangian/integrate/simulate.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::scene;

constexpr double kAgree = 1e-10;  // event times (s) and states (m, m/s) of the two formulations
// Speeds at an impact (m/s) are taken at a time located to within the event
// time tolerance (~1e-12 s): with |φ̈| up to ~40 m/s² they agree to a few
// 1e-11 m/s, late in an accumulation to ~1.1e-10 (measured).
constexpr double kSpeedAgree = 1e-9;

RunControls quiet() {
  RunControls c;
  c.write_outputs = false;
  return c;
}

Scene base(double t_end) {
  Scene s;
  s.name = "parity";
  s.run.t_end = t_end;
  s.run.rtol = 1e-11;
  s.run.atol = 1e-13;
  s.run.output_interval = 0.01;
  s.run.engine = "ode";
  return s;
}

SimulationOptions options(double t_end) {
  SimulationOptions o;
  o.t_end = t_end;
  o.rtol = 1e-11;
  o.atol = 1e-13;
  o.output_interval = 0.01;
  return o;
}

template <int N>
struct Final {
  RunReport report;
  State<N> end;
};

template <class M, int N = coordinate_count_v<M>>
Final<N> run_model(const M& model, const State<N>& x0, const SimulationOptions& o) {
  Recorder<N> rec;
  Final<N> f;
  f.report = simulate(model, x0, o, rec);
  f.end.q = rec.samples.back().q;
  f.end.qd = rec.samples.back().qd;
  return f;
}

/// The event logs agree: kinds, contacts, times and speeds.
std::string listing(const RunReport& r) {
  std::string out;
  for (const auto& e : r.events)
    out += "  " + std::to_string(static_cast<int>(e.kind)) + " " + e.name + " t = " + std::to_string(e.t) +
           " u_in = " + std::to_string(e.approach_speed) + " u_out = " + std::to_string(e.separation_speed) + "\n";
  return out;
}

void expect_same_events(const RunReport& model, const RunReport& particles) {
  ASSERT_EQ(model.events.size(), particles.events.size()) << "model:\n"
                                                          << listing(model) << "particles:\n"
                                                          << listing(particles);
  for (std::size_t k = 0; k < model.events.size(); ++k) {
    const EventRecord &a = model.events[k], &b = particles.events[k];
    SCOPED_TRACE("event " + std::to_string(k) + " (" + a.name + ")");
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.name, b.name);
    EXPECT_NEAR(a.t, b.t, kAgree);
    EXPECT_NEAR(a.approach_speed, b.approach_speed, kSpeedAgree);
    EXPECT_NEAR(a.separation_speed, b.separation_speed, kSpeedAgree);
  }
  EXPECT_EQ(model.impacts, particles.impacts);
}

/// Two bodies on a vertical line: a ball A (mass mA, radius R) on the
/// floor z = 0, and a point B (mass mB) above it, joined by a spring
/// (stiffness k, rest length L0); coordinates z_A, z_B (m):
///   T = ½ mA ż_A² + ½ mB ż_B²,
///   V = mA g z_A + mB g z_B + ½ k (z_B − z_A − L0)²,  φ = z_A − R ≥ 0.
/// While B swings low the spring presses A onto the floor; when B swings
/// high enough, k (z_B − z_A − L0) > mA g lifts A off.
struct BallUnderSpring {
  static constexpr int dof = 2;
  double mA = 2.0, mB = 1.0, g = 9.81, R = 0.05, k = 100.0, L0 = 0.5, e = 0.2;
  std::string name() const { return "ball_under_spring"; }
  std::array<std::string, 1> unilateral_names() const { return {"A-floor"}; }
  std::array<double, 1> restitution() const { return {e}; }
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * mA * qd[0] * qd[0] + 0.5 * mB * qd[1] * qd[1];
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    const S stretch = q[1] - q[0] - L0;
    return mA * g * q[0] + mB * g * q[1] + 0.5 * k * stretch * stretch;
  }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(q[0] - R);
  }
};

/// A bob on a massless link of length l from the origin, in Cartesian
/// coordinates: T = ½ m |ṙ|², V = m g z, g(r) = ½ (|r|² − l²) = 0.
struct LinkedBob {
  static constexpr int dof = 3;
  double m = 0.7, g = 9.81, l = 1.5;
  std::string name() const { return "linked_bob"; }
  std::array<std::string_view, 1> holonomic_names() const { return {"rod"}; }
  std::array<Particle, 1> particles() const { return {Particle{m, {0, 1, 2}}}; }
  template <class S>
  S kinetic(const Vec<S, 3>&, const Vec<S, 3>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1] + qd[2] * qd[2]);
  }
  template <class S>
  S potential(const Vec<S, 3>& q, const S&) const {
    return m * g * q[2];
  }
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 3>& q, const S&) const {
    return Vec<S, 1>(0.5 * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - l * l));
  }
};

/// A sphere between two walls a clearance W − 2R apart, no force: each
/// impact keeps a fraction e of the speed. φ₁ = x − R, φ₂ = W − R − x.
struct SphereBetweenWalls {
  static constexpr int dof = 1;
  double m = 1.0, R = 0.5, W = 1.0 + 1e-7, e = 5e-4;
  std::string name() const { return "sphere_between_walls"; }
  std::array<std::string, 2> unilateral_names() const { return {"s-wall:x_min", "s-wall:x_max"}; }
  std::array<double, 2> restitution() const { return {e, e}; }
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * m * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>&, const S&) const {
    return S(0);
  }
  template <class S>
  Vec<S, 2> unilateral(const Vec<S, 1>& q, const S&) const {
    return Vec<S, 2>(q[0] - R, W - R - q[0]);
  }
};

TEST(EngineParity, NewtonsCradleOnALine) {
  // Five equal spheres, four touching at rest, the first arriving at 1 m/s:
  // models::SpheresOnLine<5> and five bodies with sphere contacts.
  const double m = 0.1, r = 0.0125, t_end = 1.0;
  const std::array<double, 5> x0{-0.1, 0.025, 0.05, 0.075, 0.1};
  models::SpheresOnLine<5> cradle({m, m, m, m, m}, {r, r, r, r, r}, 1.0);
  State<5> s0;
  for (int i = 0; i < 5; ++i) s0.q[i] = x0[static_cast<std::size_t>(i)];
  s0.qd[0] = 1.0;
  const auto model = run_model(cradle, s0, options(t_end));

  Scene s = base(t_end);
  for (int i = 0; i < 5; ++i)
    s.bodies.push_back({.name = "s" + std::to_string(i + 1), .mass = m, .radius = r,
                        .position = {x0[static_cast<std::size_t>(i)], 0, 0}, .velocity = {i == 0 ? 1.0 : 0.0, 0, 0}});
  s.sphere_contacts = SphereContacts{1.0, {}};
  const RunResult particles = run(s, quiet());

  ASSERT_EQ(model.report.impacts, 4u);  // the momentum passes down the row
  expect_same_events(model.report, particles.report);
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(model.end.q[i], particles.q_final[static_cast<std::size_t>(3 * i)], kAgree);
    EXPECT_NEAR(model.end.qd[i], particles.qd_final[static_cast<std::size_t>(3 * i)], kAgree);
  }
  EXPECT_NEAR(particles.qd_final[12], 1.0, 1e-12);  // the last sphere leaves at the striker's speed
}

TEST(EngineParity, BallComesToRestAndLiftsOff) {
  // A dropped 2 mm onto the floor while B, released 0.35 m below its
  // equilibrium (the spring compressed by mB g / k), swings up: A's bounces accumulate and it comes to rest
  // (the Zeno rule), then B's pull lifts it off, and it lands again.
  const BallUnderSpring sys;
  const double t_end = 0.6;
  const double zA = sys.R + 0.002, zB = zA + sys.L0 - sys.mB * sys.g / sys.k - 0.35;
  State<2> x0;
  x0.q << zA, zB;
  const auto model = run_model(sys, x0, options(t_end));

  Scene s = base(t_end);
  s.bodies.push_back({.name = "A", .mass = sys.mA, .radius = sys.R, .position = {0, 0, zA}});
  s.bodies.push_back({.name = "B", .mass = sys.mB, .position = {0, 0, zB}});
  s.gravity = UniformGravity{{0, 0, -sys.g}};
  s.springs.push_back({.name = "spring", .a = "A", .b = "B", .stiffness = sys.k, .rest_length = sys.L0});
  s.planes.push_back({.name = "floor", .point = {0, 0, 0}, .normal = {0, 0, 1}, .restitution = sys.e, .bodies = {"A"}});
  const RunResult particles = run(s, quiet());

  // What happened: impacts, a rest, a lift-off, and a landing.
  const auto& ev = model.report.events;
  std::size_t rest = 0, release = 0;
  for (std::size_t k = 0; k < ev.size(); ++k) {
    if (ev[k].kind == EventKind::rest && rest == 0) rest = k;
    if (ev[k].kind == EventKind::release && release == 0) release = k;
  }
  ASSERT_GT(rest, 1u) << listing(model.report);
  ASSERT_GT(release, rest) << listing(model.report);
  ASSERT_GT(ev.size(), release + 1) << listing(model.report);
  expect_same_events(model.report, particles.report);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(model.end.q[i], particles.q_final[static_cast<std::size_t>(3 * i + 2)], kAgree);
    EXPECT_NEAR(model.end.qd[i], particles.qd_final[static_cast<std::size_t>(3 * i + 2)], kAgree);
  }
  // Where it lifts off: A at rest on the floor (z_A = R, ż_A = 0) until the
  // floor's force on it, mA g − k (z_B − z_A − L0), falls to zero, i.e. the
  // spring's pull reaches mA g. A sample at every step puts one at the release.
  SimulationOptions every_step = options(t_end);
  every_step.output_interval = 0;
  Recorder<2> rec;
  const RunReport stepwise = simulate(sys, x0, every_step, rec);
  double t_release = -1;
  for (const auto& e : stepwise.events)
    if (e.kind == EventKind::release && t_release < 0) t_release = e.t;
  EXPECT_NEAR(t_release, ev[release].t, 1e-9);
  bool found = false;
  for (const auto& smp : rec.samples) {
    if (smp.t != t_release) continue;
    found = true;
    EXPECT_NEAR(smp.q[0], sys.R, 1e-9);
    EXPECT_NEAR(smp.qd[0], 0.0, 1e-9);
    EXPECT_NEAR(sys.k * (smp.q[1] - smp.q[0] - sys.L0), sys.mA * sys.g, 1e-7 * sys.mA * sys.g);
  }
  EXPECT_TRUE(found) << "no sample at the release, t = " << t_release;
}

TEST(EngineParity, PendulumOnALink) {
  const LinkedBob bob;
  const double theta0 = 1.2, t_end = 6.0;
  State<3> x0;
  x0.q << bob.l * std::sin(theta0), 0.0, -bob.l * std::cos(theta0);
  x0.qd << 0.0, 0.3, 0.0;  // off the plane: a spherical pendulum
  const auto model = run_model(bob, x0, options(t_end));

  Scene s = base(t_end);
  s.bodies.push_back({.name = "bob", .mass = bob.m, .position = {x0.q[0], x0.q[1], x0.q[2]}, .velocity = {0, 0.3, 0}});
  s.gravity = UniformGravity{{0, 0, -bob.g}};
  s.links.push_back({.name = "rod", .a = "bob", .anchor = {0, 0, 0}, .length = bob.l});
  const RunResult particles = run(s, quiet());

  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(model.end.q[i], particles.q_final[static_cast<std::size_t>(i)], kAgree);
    EXPECT_NEAR(model.end.qd[i], particles.qd_final[static_cast<std::size_t>(i)], kAgree);
  }
}

TEST(EngineParity, TheZenoRuleRestsOnlyWhatTheForcesPressShut) {
  // A free sphere rattling between two walls 0.1 µm apart keeps a fraction
  // e = 5e-4 of its speed at each impact: 1 km/s onto the right wall, 0.5
  // m/s onto the left, 2.5e-4 m/s onto the right again — 2.5e-7 of that
  // wall's first approach, which passes the speed test of the Zeno rule
  // (≤ 1e-6). No force presses the sphere against the wall, so the rule
  // must not rest it: the third impact is an impact with e applied, and the
  // sphere leaves at e³ · 1 km/s, in both formulations.
  const SphereBetweenWalls m;
  const double t_end = 0.5, v0 = 1000.0;
  State<1> x0;
  x0.q[0] = m.R + 0.5e-7;
  x0.qd[0] = v0;
  const auto model = run_model(m, x0, options(t_end));

  Scene s = base(t_end);
  s.bodies.push_back({.name = "s", .mass = m.m, .radius = m.R, .position = {x0.q[0], 0.5, 0.5}, .velocity = {v0, 0, 0}});
  s.box = BoxContact{{0, 0, 0}, {m.W, 1.0, 1.0}, m.e};
  const RunResult particles = run(s, quiet());

  // Impacts at t = 5e-11 s, + 1e-7/0.5 = 2e-7 s, + 1e-7/2.5e-4 = 4e-4 s.
  ASSERT_EQ(model.report.impacts, 3u);
  for (const auto& e : model.report.events) EXPECT_EQ(e.kind, EventKind::impact) << e.name << " at t = " << e.t;
  EXPECT_NEAR(model.report.events[2].t, 5e-11 + 2e-7 + 4e-4, 1e-12);
  const double v_end = -m.e * m.e * m.e * v0;
  EXPECT_NEAR(model.end.qd[0], v_end, 1e-6 * std::abs(v_end));
  EXPECT_NEAR(particles.qd_final[0], v_end, 1e-6 * std::abs(v_end));
  expect_same_events(model.report, particles.report);
}

}  // namespace
