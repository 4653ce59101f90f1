// Kepler orbits of every conic in closed form: the universal-variable
// propagator against the eccentric anomaly (ellipses), the hyperbolic
// anomaly (hyperbolas) and Barker's equation (parabolas); its own
// conservation of energy and angular momentum; and simulated flybys checked
// against it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/kepler.hpp"
#include "lagrangian/models/two_body.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;
using V3 = Eigen::Vector3d;

// A rotation out of the x-y plane, so that no component is trivially zero.
const Eigen::Matrix3d& tilt() {
  static const Eigen::Matrix3d m =
      (Eigen::AngleAxisd(0.7, V3::UnitX()) * Eigen::AngleAxisd(-0.3, V3::UnitZ())).toRotationMatrix();
  return m;
}

double specific_energy(double gm, const V3& r, const V3& v) { return 0.5 * v.squaredNorm() - gm / r.norm(); }

TEST(Kepler, UniversalVariableAgreesWithTheEccentricAnomalyOnEllipses) {
  const double gm = 2.5;
  for (double e : {0.0, 0.3, 0.9, 0.999}) {
    const KeplerOrbit orbit(1.7, e, gm, 0.4);
    const auto s0 = orbit.state(0.0);
    const V3 r0 = tilt() * V3(s0[0], s0[1], 0), v0 = tilt() * V3(s0[2], s0[3], 0);
    const double P = orbit.period();
    for (double t : {-7.3, -0.2, 0.3, 1.7, 0.5 * P, 5.0 * P + 0.1, 23.0, 40.0 * P}) {
      const auto [re, ve] = elliptic_kepler_propagate(gm, r0, v0, t);
      const auto [ru, vu] = universal_kepler_propagate(gm, r0, v0, t);
      EXPECT_LE((ru - re).norm(), 1e-11 * orbit.a) << "e " << e << ", t " << t;
      EXPECT_LE((vu - ve).norm(), 1e-11 * orbit.periapsis_speed()) << "e " << e << ", t " << t;
    }
  }
}

// Hyperbola with periapsis distance r_p and eccentricity e > 1, a_h = r_p/(e − 1):
//   x = a_h (e − cosh H),  y = a_h √(e² − 1) sinh H,
//   n (t − t_p) = e sinh H − H,  n = √(GM/a_h³),  Ḣ = n / (e cosh H − 1).
TEST(Kepler, HyperbolasFollowTheHyperbolicAnomaly) {
  const double gm = 2.5, rp = 0.8;
  for (double e : {1.0001, 1.05, 2.0, 10.0}) {
    const double ah = rp / (e - 1.0), n = std::sqrt(gm / (ah * ah * ah)), b = std::sqrt(e * e - 1.0);
    const V3 r0 = tilt() * V3(rp, 0, 0), v0 = tilt() * V3(0, std::sqrt(gm * (1.0 + e) / rp), 0);
    for (double H : {-3.0, -0.5, 0.2, 1.0, 4.0, 9.0}) {
      const double t = (e * std::sinh(H) - H) / n, Hd = n / (e * std::cosh(H) - 1.0);
      const V3 r_exact = tilt() * V3(ah * (e - std::cosh(H)), ah * b * std::sinh(H), 0);
      const V3 v_exact = tilt() * V3(-ah * std::sinh(H) * Hd, ah * b * std::cosh(H) * Hd, 0);
      const auto [r, v] = kepler_propagate(gm, r0, v0, t);
      // The start state is rounded, and α = 2/r_p − v_p²/GM keeps only
      // ~ε/(e − 1) of it relative: near-parabolic orbits are known less well.
      const double tol = 1e-12 * (1.0 + 1e-3 / (e - 1.0));
      EXPECT_LE((r - r_exact).norm(), tol * r_exact.norm()) << "e " << e << ", H " << H;
      EXPECT_LE((v - v_exact).norm(), tol * v0.norm()) << "e " << e << ", H " << H;
    }
  }
}

// Parabola with periapsis distance q, D = tan(ν/2) (Barker's equation):
//   t − t_p = √(2q³/GM) (D + D³/3),  x = q (1 − D²),  y = 2 q D,
//   Ḋ = 1 / (√(2q³/GM) (1 + D²)).
TEST(Kepler, ParabolasFollowBarkersEquation) {
  const double gm = 2.5, q = 0.6, k = std::sqrt(2.0 * q * q * q / gm);
  const V3 r0 = tilt() * V3(q, 0, 0), v0 = tilt() * V3(0, std::sqrt(2.0 * gm / q), 0);
  for (double D : {-5.0, -1.0, 0.3, 2.0, 20.0}) {
    const double t = k * (D + D * D * D / 3.0), Dd = 1.0 / (k * (1.0 + D * D));
    const V3 r_exact = tilt() * V3(q * (1.0 - D * D), 2.0 * q * D, 0);
    const V3 v_exact = tilt() * V3(-2.0 * q * D * Dd, 2.0 * q * Dd, 0);
    const auto [r, v] = kepler_propagate(gm, r0, v0, t);
    EXPECT_LE((r - r_exact).norm(), 1e-12 * r_exact.norm()) << "D " << D;
    EXPECT_LE((v - v_exact).norm(), 1e-12 * v0.norm()) << "D " << D;
  }
}

TEST(Kepler, UnboundOrbitsKeepTheirEnergyAndAngularMomentum) {
  const double gm = 1.0;
  const V3 r0(1.0, 0.2, -0.1), h_dir(0.1, 0.3, 1.0);
  for (double speed : {std::sqrt(2.0 * gm / r0.norm()), 1.6, 5.0}) {
    const V3 v0 = speed * h_dir.cross(r0).normalized() + V3(0.3, -0.1, 0.05);
    const double E0 = specific_energy(gm, r0, v0);
    const V3 h0 = r0.cross(v0);
    for (double t : {-1e3, -2.0, 0.5, 10.0, 1e4}) {
      const auto [r, v] = kepler_propagate(gm, r0, v0, t);
      EXPECT_NEAR(specific_energy(gm, r, v), E0, 1e-12 * (0.5 * v0.squaredNorm())) << speed << " " << t;
      EXPECT_LE((r.cross(v) - h0).norm(), 1e-12 * r.norm() * v.norm()) << speed << " " << t;
      // Going back from (r, v) by −t returns to the start (over arcs that
      // stay within ~50 r₀; further out the round trip loses accuracy as
      // the distance grows: 5e-7 after 1e4 s at speed 5, see kepler.hpp).
      if (std::abs(t) <= 10.0) {
        const auto [rb, vb] = kepler_propagate(gm, r, v, -t);
        EXPECT_LE((rb - r0).norm(), 1e-12 * r0.norm()) << speed << " " << t;
        EXPECT_LE((vb - v0).norm(), 1e-12 * v0.norm()) << speed << " " << t;
      }
    }
  }
  EXPECT_THROW(kepler_propagate(1.0, V3(1, 0, 0), V3(2.0, 0, 0), 1.0), ParameterError);  // radial: meets the centre
}

// A hyperbolic flyby, simulated as the reduced problem and as the two-body
// problem; both report their error against the closed form.
TEST(Kepler, HyperbolicFlybysAreSimulatedAgainstTheClosedForm) {
  SimulationOptions o;
  o.method = Method::dopri5;
  o.rtol = 1e-12;
  o.atol = 1e-14;
  o.t_end = 40.0;
  o.output_interval = 1.0;

  const auto one = gravitational_relative_motion<2>(1.0, 1.0, 1.0);  // GM = k/μ = 2
  State<2> s;
  s.q << -20.0, 1.0;
  s.qd << 1.2, 0.0;  // v² = 1.44 > 2 GM / r ≈ 0.2: unbound
  const RunReport r1 = simulate(one, s, o);
  ASSERT_TRUE(r1.has_reference);
  EXPECT_LE(r1.reference_error_max, 1e-8);
  EXPECT_GT(r1.reference_error_max, 0.0);

  const auto two = gravitational_two_body<2>(1.0, 3.0, 1.0);
  State<4> x;
  x.q << 0.0, 0.0, -20.0, 1.5;
  x.qd << 0.0, 0.0, 1.0, 0.0;
  const RunReport r2 = simulate(two, x, o);
  ASSERT_TRUE(r2.has_reference);
  EXPECT_LE(r2.reference_error_max, 1e-8);
  std::printf("hyperbolic flyby, reference error: reduced %.2e, two-body %.2e\n", r1.reference_error_max,
              r2.reference_error_max);
}

}  // namespace
