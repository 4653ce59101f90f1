// Tiny and huge scales: the same Kepler orbit with lengths 1e-9 m and 1e9 m
// and masses 1e-27 kg and 1e30 kg, and the same double pendulum with rods
// of 1e-9 m and 1e9 m: in units of L (and L/s), every run agrees with the
// unit-scale run to 1e-10.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/two_body.hpp"
#include "stability_helpers.hpp"

namespace {

using namespace lagrangian;

struct Scale {
  double length, mass;
};
constexpr Scale kScales[] = {{1e-9, 1e-27}, {1e9, 1e30}, {1e-9, 1e30}, {1e9, 1e-27}};

std::string label(const Scale& s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "L = %.0e m, m = %.0e kg", s.length, s.mass);
  return buf;
}

/// Final state of an e = 0.5 Kepler orbit (one period is 2π s: GM = L³/s²)
/// after 10 s, in units of L and L/s.
State<2> kepler_final(const Scale& s, Method method) {
  const double L = s.length;
  const models::RelativeMotion<2> model(s.mass, models::NewtonianGravity{s.mass * L * L * L});
  State<2> x0;
  x0.q << 0.5 * L, 0.0;
  x0.qd << 0.0, std::sqrt(3.0) * L;  // periapsis of a = L, e = 0.5
  SimulationOptions o;
  o.method = method;
  o.t_end = 10.0;
  o.rtol = 1e-13;
  o.atol = 1e-15 * L;  // absolute tolerances carry the length unit
  o.dt = 1e-3;
  o.output_interval = -1;
  State<2> last;
  simulate(model, x0, o, [&](const Sample<2>& smp) {
    last.q = smp.q / L;
    last.qd = smp.qd / L;
  });
  return last;
}

TEST(StabilityScales, KeplerNondimensionalAgreement) {
  for (const Method method : {Method::dopri5, Method::variational}) {
    const State<2> ref = kepler_final({1.0, 1.0}, method);
    double worst = 0;
    for (const Scale& s : kScales) {
      const State<2> x = kepler_final(s, method);
      const double d = std::max((x.q - ref.q).lpNorm<Eigen::Infinity>(), (x.qd - ref.qd).lpNorm<Eigen::Infinity>());
      EXPECT_LE(d, 1e-10) << method << " " << label(s);
      worst = std::max(worst, d);
    }
    stability::record("Kepler e = 0.5, 10 s, L = 1e-9/1e9 m, m = 1e-27/1e30 kg: max |x/L - x_unit|", method, worst,
                      1e-10);
  }
}

/// Final angles and rates of a double pendulum of rods L and bobs m with
/// g = 9.81 L/s² (the same motion in units of L) after 10 s, released from
/// θ1 = 0.5, θ2 = 0.3 rad.
State<2> pendulum_final(const Scale& s, Method method) {
  const models::DoublePendulum model(s.mass, s.mass, s.length, s.length, 9.81 * s.length);
  State<2> x0;
  x0.q << 0.5, 0.3;  // regular motion: a chaotic one would amplify the last-bit differences of g/L
  SimulationOptions o;
  o.method = method;
  o.t_end = 10.0;
  o.rtol = 1e-13;
  o.atol = 1e-15;
  o.dt = 1e-3;
  o.output_interval = -1;
  State<2> last;
  simulate(model, x0, o, [&](const Sample<2>& smp) {
    last.q = smp.q;
    last.qd = smp.qd;
  });
  return last;
}

TEST(StabilityScales, DoublePendulumNondimensionalAgreement) {
  for (const Method method : {Method::dopri5, Method::variational}) {
    const State<2> ref = pendulum_final({1.0, 1.0}, method);
    double worst = 0;
    for (const Scale& s : kScales) {
      const State<2> x = pendulum_final(s, method);
      const double d = std::max((x.q - ref.q).lpNorm<Eigen::Infinity>(), (x.qd - ref.qd).lpNorm<Eigen::Infinity>());
      EXPECT_LE(d, 1e-10) << method << " " << label(s);
      worst = std::max(worst, d);
    }
    stability::record("double pendulum, 10 s, L = 1e-9/1e9 m, m = 1e-27/1e30 kg: max |angle, rate - unit run|", method,
                      worst, 1e-10);
  }
}

}  // namespace
