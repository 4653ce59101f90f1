// Projectiles (course notes 1.5, corrected): flight time, range and height
// over flat ground and up and down an inclined plane, the landing as an
// event; linear drag against its closed form; quadratic drag's terminal
// speed; aiming with NLopt.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/projectile_aim.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;
const double kPi = std::acos(-1.0);
const double kDeg = kPi / 180;

SimulationOptions tight() {
  SimulationOptions o;
  o.t_end = 100.0;
  o.rtol = 1e-12;
  o.atol = 1e-14;
  o.output_interval = -1;
  return o;
}

TEST(Projectile, FlightTimeRangeAndHeightOverFlatGroundAndInclines) {
  const double u = 20.0, g = 9.81;
  int checked = 0;
  for (double beta_deg : {0.0, 15.0, 30.0, -20.0, -45.0}) {  // flat, up the slope, down the slope
    const Projectile<> p(0.5, g, beta_deg * kDeg);
    for (double alpha_deg : {10.0, 35.0, 45.0, 60.0, 89.0, 90.0}) {
      const double alpha = alpha_deg * kDeg;
      if (!(alpha > p.beta)) continue;
      Recorder<2> rec;
      const RunReport r = simulate(p, p.launch(u, alpha), tight(), rec);
      ASSERT_EQ(r.stopped_by, "landing") << beta_deg << " " << alpha_deg;
      const double T = p.flight_time(u, alpha), R = p.range(u, alpha);
      const auto& end = rec.samples.back();
      const std::string where = "beta " + std::to_string(beta_deg) + " alpha " + std::to_string(alpha_deg);
      EXPECT_NEAR(r.stopped_at, T, 1e-12 * T) << where;
      const double along = std::hypot(end.q[0], end.q[1]);
      EXPECT_NEAR(along, std::abs(R), 1e-12 * std::abs(R) + 1e-13) << where;
      // The apex at u sin α / g, unless the slope is met first.
      const double t_apex = u * std::sin(alpha) / g;
      if (t_apex < T) {
        ASSERT_EQ(r.events[0].name, "apex") << where;
        EXPECT_NEAR(r.events[0].t, t_apex, 1e-12) << where;
      } else {
        EXPECT_EQ(r.events[0].name, "landing") << where;
      }
      ++checked;
    }
  }
  EXPECT_GE(checked, 25);
  // Flat ground: the textbook forms.
  const Projectile<> flat(1.0, g);
  const double a = 35 * kDeg;
  EXPECT_NEAR(flat.flight_time(u, a), 2 * u * std::sin(a) / g, 1e-15);
  EXPECT_NEAR(flat.range(u, a), u * u * std::sin(2 * a) / g, 1e-12);
  // The simulated apex height.
  Recorder<2> rec;
  SimulationOptions o = tight();
  o.output_interval = 0;  // every step, so the apex (a step end) is a sample
  const RunReport r = simulate(flat, flat.launch(u, a), o, rec);
  double top = 0;
  for (const auto& s : rec.samples) top = std::max(top, s.q[1]);
  EXPECT_NEAR(top, flat.max_height(u, a), 1e-11);
  EXPECT_EQ(r.events.size(), 3u);  // apex, landing, stop
}

TEST(Projectile, TheNotesInclineDerivationChecksOut) {
  // Notes 1.5.2: R = u cos(α−θ) T − ½ g sin θ T² with T = 2u sin(α−θ)/(g cos θ)
  // (the print has u sin(α−θ) in the first term); the final form is right.
  const double u = 13.0, g = 9.81, theta = 0.3, alpha = 0.9;
  const double T = 2 * u * std::sin(alpha - theta) / (g * std::cos(theta));
  const double R = u * std::cos(alpha - theta) * T - 0.5 * g * std::sin(theta) * T * T;
  const Projectile<> p(1.0, g, theta);
  EXPECT_NEAR(R, p.range(u, alpha), 1e-12 * R);
  const double printed = u * std::sin(alpha - theta) * T - 0.5 * g * std::sin(theta) * T * T;
  EXPECT_GT(std::abs(printed - R), 1.0);
}

TEST(Projectile, OneDimensionalThrows) {
  // Straight up: back down at 2u/g; straight down from a height: a falling
  // y reaches the ground at the free-fall time.
  const Projectile<> flat(1.0, 9.81);
  const RunReport up = simulate(flat, flat.launch(7.0, kPi / 2), tight());
  EXPECT_NEAR(up.stopped_at, 2 * 7.0 / 9.81, 1e-12);
  State<2> down;
  down.q << 0.0, 10.0;
  down.qd << 0.0, -3.0;
  const RunReport r = simulate(flat, down, tight());
  EXPECT_EQ(r.stopped_by, "landing");
  EXPECT_NEAR(r.stopped_at, (-3.0 + std::sqrt(9.0 + 2 * 9.81 * 10.0)) / 9.81, 1e-12);
}

TEST(Projectile, LinearDragFollowsItsClosedForm) {
  const Projectile<Drag::linear> p(0.4, 9.81, 0.0, 0.12);  // k = b/m = 0.3 /s
  const double u = 30.0, alpha = 50 * kDeg;
  SimulationOptions o = tight();
  o.output_interval = 0.05;
  Recorder<2> rec;
  const RunReport r = simulate(p, p.launch(u, alpha), o, rec);
  double worst = 0;  // max over samples of max(|Δx|, |Δy|), the report's measure
  for (const auto& s : rec.samples) {
    const auto ref = p.linear_drag_position(u, alpha, s.t);
    worst = std::max({worst, std::abs(s.q[0] - ref[0]), std::abs(s.q[1] - ref[1])});
  }
  EXPECT_LE(worst, 1e-10);
  EXPECT_FALSE(r.conservative);
  ASSERT_TRUE(r.has_reference);
  EXPECT_NEAR(r.reference_error_max, worst, 1e-15);  // the run measured the same true error itself
  // Shorter than without drag.
  EXPECT_LT(rec.samples.back().q[0], Projectile<>(0.4).range(u, alpha));
}

TEST(Projectile, QuadraticDragReachesTheTerminalSpeedAndOnlyDissipates) {
  const Projectile<Drag::quadratic> p(0.2, 9.81, 0.0, 0.01);  // v_t = √(m g / c) = 14.0 m/s
  State<2> s;
  s.q << 0.0, 1e4;
  s.qd << 5.0, 0.0;
  SimulationOptions o = tight();
  o.t_end = 30.0;
  o.output_interval = 0.5;
  Recorder<2> rec;
  simulate(p, s, o, rec);
  const auto& end = rec.samples.back();
  EXPECT_NEAR(end.qd.norm(), p.terminal_speed(), 1e-9 * p.terminal_speed());
  EXPECT_NEAR(end.qd[0], 0.0, 1e-6);  // the horizontal motion has died away
  for (std::size_t k = 1; k < rec.samples.size(); ++k)
    EXPECT_LT(rec.samples[k].total_energy, rec.samples[k - 1].total_energy);  // drag only takes energy
  // Dropped from rest (where |v| has no derivative): still the terminal speed.
  State<2> rest;
  rest.q << 0.0, 1e4;
  rest.qd << 0.0, 0.0;
  Recorder<2> fall;
  simulate(p, rest, o, fall);
  EXPECT_NEAR(fall.samples.back().qd[1], -p.terminal_speed(), 1e-9 * p.terminal_speed());
}

TEST(Projectile, NLoptFindsTheBestElevationOnAnIncline) {
  for (double beta : {0.0, 20 * kDeg, -30 * kDeg}) {
    const Projectile<> p(1.0, 9.81, beta);
    // The default start (a third of the way up the bracket) is 11° or more
    // from the answer; starts near either end of the bracket find it too.
    const Aim best = best_elevation(p, 15.0, tight());
    for (double start : {beta + 2 * kDeg, 88 * kDeg}) {
      const Aim from = best_elevation(p, 15.0, tight(), start);
      EXPECT_NEAR(from.alpha, p.best_elevation(), 1e-6) << beta << " from " << start;
    }
    // α* = π/4 + β/2, R_max = u² / (g (1 + sin β)); the range is flat at its
    // maximum, so α is found to ~√(rtol) and R to ~rtol.
    EXPECT_NEAR(best.alpha, p.best_elevation(), 1e-6) << beta;
    EXPECT_NEAR(best.value, p.max_range(15.0), 1e-10 * p.max_range(15.0)) << beta;
    std::printf("beta %.1f deg: best elevation %.9f deg (closed form %.9f), range %.12f m, %d flights\n",
                beta / kDeg, best.alpha / kDeg, p.best_elevation() / kDeg, best.value, best.evaluations);
  }
  // With drag the best elevation is lower than 45 degrees.
  const Projectile<Drag::linear> dragged(1.0, 9.81, 0.0, 0.5);
  EXPECT_LT(best_elevation(dragged, 30.0, tight()).alpha, 44 * kDeg);
}

TEST(Projectile, NLoptFindsTheTwoElevationsThatHitATarget) {
  const Projectile<> p(1.0, 9.81);
  const double u = 25.0, x = 40.0, y = 6.0, g = 9.81;
  const auto [low, high] = elevations_to_hit(p, u, x, y, 1e-9, tight());
  // tan α = (u² ± √(u⁴ − g(g x² + 2 y u²))) / (g x).
  const double disc = std::sqrt(u * u * u * u - g * (g * x * x + 2 * y * u * u));
  EXPECT_NEAR(low.alpha, std::atan((u * u - disc) / (g * x)), 1e-9);
  EXPECT_NEAR(high.alpha, std::atan((u * u + disc) / (g * x)), 1e-9);
  EXPECT_LE(low.value, 1e-9);
  EXPECT_LE(high.value, 1e-9);
  // Out of reach: a clear error.
  try {
    elevations_to_hit(p, 10.0, 40.0, 6.0, 1e-9, tight());
    FAIL() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("the target (40, 6) m is out of reach at u = 10 m/s"), std::string::npos)
        << e.what();
  }
}

TEST(Projectile, AStartBelowItsPlaneIsRefusedNamingTheEdge) {
  // The landing event (y − x tan β falls through 0) ends the model's domain: a projectile started under
  // the plane would fly through the ground. 1 m below a 10° incline at x = 2 m: y − x tan β = −1 − 2 tan 10°.
  const Projectile<> p(1.0, 9.81, 10 * kDeg);
  State<2> s;
  s.q << 2.0, -1.0;
  s.qd << 3.0, 4.0;
  try {
    simulate(p, s, tight());
    FAIL() << "a start below the plane was accepted";
  } catch (const DomainError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'landing'"), std::string::npos) << m;
    char value[32];
    std::snprintf(value, sizeof value, "%.6g", -1.0 - 2.0 * std::tan(10 * kDeg));
    EXPECT_NE(m.find(std::string(value).substr(0, 6)), std::string::npos) << m;
  }
  // On the plane is inside the domain: the launch point itself.
  EXPECT_NO_THROW(simulate(p, p.launch(10.0, 40 * kDeg), tight()));
}

TEST(Projectile, BadInputIsAClearError) {
  const Projectile<> p(1.0, 9.81, 30 * kDeg);
  EXPECT_THROW(p.launch(-1.0, 0.8), ParameterError);
  try {
    p.launch(10.0, 20 * kDeg);  // below the plane: no flight
    FAIL() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("Projectile: parameter 'alpha' must be above the plane"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(p.launch(10.0, 100 * kDeg), ParameterError);
  EXPECT_THROW(Projectile<>(-1.0), ParameterError);
  EXPECT_THROW(Projectile<>(1.0, 9.81, kPi / 2), ParameterError);
  EXPECT_THROW(Projectile<>(1.0, 9.81, 0.0, 0.3), ParameterError);  // drag without declaring it
  EXPECT_THROW(Projectile<Drag::linear>(1.0, 9.81, 0.0, -0.3), ParameterError);
}

}  // namespace
