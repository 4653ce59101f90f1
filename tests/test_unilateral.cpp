// Unilateral constraints: active while the multiplier pushes, released where
// it would pull (a particle sliding off a smooth sphere).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"

#include "contact_models.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

using lagrangian::testing::PolygonBilliard;

TEST(Unilateral, TwoHundredContactsOfOneModelAllTakePart) {
  // A billiard in a regular 200-gon, started off the centre: its impacts,
  // wall after wall, against the same billiard traced by hand — straight
  // flights to the first wall the ray meets, reflections v − 2 (v·n) n.
  const PolygonBilliard model{200};
  const double t_end = 60.0;
  State<2> s;
  s.q << 0.3, 0.0;
  s.qd << 10 * std::cos(1.0), 10 * std::sin(1.0);  // a direction irrational to the polygon's: every wall in turn
  SimulationOptions o;
  o.t_end = t_end;
  o.rtol = 1e-12;
  o.atol = 1e-14;
  o.output_interval = t_end;
  Recorder<2> rec;
  const RunReport rep = simulate(model, s, o, rec);

  Eigen::Vector2d p(0.3, 0.0), v(s.qd);
  double t = 0;
  std::vector<int> hit;  // the walls, by hand
  std::vector<double> when;
  for (;;) {
    int first = -1;
    double dt = std::numeric_limits<double>::infinity();
    for (int k = 0; k < model.walls; ++k) {
      const Eigen::Vector2d n(std::cos(model.angle(k)), std::sin(model.angle(k)));
      const double closing = v.dot(n);
      if (closing <= 0) continue;
      const double tk = (model.a - p.dot(n)) / closing;
      if (tk < dt) {
        dt = tk;
        first = k;
      }
    }
    if (t + dt > t_end) break;
    t += dt;
    p += dt * v;
    const Eigen::Vector2d n(std::cos(model.angle(first)), std::sin(model.angle(first)));
    v -= 2 * v.dot(n) * n;
    hit.push_back(first);
    when.push_back(t);
  }
  ASSERT_EQ(rep.events.size(), hit.size());
  EXPECT_EQ(rep.impacts, hit.size());
  std::set<int> walls;
  for (std::size_t i = 0; i < hit.size(); ++i) {
    EXPECT_EQ(rep.events[i].name, "wall" + std::to_string(hit[i])) << i;
    EXPECT_NEAR(rep.events[i].t, when[i], 1e-8) << i;
    walls.insert(hit[i]);
  }
  EXPECT_GT(walls.size(), 150u);  // most of the 200 contacts closed at least once
  const Sample<2>& end = rec.samples.back();
  ASSERT_DOUBLE_EQ(end.t, t_end);
  EXPECT_NEAR(end.q[0], p[0] + (t_end - t) * v[0], 1e-8);
  EXPECT_NEAR(end.q[1], p[1] + (t_end - t) * v[1], 1e-8);
  EXPECT_NEAR(end.qd.norm(), 10.0, 1e-11);  // |v| kept by every impact (e = 1)
}

State<2> on_top(double R, double theta0) {
  State<2> s;
  s.q << R * std::sin(theta0), R * std::cos(theta0);
  return s;
}

TEST(Unilateral, ParticleLeavesTheSphereWhereTheNormalForceVanishes) {
  const double m = 0.5, R = 1.2, g = 9.81, theta0 = 0.1;
  const ParticleOffSphere model(m, R, g);
  const double cos_star = 2.0 / 3.0 * std::cos(theta0);
  for (const Method method : {Method::dopri5, Method::cash_karp54, Method::fehlberg78, Method::gauss_radau15, Method::rk4}) {
    SimulationOptions o;
    o.method = method;
    o.t_end = 2.0;
    o.rtol = 1e-12;
    o.atol = 1e-14;
    o.dt = 1e-3;
    o.output_interval = 0;  // every step, so the release point is a sample
    Recorder<2> rec;
    const RunReport r = simulate(model, on_top(R, theta0), o, rec);
    ASSERT_EQ(r.events.size(), 1u) << method;
    EXPECT_EQ(r.events[0].kind, EventKind::release) << method;
    EXPECT_EQ(r.events[0].name, "surface") << method;
    const double t_release = r.events[0].t;
    bool found = false;
    for (const auto& s : rec.samples) {
      if (s.t < t_release) {
        // On the surface: λ = N = m g (3 cos θ − 2 cos θ0) ≥ 0, along +∇g (outwards).
        const double cos_theta = s.q[1] / s.q.norm();
        EXPECT_NEAR(s.multipliers[0], m * g * (3 * cos_theta - 2 * std::cos(theta0)), 1e-7) << method << " " << s.t;
        EXPECT_GE(s.multipliers[0], -1e-9);
      } else if (s.t == t_release) {
        found = true;
        const double cos_theta = s.q[1] / R;
        EXPECT_NEAR(cos_theta, cos_star, method == Method::rk4 ? 1e-7 : 1e-9) << method;
        // Speed from energy: v² = 2 g R (cos θ0 − cos θ*).
        EXPECT_NEAR(s.qd.squaredNorm(), 2 * g * R * (std::cos(theta0) - cos_star), 1e-7) << method;
      } else {
        EXPECT_EQ(s.multipliers[0], 0.0) << method;  // free flight: no force
        EXPECT_GT(s.q.norm(), R) << method;        // moving away from the sphere
      }
    }
    EXPECT_TRUE(found) << method;
    EXPECT_LE(r.total_energy_drift_max, 1e-8) << method;
  }
}

TEST(Unilateral, StartingInsideOrIntoTheSurfaceIsAClearError) {
  const ParticleOffSphere model;
  State<2> inside;
  inside.q << 0.0, 0.9;
  try {
    simulate(model, inside, SimulationOptions{});
    FAIL() << "no error";
  } catch (const ConstraintError& e) {
    EXPECT_NE(std::string(e.what()).find("unilateral constraint surface is violated at t0: g = -0.09"),
              std::string::npos)
        << e.what();
  }
  State<2> diving = on_top(1.0, 0.0);
  diving.qd << 0.0, -1.0;
  EXPECT_THROW(simulate(model, diving, SimulationOptions{}), ConstraintError);
}

TEST(Unilateral, AboveTheSurfaceItIsInactive) {
  // Dropped from above: free fall until it would touch; no force before.
  const ParticleOffSphere model;
  State<2> s;
  s.q << 0.3, 3.0;
  SimulationOptions o;
  o.t_end = 0.2;
  o.output_interval = 0.05;
  Recorder<2> rec;
  simulate(model, s, o, rec);
  for (const auto& x : rec.samples) {
    EXPECT_EQ(x.multipliers[0], 0.0);
    EXPECT_NEAR(x.q[1], 3.0 - 0.5 * 9.81 * x.t * x.t, 1e-10);
  }
}

TEST(Unilateral, ComingBackIntoContactWithoutRestitutionIsReportedNotIgnored) {
  // Dropped onto the sphere: the contact is an impact, and this model
  // declares no restitution; the run must stop with a clear message, not
  // pass through.
  const ParticleOffSphere model;
  State<2> s;
  s.q << 0.0, 1.5;
  SimulationOptions o;
  o.t_end = 1.0;
  try {
    simulate(model, s, o);
    FAIL() << "no error";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("contact surface closed at t = "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("declares no restitution()"), std::string::npos) << e.what();
    // Free fall from y = 1.5 to the top of the unit sphere: t = sqrt(2 * 0.5 / g).
    EXPECT_NEAR(e.time(), std::sqrt(2 * 0.5 / 9.81), 1e-11);
  }
}

}  // namespace
