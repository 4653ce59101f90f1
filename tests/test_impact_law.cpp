// Newton's law of restitution in generalized coordinates (apply_impact)
// against the course notes' closed forms for smooth spheres (corrected where
// misprinted), conservation of momentum, and a constrained system written two
// ways.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/impacts.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

constexpr double kClosedForm = 1e-13;  // agreement with the closed forms, relative to the speed scale
constexpr double kMomentum = 1e-12;    // momentum conservation, relative to Σ|m u|
const double kPi = std::acos(-1.0);

const std::array<double, 3> kRestitution = {0.0, 0.3, 1.0};
const std::array<double, 7> kMassRatios = {1e-9, 1e-6, 1e-3, 1.0, 1e3, 1e6, 1e9};

TEST(DirectImpact, GeneralLawGivesTheNotesVelocitiesImpulseAndEnergyLoss) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> speed(-5.0, 5.0);
  int checked = 0;
  for (double e : kRestitution) {
    for (double ratio : kMassRatios) {
      for (int k = 0; k < 10; ++k) {
        const double m1 = 0.7, m2 = 0.7 * ratio;
        double u1 = speed(rng), u2 = speed(rng);
        if (u1 < u2) std::swap(u1, u2);  // sphere 1 (left) catches sphere 2: approaching
        if (u1 == u2) continue;
        const SpheresOnLine<2> model({m1, m2}, {0.1, 0.2}, e);
        Vec<double, 2> q(0.0, 0.3), qd(u1, u2);  // touching: x2 − x1 = r1 + r2
        const auto res = apply_impact(model, q, qd, 0.0, 0, e);
        const DirectImpact d = direct_impact(m1, m2, u1, u2, e);
        const double vs = std::max(std::abs(u1), std::abs(u2));
        EXPECT_NEAR(qd[0], d.v1, kClosedForm * vs) << "e " << e << " ratio " << ratio;   // (1.3.3)
        EXPECT_NEAR(qd[1], d.v2, kClosedForm * vs) << "e " << e << " ratio " << ratio;   // (1.3.4) corrected
        // Newton's law along the line: v1 − v2 = −e (u1 − u2).
        EXPECT_NEAR(qd[0] - qd[1], -e * (u1 - u2), kClosedForm * vs);
        // Momentum m1 v1 + m2 v2 = m1 u1 + m2 u2 (1.3.1).
        const double p_scale = std::abs(m1 * u1) + std::abs(m2 * u2);
        EXPECT_NEAR(m1 * qd[0] + m2 * qd[1], m1 * u1 + m2 * u2, kMomentum * p_scale);
        // Impulse (Cor. 1): the impulse on sphere 1 is −Λ (Λ acts along +∇φ = +x on sphere 2).
        const double mu = m1 * m2 / (m1 + m2);
        EXPECT_NEAR(-res.impulse, d.impulse_on_1, kClosedForm * mu * std::abs(u1 - u2));
        EXPECT_NEAR(d.impulse_on_1, mu * (1 + e) * (u2 - u1), kClosedForm * mu * std::abs(u1 - u2));
        // Energy loss ½ μ (1 − e²)(u1 − u2)² (1.3.7), and none at e = 1.
        const double loss = res.kinetic_energy_before - res.kinetic_energy_after;
        const double t_scale = 0.5 * m1 * u1 * u1 + 0.5 * m2 * u2 * u2;
        EXPECT_NEAR(loss, d.kinetic_energy_loss, 1e-12 * t_scale);
        EXPECT_NEAR(d.kinetic_energy_loss, 0.5 * mu * (1 - e * e) * (u1 - u2) * (u1 - u2), 1e-14 * t_scale);
        if (e == 1.0) {
          EXPECT_NEAR(loss, 0.0, 1e-12 * t_scale);
        }
        EXPECT_NEAR(res.separation_speed, e * res.approach_speed, kClosedForm * vs);
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 200);
}

TEST(DirectImpact, TheNotesPrintedFormulaForV2BreaksMomentumTheCorrectedOneKeepsIt) {
  // Notes (1.3.4) as printed: v2 = (m1 u1 (1 + e) + u2 (m2 + e m1)) / (m1 + m2).
  const double m1 = 2.0, m2 = 3.0, u1 = 4.0, u2 = 1.0, e = 0.5;
  const double printed = (m1 * u1 * (1 + e) + u2 * (m2 + e * m1)) / (m1 + m2);
  const DirectImpact d = direct_impact(m1, m2, u1, u2, e);
  const double p0 = m1 * u1 + m2 * u2;
  EXPECT_NEAR(m1 * d.v1 + m2 * d.v2, p0, 1e-14 * p0);
  // The printed version gains 2 e m1 u2 · m2/(m1+m2) of momentum.
  EXPECT_NEAR(m1 * d.v1 + m2 * printed - p0, 2 * e * m1 * u2 * m2 / (m1 + m2), 1e-12);
  EXPECT_GT(std::abs(m1 * d.v1 + m2 * printed - p0), 0.1);
}

TEST(DirectImpact, EqualPerfectlyElasticSpheresExchangeVelocities) {
  // Cor. 2: m1 = m2, e = 1 ⇒ v1 = u2, v2 = u1.
  const SpheresOnLine<2> model({1.5, 1.5}, {0.5, 0.5}, 1.0);
  for (const auto& [u1, u2] : {std::pair{3.0, -1.0}, std::pair{2.0, 0.0}, std::pair{1e-6, -7.0}}) {
    Vec<double, 2> q(0.0, 1.0), qd(u1, u2);
    apply_impact(model, q, qd, 0.0, 0, 1.0);
    EXPECT_NEAR(qd[0], u2, 1e-15 * std::abs(u1 - u2));
    EXPECT_NEAR(qd[1], u1, 1e-15 * std::abs(u1 - u2));
  }
}

TEST(DirectImpact, SeparatingSpheresAreLeftAlone) {
  const SpheresOnLine<2> model({1.0, 2.0}, {0.5, 0.5}, 0.5);
  Vec<double, 2> q(0.0, 1.0), qd(-1.0, 1.0);
  const auto res = apply_impact(model, q, qd, 0.0, 0, 0.5);
  EXPECT_EQ(res.impulse, 0.0);
  EXPECT_EQ(qd[0], -1.0);
  EXPECT_EQ(qd[1], 1.0);
}

// Oblique impact in 2-D and 3-D: sphere 1 at the origin, sphere 2 touching it
// along the unit normal n; velocities at angles α, β to n.
template <int D>
void check_oblique(std::mt19937_64& rng) {
  using V = Eigen::Matrix<double, D, 1>;
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> speed(0.5, 5.0);
  const std::array<double, 5> angles_deg = {0.0, 30.0, 60.0, 85.0, 89.9};
  int checked = 0;
  for (double e : kRestitution) {
    for (double ratio : kMassRatios) {
      for (double a_deg : angles_deg) {
        for (double b_deg : angles_deg) {
          const double m1 = 1.3, m2 = 1.3 * ratio, r1 = 0.2, r2 = 0.35;
          V n;
          for (int k = 0; k < D; ++k) n[k] = gauss(rng);
          n.normalize();
          // Unit tangents: 2-D has one (up to sign); 3-D picks two different ones.
          auto tangent = [&]() {
            V t;
            for (int k = 0; k < D; ++k) t[k] = gauss(rng);
            t -= t.dot(n) * n;
            return V(t.normalized());
          };
          const V t1 = tangent(), t2 = tangent();
          const double alpha = a_deg * kPi / 180, beta = (180.0 - b_deg) * kPi / 180;  // sphere 2 moves towards 1
          const double u1 = speed(rng), u2 = speed(rng);
          const V u1v = u1 * (std::cos(alpha) * n + std::sin(alpha) * t1);
          const V u2v = u2 * (std::cos(beta) * n + std::sin(beta) * t2);
          if (!(u2v.dot(n) - u1v.dot(n) < 0)) continue;  // must approach
          const TwoSpheres<D> model(m1, m2, r1, r2, e);
          Vec<double, 2 * D> q, qd;
          q << V::Zero(), (r1 + r2) * n;
          qd << u1v, u2v;
          const auto res = apply_impact(model, q, qd, 0.0, 0, e);
          const V v1 = qd.template head<D>(), v2 = qd.template tail<D>();
          const ObliqueImpact o = oblique_impact(m1, m2, u1, u2, alpha, beta, e);
          const double vs = std::max(u1, u2);
          const std::string where = "D " + std::to_string(D) + " e " + std::to_string(e) + " ratio " +
                                    std::to_string(ratio) + " alpha " + std::to_string(a_deg) + " beta " +
                                    std::to_string(b_deg);
          EXPECT_NEAR(v1.dot(n), o.v1_normal, kClosedForm * vs) << where;  // (1.4.5)
          EXPECT_NEAR(v2.dot(n), o.v2_normal, kClosedForm * vs) << where;  // (1.4.6) corrected
          // Tangential components unchanged (1.4.3–1.4.4).
          EXPECT_LE((v1 - v1.dot(n) * n - u1 * std::sin(alpha) * t1).norm(), kClosedForm * vs) << where;
          EXPECT_LE((v2 - v2.dot(n) * n - u2 * std::sin(beta) * t2).norm(), kClosedForm * vs) << where;
          EXPECT_NEAR(v1.norm(), o.v1, kClosedForm * vs) << where;
          EXPECT_NEAR(v2.norm(), o.v2, kClosedForm * vs) << where;
          // Directions: the angle θ of v1 with the common normal.
          if (v1.norm() > 1e-3 * vs) {
            EXPECT_NEAR(std::atan2((v1 - v1.dot(n) * n).norm(), v1.dot(n)), std::abs(o.theta), 1e-10) << where;
          }
          // … and φ of v2 (notes 1.4: tan φ = v₂ sin φ / v₂ cos φ from (1.4.4) and (1.4.6)).
          if (v2.norm() > 1e-3 * vs) {
            EXPECT_NEAR(std::atan2((v2 - v2.dot(n) * n).norm(), v2.dot(n)), std::abs(o.phi), 1e-10) << where;
          }
          // Impulse (1.4.7): on sphere 1 along n, equal and opposite on sphere 2.
          const double mu = m1 * m2 / (m1 + m2);
          const double i_scale = mu * vs;
          EXPECT_NEAR(o.impulse_on_1, mu * (1 + e) * (u2 * std::cos(beta) - u1 * std::cos(alpha)), kClosedForm * i_scale);
          EXPECT_LE((res.generalized_impulse.template head<D>() - o.impulse_on_1 * n).norm(), kClosedForm * i_scale)
              << where;
          EXPECT_LE((res.generalized_impulse.template tail<D>() + o.impulse_on_1 * n).norm(), kClosedForm * i_scale)
              << where;
          // Momentum, all components.
          const double p_scale = m1 * u1 + m2 * u2;
          EXPECT_LE((m1 * v1 + m2 * v2 - m1 * u1v - m2 * u2v).norm(), kMomentum * p_scale) << where;
          // Energy loss with u cos α, u cos β (1.4.1).
          const double uc = u1 * std::cos(alpha) - u2 * std::cos(beta);
          const double t_scale = 0.5 * m1 * u1 * u1 + 0.5 * m2 * u2 * u2;
          EXPECT_NEAR(res.kinetic_energy_before - res.kinetic_energy_after, 0.5 * mu * (1 - e * e) * uc * uc,
                      1e-12 * t_scale)
              << where;
          EXPECT_NEAR(o.kinetic_energy_loss, 0.5 * mu * (1 - e * e) * uc * uc, 1e-14 * t_scale) << where;
          // The vector form agrees with the general law too.
          const auto sv = smooth_spheres_impact<D>(m1, m2, u1v, u2v, n, e);
          EXPECT_LE((sv.v1 - v1).norm(), kClosedForm * vs) << where;
          EXPECT_LE((sv.v2 - v2).norm(), kClosedForm * vs) << where;
          ++checked;
        }
      }
    }
  }
  EXPECT_GE(checked, 300);
}

TEST(ObliqueImpact, GeneralLawGivesTheNotesComponentsIn2D) {
  std::mt19937_64 rng(7);
  check_oblique<2>(rng);
}

TEST(ObliqueImpact, GeneralLawGivesTheNotesComponentsIn3D) {
  std::mt19937_64 rng(11);
  check_oblique<3>(rng);
}

TEST(ObliqueImpact, TheNotesPrintedFormulaForV2UsesTheWrongVelocity) {
  // Notes (1.4.6) as printed has v1 cos α (after impact) where u1 cos α belongs.
  const double m1 = 1.0, m2 = 2.0, u1 = 3.0, u2 = 1.0, alpha = 0.4, beta = 2.5, e = 0.6;
  const ObliqueImpact o = oblique_impact(m1, m2, u1, u2, alpha, beta, e);
  const double printed = (m1 * (1 + e) * o.v1 * std::cos(alpha) + (m2 - e * m1) * u2 * std::cos(beta)) / (m1 + m2);
  const double pn = m1 * u1 * std::cos(alpha) + m2 * u2 * std::cos(beta);
  EXPECT_NEAR(m1 * o.v1_normal + m2 * o.v2_normal, pn, 1e-14 * std::abs(pn) + 1e-15);
  EXPECT_GT(std::abs(m1 * o.v1_normal + m2 * printed - pn), 0.1);
}

// A pendulum bob (length l, pivot at the origin, angle θ from the downward
// vertical) hitting a vertical wall x = w, written in θ and in Cartesian
// coordinates with a rod constraint: the same bob velocity after impact.
struct PendulumAngle {
  static constexpr int dof = 1;
  double m = 0.8, l = 1.2, g = 9.81, w = 0.6, e = 0.7;
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * m * l * l * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    using std::cos;
    return -m * g * l * cos(q[0]);
  }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 1>& q, const S&) const {
    using std::sin;
    return Vec<S, 1>(w - l * sin(q[0]));
  }
  std::array<double, 1> restitution() const { return {e}; }
};
struct PendulumCartesian {
  static constexpr int dof = 2;
  double m = 0.8, l = 1.2, g = 9.81, w = 0.6, e = 0.7;
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return m * g * q[1];
  }
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 2>& q, const S&) const {
    using std::sqrt;
    return Vec<S, 1>(sqrt(q[0] * q[0] + q[1] * q[1]) - l);
  }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(w - q[0]);
  }
  std::array<double, 1> restitution() const { return {e}; }
};

TEST(ImpactLaw, ConstrainedPendulumAgreesInAngleAndInCartesianCoordinates) {
  const PendulumAngle a;
  const PendulumCartesian c;
  const double theta = std::asin(a.w / a.l), omega = 2.3;
  Vec<double, 1> qa(theta), va(omega);
  const auto ra = apply_impact(a, qa, va, 0.0, 0, a.e);
  Vec<double, 2> qc(a.l * std::sin(theta), -a.l * std::cos(theta));
  Vec<double, 2> vc(a.l * std::cos(theta) * omega, a.l * std::sin(theta) * omega);
  const auto rc = apply_impact(c, qc, vc, 0.0, 0, c.e);
  // In θ the law is θ̇⁺ = −e θ̇⁻.
  EXPECT_NEAR(va[0], -a.e * omega, 1e-14 * omega);
  // The Cartesian bob moves with the same velocity and stays on the rod.
  EXPECT_NEAR(vc[0], a.l * std::cos(theta) * va[0], 1e-13 * a.l * omega);
  EXPECT_NEAR(vc[1], a.l * std::sin(theta) * va[0], 1e-13 * a.l * omega);
  EXPECT_NEAR(qc.dot(vc), 0.0, 1e-13 * a.l * a.l * omega);
  EXPECT_NEAR(ra.kinetic_energy_after, rc.kinetic_energy_after, 1e-13 * ra.kinetic_energy_before);
  // The wall's impulse differs (the pivot takes part of it in Cartesian
  // form) but the loss is (1 − e²) of the kinetic energy in both.
  EXPECT_NEAR(rc.kinetic_energy_after, a.e * a.e * rc.kinetic_energy_before, 1e-13 * rc.kinetic_energy_before);
}

TEST(ImpactLaw, APendulumHittingAWallMovesAlikeInBothFormulations) {
  // Released at θ = −0.9 rad, the bob swings into the wall at θ* = asin(w/l)
  // and bounces back with e = 0.7, several times, over 10 s: the Cartesian run
  // (rod constraint, projection, contact) follows the angle run.
  const PendulumAngle a;
  const PendulumCartesian c;
  const double theta0 = -0.9;
  State<1> sa;
  sa.q << theta0;
  sa.qd << 0.0;
  State<2> sc;
  sc.q << a.l * std::sin(theta0), -a.l * std::cos(theta0);
  sc.qd << 0.0, 0.0;
  SimulationOptions o;
  o.t_end = 10.0;
  o.rtol = 1e-12;
  o.atol = 1e-14;
  o.output_interval = 0.5;
  Recorder<1> ra;
  Recorder<2> rc;
  const RunReport pa = simulate(a, sa, o, ra);
  const RunReport pc = simulate(c, sc, o, rc);
  ASSERT_GE(pa.impacts, 4u);
  ASSERT_EQ(pa.impacts, pc.impacts);
  for (std::size_t k = 0; k < pa.events.size(); ++k) {
    EXPECT_NEAR(pa.events[k].t, pc.events[k].t, 1e-9) << k;
    EXPECT_NEAR(pa.events[k].kinetic_energy_after, pc.events[k].kinetic_energy_after, 1e-9) << k;
  }
  ASSERT_EQ(ra.samples.size(), rc.samples.size());
  for (std::size_t k = 0; k < ra.samples.size(); ++k) {
    const double theta_c = std::atan2(rc.samples[k].q[0], -rc.samples[k].q[1]);
    EXPECT_NEAR(ra.samples[k].q[0], theta_c, 1e-8) << "t = " << ra.samples[k].t;
  }
  // Each bounce keeps e² of the kinetic energy at the wall.
  for (const auto& ev : pa.events) {
    if (ev.kind == EventKind::impact) {
      EXPECT_NEAR(ev.kinetic_energy_after, a.e * a.e * ev.kinetic_energy_before, 1e-12 * ev.kinetic_energy_before);
    }
  }
  EXPECT_LE(pc.constraints.max_position_residual, 1e-12 * (1 + a.l));  // projection_tolerance · (1 + ‖q‖∞)
}

TEST(ImpactLaw, RestitutionOutsideTheUnitIntervalIsAClearError) {
  const SpheresOnLine<2> model({1.0, 1.0}, {0.5, 0.5}, 0.5);
  Vec<double, 2> q(0.0, 1.0), qd(1.0, -1.0);
  for (double bad : {-0.1, 1.5, std::nan("")}) {
    try {
      apply_impact(model, q, qd, 0.0, 0, bad);
      FAIL() << "no error for e = " << bad;
    } catch (const ParameterError& err) {
      EXPECT_NE(std::string(err.what()).find("restitution e must be in [0, 1], got"), std::string::npos) << err.what();
    }
  }
  EXPECT_EQ(qd[0], 1.0);  // untouched
  try {
    SpheresOnLine<2>({1.0, 1.0}, {0.5, 0.5}, 1.2);
    FAIL() << "no error";
  } catch (const ParameterError& err) {
    EXPECT_NE(std::string(err.what()).find("SpheresOnLine: parameter 'e' must be in [0, 1], got 1.2"),
              std::string::npos)
        << err.what();
  }
  EXPECT_THROW(direct_impact(1.0, -2.0, 1.0, 0.0, 0.5), ParameterError);
  EXPECT_THROW(direct_impact(1.0, 2.0, std::nan(""), 0.0, 0.5), ParameterError);
  EXPECT_THROW(TwoSpheres<3>(1.0, 1.0, 0.1, 0.1, -0.5), ParameterError);
  EXPECT_THROW(BallAndPlane(1.0, 0.1, 0.5, 9.81, {0.0, 0.0, 0.0}), ParameterError);
}

}  // namespace
