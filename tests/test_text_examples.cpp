// The course notes' systems stated as text (examples/scenes/text/): each
// scene file read as a user's program would read it, its model built by
// text::TextModel, and its motion checked against the closed form the notes
// derive for it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/scene/io.hpp"
#include "lagrangian/scene/text_model.hpp"
#include "lagrangian/text/text_model.hpp"

namespace {

using namespace lagrangian;
namespace fs = std::filesystem;

/// An example scene's model and its initial state.
struct Example {
  scene::Scene scene;
  text::TextModel model;
  State<Dynamic> x0;
  double parameter(const std::string& name) const { return scene.model->parameters.at(name); }
};

Example example(const std::string& file) {
  const fs::path path = fs::path(LAGRANGIAN_SOURCE_DIR) / "examples" / "scenes" / "text" / file;
  scene::Scene s = scene::load_scene(path.string());
  text::TextModel model(scene::text_definition(*s.model));
  State<Dynamic> x0(model.size());
  for (int i = 0; i < model.size(); ++i) {
    x0.q[i] = s.model->q[static_cast<std::size_t>(i)];
    x0.qd[i] = s.model->qd[static_cast<std::size_t>(i)];
  }
  return {std::move(s), std::move(model), x0};
}

SimulationOptions tight(double t_end, double interval) {
  SimulationOptions o;
  o.t_end = t_end;
  o.rtol = 1e-12;
  o.atol = 1e-12;
  o.output_interval = interval;
  return o;
}

// Bead on a hoop of radius R turning at ω: U(θ) = −½ m R² ω² sin²θ − m g R
// cos θ has U' = m R sin θ (g − R ω² cos θ), zero at cos θ* = g/(ω² R), and
// U''(θ*) = m R² ω² sin²θ*, so the bead oscillates there at ω sin θ*.
TEST(TextExamples, BeadOnARotatingHoopHasItsOffAxisEquilibriumAndFrequency) {
  const Example e = example("bead_on_rotating_hoop.toml");
  const double R = e.parameter("R"), w = e.parameter("omega"), g = e.parameter("g");
  const double theta_star = std::acos(g / (w * w * R));
  EquilibriumOptions eo;
  eo.starts = {Eigen::VectorXd::Constant(1, 0.5)};
  eo.deflation = false;
  const auto eq = find_equilibria(e.model, eo);
  ASSERT_GE(eq.size(), 1u);
  EXPECT_NEAR(std::abs(eq[0].q[0]), theta_star, 1e-9);
  EXPECT_TRUE(eq[0].stable);
  const Modes modes = small_oscillations(e.model, eq[0].q);
  ASSERT_EQ(modes.omega.size(), 1);
  EXPECT_NEAR(modes.omega[0], w * std::sin(theta_star), 1e-9);
}

// Spherical pendulum: a conical orbit at θ0 needs φ̇² = g/(l cos θ0)
// (θ̈ = sin θ cos θ φ̇² − (g/l) sin θ = 0); θ stays at θ0.
TEST(TextExamples, SphericalPendulumKeepsAConicalOrbitAtItsAngle) {
  Example e = example("spherical_pendulum.toml");
  const double l = e.parameter("l"), g = e.parameter("g"), theta0 = 0.7;
  e.x0.q << theta0, 0.0;
  e.x0.qd << 0.0, std::sqrt(g / (l * std::cos(theta0)));
  Recorder<Dynamic> rec;
  simulate(e.model, e.x0, tight(10.0, 0.1), rec);
  ASSERT_EQ(rec.samples.size(), 101u);
  double worst = 0;
  for (const auto& s : rec.samples) worst = std::max(worst, std::abs(s.q[0] - theta0));
  EXPECT_LE(worst, 1e-9);
  EXPECT_NEAR(rec.samples.back().q[1], 10.0 * e.x0.qd[1], 1e-8);
}

// Atwood machine: ÿ1 = −g (m1 − m2)/(m1 + m2) from rest, and the tension
// 2 m1 m2 g/(m1 + m2) is the string constraint's multiplier.
TEST(TextExamples, AtwoodMachineAcceleratesAsTheClosedFormSaysWithItsTension) {
  const Example e = example("atwood_machine.toml");
  const double m1 = e.parameter("m1"), m2 = e.parameter("m2"), g = e.parameter("g");
  const double a = -g * (m1 - m2) / (m1 + m2);
  Recorder<Dynamic> rec;
  simulate(e.model, e.x0, tight(e.scene.run.t_end, 0.1), rec);
  ASSERT_EQ(rec.samples.size(), 7u);
  for (const auto& s : rec.samples) {
    EXPECT_NEAR(s.q[0], e.x0.q[0] + 0.5 * a * s.t * s.t, 1e-11) << s.t;
    EXPECT_NEAR(s.qd[1], -a * s.t, 1e-11) << s.t;
    EXPECT_NEAR(s.multipliers[0], 2 * m1 * m2 * g / (m1 + m2), 1e-9) << s.t;
  }
}

// Two bodies in the relative coordinate: the ellipse closes after
// T = 2π √(a³/(G (m1 + m2))), a = r_p/(1 − e) from the periapsis state.
TEST(TextExamples, TwoBodiesReturnToPeriapsisAfterKeplersPeriod) {
  const Example e = example("kepler.toml");
  const double G = e.parameter("G"), M = e.parameter("m1") + e.parameter("m2");
  const double rp = e.x0.q[0], vp = rp * e.x0.qd[1];
  const double a = 1.0 / (2.0 / rp - vp * vp / (G * M));  // vis-viva
  const double period = 2 * std::numbers::pi * std::sqrt(a * a * a / (G * M));
  Recorder<Dynamic> rec;
  const RunReport r = simulate(e.model, e.x0, tight(period, period / 4), rec);
  const auto& end = rec.samples.back();
  EXPECT_NEAR(end.t, period, 1e-12);
  EXPECT_NEAR(end.q[0], rp, 1e-9);
  EXPECT_NEAR(end.q[1], 2 * std::numbers::pi, 1e-9);
  EXPECT_NEAR(end.qd[0], 0.0, 1e-8);
  // Half a period later it is at apoapsis, r = 2a − r_p.
  EXPECT_NEAR(rec.samples[2].q[0], 2 * a - rp, 1e-9);
  EXPECT_LE(r.energy_drift_max, 1e-10);
}

// Kapitza's pendulum: averaged over the fast shaking, the pendulum moves in
// −m g l cos θ + ¼ m a²Ω² sin²θ, whose curvature at upright, m(½ a²Ω² − g l),
// is positive when a²Ω² > 2 g l. The example (a²Ω² = 100 m²/s², 2gl = 19.6)
// wobbles about upright; the same pendulum shaken at Ω = 60 rad/s
// (a²Ω² = 9 < 19.6) falls over.
TEST(TextExamples, KapitzaPendulumIsUprightStableOnlyAboveTheThreshold) {
  const Example e = example("driven_pendulum.toml");
  const double a = e.parameter("a"), w = e.parameter("Omega"), g = e.parameter("g"), l = e.parameter("l");
  ASSERT_GT(a * a * w * w, 2 * g * l);
  auto farthest_from_upright = [&](const text::TextModel& model) {
    SimulationOptions o = tight(5.0, 0.002);
    o.rtol = 1e-10;
    Recorder<Dynamic> rec;
    simulate(model, e.x0, o, rec);
    double worst = 0;
    for (const auto& s : rec.samples) worst = std::max(worst, std::abs(s.q[0] - std::numbers::pi));
    return worst;
  };
  const double start = std::abs(e.x0.q[0] - std::numbers::pi);
  EXPECT_LE(farthest_from_upright(e.model), 1.5 * start);
  text::Definition slow = scene::text_definition(*e.scene.model);
  for (auto& [name, value] : slow.parameters)
    if (name == "Omega") value = 60.0;
  EXPECT_GE(farthest_from_upright(text::TextModel(slow)), 1.0);
}

// Projectile on an incline (course notes 1.5.2): from O with speed u at α
// to the horizontal, on a plane at θ, the first flight lasts
// T = 2u sin(α − θ)/(g cos θ) and lands 2u² sin(α − θ) cos α/(g cos²θ) up the
// plane. The motion normal to the plane is a ball bouncing in g cos θ, so the
// flights shrink by e and the particle rests on the plane at T/(1 − e).
TEST(TextExamples, ProjectileOnAnInclineLandsAtTheRangeAndRestsAtTheZenoTime) {
  const Example e = example("projectile_on_incline.toml");
  const double g = e.parameter("g"), theta = e.parameter("theta");
  const double u = e.x0.qd.norm(), alpha = std::atan2(e.x0.qd[1], e.x0.qd[0]);
  const double restitution = e.scene.model->text->contacts.at(0).restitution;
  const double flight = 2 * u * std::sin(alpha - theta) / (g * std::cos(theta));
  const double range = 2 * u * u * std::sin(alpha - theta) * std::cos(alpha) / (g * std::cos(theta) * std::cos(theta));
  SimulationOptions o = tight(e.scene.run.t_end, 0.5);
  Recorder<Dynamic> rec;
  const RunReport r = simulate(e.model, e.x0, o, rec);
  ASSERT_GE(r.events.size(), 3u);
  const EventRecord& first = r.events.front();
  EXPECT_EQ(first.kind, EventKind::impact);
  EXPECT_EQ(first.name, "incline");
  EXPECT_NEAR(first.t, flight, 1e-9);
  // Where it landed: the state at the first impact, from a run stopped there.
  SimulationOptions to_first = tight(flight, flight);
  Recorder<Dynamic> landing;
  simulate(e.model, e.x0, to_first, landing);
  EXPECT_NEAR(landing.samples.back().q.norm(), range, 1e-8);
  // Each flight e times the one before.
  EXPECT_NEAR(r.events[1].t - r.events[0].t, restitution * flight, 1e-8);
  const auto rest = std::find_if(r.events.begin(), r.events.end(),
                                 [](const EventRecord& ev) { return ev.kind == EventKind::rest; });
  ASSERT_NE(rest, r.events.end());
  EXPECT_NEAR(rest->t, flight / (1 - restitution), 1e-5);  // the Zeno rule cuts the last few bounces
  // At rest on the plane it slides: the gap stays 0 to the end.
  const auto& end = rec.samples.back();
  EXPECT_NEAR(end.q[1] * std::cos(theta) - end.q[0] * std::sin(theta), 0.0, 1e-9);
}

}  // namespace
