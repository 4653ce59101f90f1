// The tangent flow by AD (analysis/tangent_flow.hpp) and the Lyapunov
// exponents built on it (analysis/lyapunov.hpp), against closed forms,
// finite differences of the library's q̈, and Liouville's theorem.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "tangent_options.hpp"
#include "lagrangian/models/projectile.hpp"
#include "nested_jet_jacobian.hpp"

namespace {

using lagrangian::Vec;
namespace lm = lagrangian::models;

/// ∂q̈/∂x_j by central differences of accelerations() (step 1e-5 · max(1, |x_j|):
/// truncation ~1e-10, rounding ~1e-11 relative).
template <class M>
Eigen::Matrix<double, M::coordinate_count, 2 * M::coordinate_count> differenced(const M& model,
                                                                                Vec<double, M::coordinate_count> q,
                                                                                Vec<double, M::coordinate_count> qd,
                                                                                double t) {
  constexpr int n = M::coordinate_count;
  Eigen::Matrix<double, n, 2 * n> j;
  for (int c = 0; c < 2 * n; ++c) {
    double& x = c < n ? q[c] : qd[c - n];
    const double x0 = x, h = 1e-5 * std::max(1.0, std::abs(x0));
    x = x0 + h;
    const Vec<double, n> up = lagrangian::accelerations(model, q, qd, t);
    x = x0 - h;
    const Vec<double, n> down = lagrangian::accelerations(model, q, qd, t);
    x = x0;
    j.col(c) = (up - down) / (2 * h);
  }
  return j;
}

template <class M>
void expect_jacobian_agrees(const M& model, const Vec<double, M::coordinate_count>& q,
                            const Vec<double, M::coordinate_count>& qd, double t) {
  constexpr int n = M::coordinate_count;
  Vec<double, n> qdd;
  Eigen::Matrix<double, n, 2 * n> jac;
  lagrangian::state_jacobian(model, q, qd, t, qdd, jac);
  const Vec<double, n> library = lagrangian::accelerations(model, q, qd, t);
  EXPECT_LE((qdd - library).norm(), 1e-13 * (1 + library.norm())) << model.name();
  const auto fd = differenced(model, q, qd, t);
  EXPECT_LE((jac - fd).norm(), 1e-7 * (1 + fd.norm())) << model.name() << "\nAD:\n" << jac << "\nFD:\n" << fd;
  // Along given directions without J (state_jvp): J V to rounding, for one
  // direction and for two.
  Eigen::Matrix<double, 2 * n, 2> v;
  for (int i = 0; i < 2 * n; ++i) {
    v(i, 0) = std::cos(1.0 + 0.7 * i);
    v(i, 1) = 0.5 - 0.3 * i;
  }
  Vec<double, n> qdd1, qdd2;
  Eigen::Matrix<double, n, 1> jv1;
  Eigen::Matrix<double, n, 2> jv2;
  lagrangian::state_jvp<1>(model, q, qd, t, Eigen::Matrix<double, 2 * n, 1>(v.col(0)), qdd1, jv1);
  lagrangian::state_jvp<2>(model, q, qd, t, v, qdd2, jv2);
  const Eigen::Matrix<double, n, 2> jv = jac * v;
  EXPECT_LE((qdd1 - qdd).norm(), 1e-14 * (1 + qdd.norm())) << model.name();
  EXPECT_LE((qdd2 - qdd).norm(), 1e-14 * (1 + qdd.norm())) << model.name();
  EXPECT_LE((jv1 - jv.col(0)).norm(), 1e-13 * (1 + jv.norm())) << model.name() << "\n" << jv1 << "\n" << jv;
  EXPECT_LE((jv2 - jv).norm(), 1e-13 * (1 + jv.norm())) << model.name() << "\n" << jv2 << "\n" << jv;
  // The same directions by another derivation: the third derivatives of L
  // from a second-order Jet over (q, q̇, t) of first-order Jets.
  Vec<double, n> qdd_nested;
  Eigen::Matrix<double, n, 2> jv_nested;
  lagrangian::testing::nested_jet_jvp<2>(model, q, qd, t, v, qdd_nested, jv_nested);
  EXPECT_LE((qdd_nested - qdd).norm(), 1e-13 * (1 + qdd.norm())) << model.name();
  EXPECT_LE((jv_nested - jv).norm(), 1e-13 * (1 + jv.norm())) << model.name() << "\n" << jv_nested << "\n" << jv;
}

TEST(TangentFlow, HarmonicOscillatorIsMinusOmegaSquared) {
  const lm::HarmonicOscillator osc(2.0, 18.0);  // ω² = k/m = 9 s⁻²
  Vec<double, 1> qdd;
  Eigen::Matrix<double, 1, 2> jac;
  lagrangian::state_jacobian(osc, Vec<double, 1>(0.3), Vec<double, 1>(-1.2), 0.0, qdd, jac);
  EXPECT_DOUBLE_EQ(qdd[0], -9.0 * 0.3);
  EXPECT_DOUBLE_EQ(jac(0, 0), -9.0);
  EXPECT_EQ(jac(0, 1), 0.0);
}

TEST(TangentFlow, LinearDragGivesMinusBOverMInTheVelocityColumns) {
  const lm::Projectile<lm::Drag::linear> p(2.0, 9.81, 0.0, 0.5);  // b/m = 0.25 s⁻¹
  Vec<double, 2> qdd;
  Eigen::Matrix<double, 2, 4> jac;
  lagrangian::state_jacobian(p, Vec<double, 2>(1.0, 2.0), Vec<double, 2>(3.0, -4.0), 0.0, qdd, jac);
  Eigen::Matrix<double, 2, 4> expected = Eigen::Matrix<double, 2, 4>::Zero();
  expected(0, 2) = expected(1, 3) = -0.25;
  EXPECT_LE((jac - expected).norm(), 1e-15);
  EXPECT_NEAR(qdd[0], -0.25 * 3.0, 1e-15);
  EXPECT_NEAR(qdd[1], -9.81 + 0.25 * 4.0, 1e-14);
}

TEST(TangentFlow, AgreesWithDifferencesOfTheLibraryAccelerations) {
  expect_jacobian_agrees(lm::DoublePendulum(1.3, 0.7, 0.9, 1.1), Vec<double, 2>(0.7, -1.9), Vec<double, 2>(1.4, -0.6),
                         0.0);
  // Time-dependent T (∂²L/∂q̇∂t ≠ 0): the driven pendulum.
  expect_jacobian_agrees(lm::DrivenPendulum(), Vec<double, 1>(2.5), Vec<double, 1>(0.8), 0.37);
  // Gyroscopic terms (∂²L/∂q̇∂q not symmetric in its use): the spherical pendulum.
  expect_jacobian_agrees(lm::SphericalPendulum(), Vec<double, 2>(0.9, 0.4), Vec<double, 2>(-0.3, 2.1), 0.0);
  // Dissipation nonlinear in q̇: quadratic drag.
  expect_jacobian_agrees(lm::Projectile<lm::Drag::quadratic>(1.5, 9.81, 0.0, 0.2), Vec<double, 2>(0.1, 0.2),
                         Vec<double, 2>(7.0, -3.0), 0.0);
  expect_jacobian_agrees(lm::PendulumChain<4>(), Vec<double, 4>(0.3, -0.2, 1.1, 2.0),
                         Vec<double, 4>(0.5, -1.0, 0.25, 2.0), 0.0);
  // Six coordinates: the numbers' sparse storage and sin/cos memo (n > 4),
  // and J in three passes of four directions.
  Vec<double, 6> q6, qd6;
  q6 << 0.3, -0.2, 1.1, 2.0, -2.4, 0.05;
  qd6 << 0.5, -1.0, 0.25, 2.0, 0.0, -1.5;
  expect_jacobian_agrees(lm::PendulumChain<6>(), q6, qd6, 0.0);
  // Three coordinates: J in one pass of four directions and one of two used.
  expect_jacobian_agrees(lm::PendulumChain<3>(), Vec<double, 3>(0.3, -0.2, 1.1), Vec<double, 3>(0.5, -1.0, 0.25),
                         0.0);
}

/// A particle whose T depends on its position (m(x) = m0 (1 + x²)) or, with
/// `in_time`, on time (m(t) = m0 (1 + t²)), but that declares
/// constant_mass_matrix anyway.
template <bool in_time>
struct WronglyDeclaredConstantMass {
  static constexpr int coordinate_count = 1;
  static constexpr bool constant_mass_matrix = true;
  std::string name() const { return "wrongly_declared"; }
  template <class S>
  S kinetic(const Vec<S, 1>& q, const Vec<S, 1>& qd, const S& t) const {
    const S& x = in_time ? t : q[0];
    return 0.5 * (1.0 + x * x) * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    return 0.5 * q[0] * q[0];
  }
};

TEST(TangentFlow, RefusesAConstantMassDeclarationThatTDenies) {
  Vec<double, 1> qdd;
  Eigen::Matrix<double, 1, 2> jac;
  try {
    // At rest: T's derivatives in q vanish at q̇ = 0, so the check must look
    // at another velocity.
    lagrangian::state_jacobian(WronglyDeclaredConstantMass<false>(), Vec<double, 1>(0.5), Vec<double, 1>(0.0), 0.0,
                               qdd, jac);
    FAIL() << "a T that changes with q was taken as constant";
  } catch (const lagrangian::DynamicsError& e) {
    EXPECT_NE(std::string(e.what()).find("constant_mass_matrix"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("q[0]"), std::string::npos) << e.what();
  }
  try {
    lagrangian::state_jacobian(WronglyDeclaredConstantMass<true>(), Vec<double, 1>(0.5), Vec<double, 1>(0.0), 0.3,
                               qdd, jac);
    FAIL() << "a T that changes with t was taken as constant";
  } catch (const lagrangian::DynamicsError& e) {
    EXPECT_NE(std::string(e.what()).find("T's coefficient of qd[0] changes with t"), std::string::npos) << e.what();
  }
}

// A rod pendulum in Cartesian coordinates that also strikes a floor.
struct RodPendulumOverFloor : lm::CartesianPendulum {
  std::array<std::string_view, 1> unilateral_names() const { return {"floor"}; }
  std::array<double, 1> restitution() const { return {0.5}; }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(q[1] + 0.9);
  }
  std::array<std::string_view, 2> constraint_units() const { return {"m", "m"}; }
};

// Contacts act only at their impacts: between them the tangent flow of a
// model with a rod and a floor is the rod pendulum's, to rounding.
TEST(TangentFlow, ContactsUnderRowsLeaveTheFlowBetweenImpactsAsItIs) {
  const RodPendulumOverFloor model;
  const lm::CartesianPendulum rod;
  const Vec<double, 2> q(std::sin(0.5), -std::cos(0.5)), qd(0.7 * std::cos(0.5), 0.7 * std::sin(0.5));
  Vec<double, 2> qdd, qdd_rod;
  Eigen::Matrix<double, 2, 4> jac, jac_rod;
  lagrangian::state_jacobian(model, q, qd, 0.0, qdd, jac);
  lagrangian::state_jacobian(rod, q, qd, 0.0, qdd_rod, jac_rod);
  EXPECT_GT(jac.norm(), 1.0);
  EXPECT_LE((qdd - qdd_rod).norm(), 1e-14 * qdd_rod.norm());
  EXPECT_LE((jac - jac_rod).norm(), 1e-14 * jac_rod.norm()) << jac << "\n\n" << jac_rod;
}

lagrangian::LyapunovOptions options(double t_end, double rtol = 1e-11) {
  return lagrangian_test::lyapunov_options(t_end, rtol);
}

TEST(Lyapunov, HarmonicOscillatorHasZeroExponents) {
  const lm::HarmonicOscillator osc;  // ω = 1 rad/s
  lagrangian::State<1> s;
  s.q[0] = 0.1;
  const double periods = 1000, t_end = periods * 2 * M_PI;
  const lagrangian::LyapunovResult r = lagrangian::lyapunov_spectrum(osc, s, options(t_end));
  ASSERT_EQ(r.spectrum.size(), 2u);
  EXPECT_LE(std::abs(r.spectrum[0]), 1e-3);
  EXPECT_LE(std::abs(r.spectrum[1]), 1e-3);
  // The flow preserves area: the exponents cancel to the integration error.
  EXPECT_LE(std::abs(r.sum), 1e-8);
  EXPECT_DOUBLE_EQ(r.t_final, t_end);
  EXPECT_GE(r.renormalisations, 100);  // at least every T/100
  EXPECT_LE(r.interval_max, t_end / 100 * (1 + 1e-9) + 10);  // (a step may overrun T/100 by its length)
}

TEST(Lyapunov, LinearDragContractsPhaseSpaceAtMinusTwoBOverM) {
  // Liouville: d/dt log det Φ = tr J = −2b/m at every state, so the
  // finite-time exponents sum to −2b/m whatever the run's length.
  const lm::Projectile<lm::Drag::linear> p(2.0, 9.81, 0.0, 0.5);
  const lagrangian::State<2> s = p.launch(20.0, 0.8);
  for (double t_end : {1.0, 7.0}) {
    const lagrangian::LyapunovResult r = lagrangian::lyapunov_spectrum(p, s, options(t_end));
    ASSERT_EQ(r.spectrum.size(), 4u);
    EXPECT_NEAR(r.sum, -2 * 0.5 / 2.0, 1e-8) << "t_end = " << t_end;
  }
}

TEST(Lyapunov, ChaoticDoublePendulumHasAPositiveExponentAndASymplecticSpectrum) {
  const lm::DoublePendulum dp;
  lagrangian::State<2> chaotic, regular;
  chaotic.q << 2.0, 2.0;
  regular.q << 0.1, 0.1;
  lagrangian::LyapunovOptions o = options(25.0, 1e-10);
  const lagrangian::LyapunovResult a = lagrangian::lyapunov_spectrum(dp, chaotic, o);
  o.interval = 0.05;  // renormalised at least every 0.05 s instead of every 0.25 s
  const lagrangian::LyapunovResult b = lagrangian::lyapunov_spectrum(dp, chaotic, o);
  ASSERT_EQ(a.spectrum.size(), 4u);
  ASSERT_EQ(b.spectrum.size(), 4u);
  EXPECT_GT(b.renormalisations, a.renormalisations);
  // A positive exponent whatever the interval: the two runs' trajectories
  // part after some 20 s (rounding grown by e^(λt)), so their estimates
  // differ by the finite-time fluctuation, not by the method.
  EXPECT_GT(a.spectrum[0], 0.5) << "largest exponent " << a.spectrum[0] << " 1/s";
  EXPECT_GT(b.spectrum[0], 0.5) << "largest exponent " << b.spectrum[0] << " 1/s";
  // Canonical coordinates: the flow keeps phase-space volume, so the sum is
  // zero to the integration error at any T.
  EXPECT_LE(std::abs(a.sum), 1e-9);
  EXPECT_LE(std::abs(b.sum), 1e-9);
  // The exponents pair as ±λ as T grows: the defect of a finite-time
  // spectrum is a transient divided by T, so four times the time leaves at
  // most half of it.
  o.interval = 0;
  o.run.t_end = 100.0;
  const lagrangian::LyapunovResult longer = lagrangian::lyapunov_spectrum(dp, chaotic, o);
  const double defect = std::abs(a.spectrum[0] + a.spectrum[3]);
  const double defect_longer = std::abs(longer.spectrum[0] + longer.spectrum[3]);
  EXPECT_GT(defect, 0.0);
  EXPECT_LT(defect_longer, 0.5 * defect) << defect << " at 25 s, " << defect_longer << " at 100 s";
  EXPECT_LE(std::abs(longer.sum), 1e-9);
  // The largest exponent alone (one tangent vector) is as positive.
  o.exponents = 1;
  o.run.t_end = 25.0;
  const lagrangian::LyapunovResult one = lagrangian::lyapunov_spectrum(dp, chaotic, o);
  ASSERT_EQ(one.spectrum.size(), 1u);
  EXPECT_GT(one.spectrum[0], 0.5);
  // Small swings are regular (quasi-periodic): tangent vectors grow at most
  // polynomially, λ ≲ ln(T)/T = 0.046 1/s at T = 100 s.
  o.exponents = 0;
  o.run.t_end = 100.0;
  const lagrangian::LyapunovResult calm = lagrangian::lyapunov_spectrum(dp, regular, o);
  EXPECT_LT(calm.spectrum[0], 0.05) << calm.spectrum[0];
  EXPECT_LE(std::abs(calm.sum), 1e-9);
}

// One tangent vector (its rate along one direction, without J) against the
// first of four (J V with the whole Jacobian): Benettin's first vector is
// only ever rescaled, so the two give one exponent; on a regular motion the
// two runs' steps, which differ, do not part the trajectories.
TEST(Lyapunov, OneVectorAloneGivesTheFirstExponentOfTheWholeSpectrum) {
  const lm::DoublePendulum m;
  lagrangian::State<2> s;
  s.q << 0.5, -0.3;
  lagrangian::LyapunovOptions one = options(20.0), all = options(20.0);
  one.exponents = 1;
  all.exponents = 4;
  const lagrangian::LyapunovResult a = lagrangian::lyapunov_spectrum(m, s, one);
  const lagrangian::LyapunovResult b = lagrangian::lyapunov_spectrum(m, s, all);
  ASSERT_EQ(a.spectrum.size(), 1u);
  ASSERT_EQ(b.spectrum.size(), 4u);
  EXPECT_GT(a.spectrum[0], 0.01);  // a finite-time value, not a trivial 0
  EXPECT_NEAR(a.spectrum[0], b.spectrum[0], 1e-6 * a.spectrum[0]) << a.spectrum[0] << " " << b.spectrum[0];
  // ⟨Y⟩ is a quadrature over each run's own steps (measured apart by 1.8e-5).
  EXPECT_NEAR(a.megno_mean, b.megno_mean, 1e-4) << a.megno_mean << " " << b.megno_mean;
}

TEST(Megno, IsochronousCentreTendsToZero) {
  const lm::HarmonicOscillator osc(2.0, 18.0);  // ω = 3 rad/s: |δx| oscillates, never grows
  lagrangian::State<1> s;
  s.q[0] = 0.3;
  lagrangian::LyapunovOptions o = options(1000.0, 1e-10);
  o.exponents = 1;
  const lagrangian::LyapunovResult r = lagrangian::lyapunov_spectrum(osc, s, o);
  EXPECT_LE(std::abs(r.megno_mean), 0.01) << r.megno_mean;
}

TEST(Megno, RegularMotionWithShearTendsToTwo) {
  // |δx| grows linearly (the period depends on the amplitude): ⟨Y⟩ → 2.
  lagrangian::LyapunovOptions o = options(1000.0, 1e-10);
  o.exponents = 1;
  const lm::SimplePendulum pendulum;
  lagrangian::State<1> swing;
  swing.q[0] = 1.0;  // below the separatrix (π)
  const lagrangian::LyapunovResult p = lagrangian::lyapunov_spectrum(pendulum, swing, o);
  EXPECT_NEAR(p.megno_mean, 2.0, 0.05);
  // A Kepler ellipse, a = 1 m, e = 0.5, from periapsis (GM = k/m = 1 m³/s²).
  const lm::KeplerPolar kepler;
  lagrangian::State<2> orbit;
  const double a = 1, e = 0.5, r0 = a * (1 - e);
  orbit.q << r0, 0.0;
  orbit.qd << 0.0, std::sqrt((1 + e) / r0) / r0;
  o.run.t_end = 600.0;  // about 95 orbits
  const lagrangian::LyapunovResult k = lagrangian::lyapunov_spectrum(kepler, orbit, o);
  EXPECT_NEAR(k.megno_mean, 2.0, 0.05);
}

TEST(Megno, ChaoticMotionGrowsAsHalfTheExponentTimesTime) {
  const lm::DoublePendulum dp;
  lagrangian::State<2> s;
  s.q << 2.0, 2.0;
  lagrangian::LyapunovOptions o = options(25.0, 1e-10);
  o.exponents = 1;
  const lagrangian::LyapunovResult r = lagrangian::lyapunov_spectrum(dp, s, o);
  // ⟨Y⟩ ≈ λ_1 t / 2 for large t (Cincotta & Simó).
  EXPECT_GT(r.megno_mean, 5.0);
  EXPECT_NEAR(r.megno_mean, r.spectrum[0] * 25.0 / 2, 0.25 * r.spectrum[0] * 25.0 / 2);
}

TEST(Lyapunov, RefusesBadOptionsByName) {
  const lm::DoublePendulum dp;
  const lagrangian::State<2> s;
  lagrangian::LyapunovOptions o = options(1.0);
  o.exponents = 5;
  try {
    lagrangian::lyapunov_spectrum(dp, s, o);
    FAIL() << "exponents = 5 accepted for n = 2";
  } catch (const lagrangian::OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("exponents = 5"), std::string::npos) << e.what();
  }
  o.exponents = 0;
  o.run.method = lagrangian::Method::velocity_verlet;
  try {
    lagrangian::lyapunov_spectrum(dp, s, o);
    FAIL() << "velocity_verlet accepted";
  } catch (const lagrangian::OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("velocity_verlet"), std::string::npos) << e.what();
  }
  o.run.method = lagrangian::Method::dopri5;
  o.interval = -1;
  try {
    lagrangian::lyapunov_spectrum(dp, s, o);
    FAIL() << "a negative interval accepted";
  } catch (const lagrangian::OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("interval = -1"), std::string::npos) << e.what();
  }
}

}  // namespace
