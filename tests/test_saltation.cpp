// The tangent flow across impacts (analysis/saltation.hpp): the saltation
// matrix of a ball on a floor against its closed form, the flow's Jacobian
// over two bounces against the product of closed forms, and against
// central differences of simulate() for a ball on a tilted plane and for
// two spheres (a direct and an oblique impact); Liouville across impacts
// (the exponents' sum gains 2 ln e per bounce), the monodromy matrix of an
// elastic bounce, contacts coming to rest (the Zeno rule, a plastic impact)
// against closed forms, and the refusals (a parameter's column through a
// rest, two contacts at one instant). Parameter columns across impacts: test_impact_sensitivity.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/saltation.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/pendulums.hpp"

#include "contact_models.hpp"
#include "final_state.hpp"
#include "plane_slide.hpp"
#include "tangent_options.hpp"

namespace {

namespace lm = lagrangian::models;
using lagrangian::Vec;

lagrangian::SensitivityOptions tight(double t_end, std::vector<std::string> parameters = {}) {
  return lagrangian_test::sensitivity_options(t_end, std::move(parameters));
}

/// Free flight of a ball over Δ seconds: x ↦ (q + Δ q̇, q̇) (gravity
/// enters only q̈, which does not depend on the state).
Eigen::MatrixXd flight(double dt) {
  Eigen::MatrixXd f = Eigen::MatrixXd::Identity(6, 6);
  f.topRightCorner(3, 3) = dt * Eigen::MatrixXd::Identity(3, 3);
  return f;
}

/// The saltation matrix of a bounce on the floor z = 0 at approach speed
/// |v|: identity except, in (z, ż), [[−e, 0], [(1 + e) g / |v|, −e]].
Eigen::MatrixXd floor_bounce(double e, double g, double speed) {
  Eigen::MatrixXd s = Eigen::MatrixXd::Identity(6, 6);
  s(2, 2) = -e;
  s(5, 5) = -e;
  s(5, 2) = (1 + e) * g / speed;
  return s;
}

using lagrangian_test::worst_relative;

/// Central differences of simulate()'s x(T) along each component of the
/// initial state (steps h (1 + |x_i|)).
template <class M>
Eigen::MatrixXd differences(const M& model, const lagrangian::State<lagrangian::coordinate_count_v<M>>& s, double T,
                            double h) {
  constexpr int n = lagrangian::coordinate_count_v<M>;
  Eigen::MatrixXd out(2 * n, 2 * n);
  for (int i = 0; i < 2 * n; ++i) {
    auto up = s, down = s;
    double& u = i < n ? up.q[i] : up.qd[i - n];
    double& d = i < n ? down.q[i] : down.qd[i - n];
    const double step = h * (1 + std::abs(u));
    u += step;
    d -= step;
    out.col(i) = (lagrangian::testing::final_state(model, up, T) - lagrangian::testing::final_state(model, down, T)) /
                 (2 * step);
  }
  return out;
}

}  // namespace

// S for a ball meeting the floor at ż = −2 m/s (file comment of
// saltation.hpp): its z-rows [[−e, 0], [(1 + e) g / 2, −e]], the rest the
// identity (the tangential motion and the plane's other directions cross
// unchanged).
TEST(Saltation, BallOnFloorMatchesItsClosedForm) {
  const double e = 0.7, g = 9.81;
  const lm::BallAndPlane ball(1.5, 0.1, e, g);
  const Vec<double, 3> q(0.2, -0.1, 0.1);
  const Vec<double, 3> qd(0.3, 0.4, -2.0);
  const auto map = lagrangian::impact_map(ball, q, qd, 0.0, 0);
  EXPECT_NEAR(map.approach, -2.0, 1e-15);
  EXPECT_NEAR(map.qd_plus[2], 2.0 * e, 1e-15);
  const Eigen::MatrixXd s = lagrangian::saltation_matrix(ball, q, qd, 0.0, 0);
  EXPECT_LT(worst_relative(s, floor_bounce(e, g, 2.0)), 1e-14) << s;
}

// Dropped from rest 1 m above the floor (with a horizontal velocity), the
// ball lands at τ1 = √(2h/g) at speed g τ1, again at τ2 = τ1 (1 + 2e) at
// e g τ1, and at t = τ2 + e² τ1 (the next apex)
//   Φ = F(e² τ1) S(e g τ1) F(2e τ1) S(g τ1) F(τ1),
// F and S the closed forms above.
TEST(Saltation, BallFlowJacobianOverTwoBouncesMatchesTheProductOfClosedForms) {
  const double e = 0.8, g = 9.81, R = 0.1, h = 1.0;
  const lm::BallAndPlane ball(1.0, R, e, g);
  lagrangian::State<3> s;
  s.q << 0.0, 0.0, R + h;
  s.qd << 0.3, -0.2, 0.0;
  const double t1 = std::sqrt(2 * h / g), t2 = t1 * (1 + 2 * e), T = t2 + e * e * t1;
  const Eigen::MatrixXd expected =
      flight(e * e * t1) * floor_bounce(e, g, e * g * t1) * flight(2 * e * t1) * floor_bounce(e, g, g * t1) * flight(t1);
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(ball, s, tight(T));
  EXPECT_EQ(r.impacts, 2);
  EXPECT_LT(worst_relative(r.sensitivities.back(), expected), 1e-8) << r.sensitivities.back() << "\n\n" << expected;
  // The state itself: at the apex after two bounces, height e⁴ h.
  EXPECT_NEAR(r.states.back()[2], R + std::pow(e, 4) * h, 1e-10);
}

// A ball on a tilted plane (normal (0.4, 0, 1), normalised) through two
// bounces (at 0.52 s and 1.26 s): the flow's Jacobian against central
// differences of plain simulate() runs (which locate and resolve the impacts
// themselves).
TEST(Saltation, BallOnTiltedPlaneMatchesDifferencesOfSimulate) {
  const lm::BallAndPlane ball(1.0, 0.1, 0.75, 9.81, {0.4, 0.0, 1.0}, 0.0);
  lagrangian::State<3> s;
  s.q << 0.3, 0.1, 1.2;
  s.qd << -0.5, 0.2, 0.4;
  const double T = 1.4;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(ball, s, tight(T));
  EXPECT_EQ(r.impacts, 2);
  const Eigen::MatrixXd fd = differences(ball, s, T, 1e-6);
  EXPECT_LT(worst_relative(r.sensitivities.back(), fd), 1e-6) << r.sensitivities.back() << "\n\n" << fd;
  // The run crossed impacts: Φ is not the free flight's.
  EXPECT_GT(worst_relative(r.sensitivities.back(), flight(T)), 0.1);
}

// Two spheres on a line, 1 kg at 1 m/s meeting 2 kg at −0.5 m/s (e = 0.8),
// and two discs in the plane meeting off-centre (the line of centres, and
// with it G, turns with the positions: ∂q̇⁺/∂q ≠ 0): Φ at a time after the
// impact against central differences of simulate().
TEST(Saltation, TwoSpheresDirectAndObliqueImpactsMatchDifferencesOfSimulate) {
  {
    const lm::SpheresOnLine<2> line({1.0, 2.0}, {0.1, 0.1}, 0.8);
    lagrangian::State<2> s;
    s.q << 0.0, 0.7;
    s.qd << 1.0, -0.5;
    const lagrangian::SensitivityResult r = lagrangian::sensitivities(line, s, tight(1.0));
    EXPECT_EQ(r.impacts, 1);
    const Eigen::MatrixXd& got = r.sensitivities.back();
    const Eigen::MatrixXd fd = differences(line, s, 1.0, 1e-6);
    EXPECT_LT(worst_relative(got, fd), 1e-6) << got << "\n\n" << fd;
    Eigen::MatrixXd free = Eigen::MatrixXd::Identity(4, 4);  // free flight over 1 s
    free.topRightCorner(2, 2) = Eigen::MatrixXd::Identity(2, 2);
    EXPECT_GT(worst_relative(got, free), 0.1);
  }
  {
    const lm::TwoSpheres<2> discs(1.0, 3.0, 0.1, 0.15, 0.6);
    lagrangian::State<4> s;
    s.q << 0.0, 0.0, 1.0, 0.12;
    s.qd << 1.5, 0.2, -0.5, 0.0;
    const lagrangian::SensitivityResult r = lagrangian::sensitivities(discs, s, tight(1.0));
    EXPECT_EQ(r.impacts, 1);
    const Eigen::MatrixXd& got = r.sensitivities.back();
    const Eigen::MatrixXd fd = differences(discs, s, 1.0, 1e-6);
    EXPECT_LT(worst_relative(got, fd), 1e-6) << got << "\n\n" << fd;
  }
}

// Liouville across impacts: between bounces the ball's flow keeps phase
// volume, and each bounce multiplies it by det S = e². Over 1 s from 1 m
// (bounces at 0.45 s and 0.90 s for e = 0.5) the six exponents therefore
// sum to 4 ln e / (1 s).
TEST(Saltation, LyapunovSumOfABouncingBallIsTwoLogEPerBounce) {
  const double e = 0.5;
  const lm::BallAndPlane ball(1.0, 0.1, e);
  lagrangian::State<3> s;
  s.q << 0.0, 0.0, 1.1;
  s.qd << 0.3, 0.0, 0.0;
  lagrangian::LyapunovOptions o;
  o.run.t_end = 1.0;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  const lagrangian::LyapunovResult r = lagrangian::lyapunov_spectrum(ball, s, o);
  ASSERT_EQ(r.spectrum.size(), 6u);
  EXPECT_EQ(r.impacts, 2);
  EXPECT_NEAR(r.sum, 4 * std::log(e), 1e-8);
  // Without the bounces' volume loss the sum would be 0.
  EXPECT_LT(r.sum, -2.7);
}

// An elastic bounce (e = 1) from its apex 1 m above the floor is periodic
// with T = 2√(2h/g). Its monodromy matrix is F(T/2) S F(T/2): in (z, ż)
// [[1, 0], [2g/v, 1]] with v = √(2gh) (a higher apex is a longer period),
// along x and y the shear [[1, T], [0, 1]]; every multiplier is 1.
TEST(Saltation, ElasticBounceMonodromyMatchesItsClosedForm) {
  const double g = 9.81, h = 1.0, R = 0.1;
  const lm::BallAndPlane ball(1.0, R, 1.0, g);
  lagrangian::State<3> s;
  s.q << 0.0, 0.0, R + h;
  s.qd << 0.25, 0.0, 0.0;
  lagrangian::FloquetOptions o;
  o.period = 2 * std::sqrt(2 * h / g);
  o.run.rtol = 1e-13;
  o.run.atol = 1e-15;
  const lagrangian::FloquetResult r = lagrangian::floquet_multipliers(ball, s, o);
  Eigen::MatrixXd expected = flight(o.period);
  expected(2, 5) = 0.0;
  expected(5, 2) = 2 * g / std::sqrt(2 * g * h);
  EXPECT_EQ(r.impacts, 1);
  EXPECT_LT(worst_relative(r.monodromy, expected), 1e-8) << r.monodromy;
  // The multipliers are a defective double 1 (a Jordan block in each
  // plane): an error δ of Φ moves them by about √δ.
  for (const auto& mu : r.multipliers) EXPECT_NEAR(std::abs(mu), 1.0, 1e-5);
  EXPECT_LT(std::abs(r.q[2] - (R + h)), 1e-12);
}

// A ball with e = 0.5 dropped from 1 m comes to rest after 3 τ1 = 1.35 s
// (its bounces' times sum to that): the tangent run rests it where a plain
// run's Zeno rule does (the gap held as a row, detail::HoldingContacts) and
// goes on. On the floor it slides at 0.3 m/s: x(3 s) = 0.9 m, z = R. The
// rest removes the two directions of the gap (every neighbouring start
// comes to rest on the floor): two exponents −∞. The other four are those
// of free sliding along x and y, the shear [[1, t/m], [0, 1]] in (x, p_x),
// whose canonical start vectors keep length 1: exponents 0.
TEST(Saltation, BallComingToRestOnTheFloorSlidesOnWithTwoDirectionsRemoved) {
  const lm::BallAndPlane ball(1.0, 0.1, 0.5);
  lagrangian::State<3> s;
  s.q << 0.0, 0.0, 1.1;
  s.qd << 0.3, 0.0, 0.0;
  lagrangian::LyapunovOptions o;
  o.run.t_end = 3.0;
  const lagrangian::LyapunovResult r = lagrangian::lyapunov_spectrum(ball, s, o);
  EXPECT_EQ(r.rests, 1);
  EXPECT_EQ(r.releases, 0);
  EXPECT_GT(r.impacts, 10);
  EXPECT_EQ(r.t_final, 3.0);
  EXPECT_NEAR(r.q_final[0], 0.9, 1e-9);
  EXPECT_NEAR(r.q_final[2], 0.1, 1e-9);
  EXPECT_NEAR(r.qd_final[2], 0.0, 1e-9);
  ASSERT_EQ(r.spectrum.size(), 6u);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(r.spectrum[static_cast<std::size_t>(i)], 0.0, 1e-9) << i;
  EXPECT_EQ(r.spectrum[4], -HUGE_VAL);
  EXPECT_EQ(r.spectrum[5], -HUGE_VAL);
}

// The C++ twin of TextSaltation.BallComingToRestOnAPlaneHasTheClosedFormFlow:
// the ball on the plane with normal n̂ ∝ (0.4, 0, 1), e = 0.5, bounces to
// rest (t∞ ≈ 1.5 s) and slides down it. Along the frictionless plane it
// falls freely whatever the bounces, and every start comes to rest on it:
// at 2.2 s Φ = [[P, t P], [0, P]], P = I − n̂n̂ᵀ.
TEST(Saltation, BallComingToRestOnATiltedPlaneHasTheClosedFormFlow) {
  const double t = 2.2;
  const lm::BallAndPlane ball(1.0, 0.1, 0.5, 9.81, {0.4, 0.0, 1.0}, 0.0);
  lagrangian::State<3> s;
  s.q << 0.3, 0.1, 1.2;
  s.qd << -0.5, 0.2, 0.4;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(ball, s, tight(t));
  const Eigen::Vector3d n = Eigen::Vector3d(0.4, 0.0, 1.0).normalized();
  const Eigen::MatrixXd expected = lagrangian_test::flow_sliding_on_a_plane(n, t);
  EXPECT_LE((r.sensitivities.back() - expected).cwiseAbs().maxCoeff(), 1e-9) << r.sensitivities.back();
  EXPECT_GT(r.impacts, 10);
  const Eigen::VectorXd& x = r.states.back();
  EXPECT_NEAR(n.dot(x.head(3)), 0.1, 1e-9);
  EXPECT_NEAR(n.dot(x.tail(3)), 0.0, 1e-9);
}

// The same ball's parameter columns through its bounces and its rest (the
// seeded twin holds the contact too): at 2.2 s the state is the closed form
// of tests/plane_slide.hpp, r = P (r0 + v0 t − ½ g t² ẑ) + (offset + R) n̂,
// v = P (v0 − g t ẑ), whatever e and m; its derivatives in g, R, the
// offset and nx (the normal renormalised) by central differences of that
// closed form, and 0 in m and e (the bounces' number and times move with e,
// the state at rest does not).
TEST(Saltation, ParameterColumnsCrossARestOnATiltedPlaneAsTheClosedForm) {
  const double t = 2.2;
  const Eigen::Vector3d r0(0.3, 0.1, 1.2), v0(-0.5, 0.2, 0.4);
  lagrangian::State<3> s;
  s.q = r0;
  s.qd = v0;
  const std::vector<std::string> names = {"m", "R", "e", "g", "nx", "offset"};
  const lagrangian::SensitivityResult r =
      lagrangian::sensitivities(lm::BallAndPlane(1.0, 0.1, 0.5, 9.81, {0.4, 0.0, 1.0}, 0.0), s, tight(t, names));
  EXPECT_GT(r.impacts, 10);
  ASSERT_EQ(r.sensitivities.back().cols(), 6 + 6);
  // (m, R, e, g, nx, offset) ↦ the closed-form state at t.
  const auto closed_form = [&](std::array<double, 6> p) {
    const Eigen::Vector3d normal(p[4], 0.0, 1.0);
    return lagrangian_test::state_sliding_on_a_plane(r0, v0, normal, (p[5] + p[1]) * normal.norm(), p[3], t);
  };
  const std::array<double, 6> at = {1.0, 0.1, 0.5, 9.81, 0.4, 0.0};
  EXPECT_LE((r.states.back() - closed_form(at)).cwiseAbs().maxCoeff(), 1e-9) << r.states.back();
  const Eigen::MatrixXd columns = lagrangian_test::central_differences(closed_form, at);
  for (int j = 0; j < 6; ++j) {
    const Eigen::VectorXd expected = columns.col(j), got = r.sensitivities.back().col(6 + j);
    EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), 1e-8) << names[static_cast<std::size_t>(j)] << "\n"
                                                              << got.transpose() << "\n"
                                                              << expected.transpose();
  }
  // Not every column is 0: g moves the slide, R and the offset the plane.
  EXPECT_GT(r.sensitivities.back().col(6 + 3).cwiseAbs().maxCoeff(), 0.5);
  EXPECT_GT(r.sensitivities.back().col(6 + 1).cwiseAbs().maxCoeff(), 0.5);
}

// A plastic impact (e = 0): spheres of 1 and 2 kg (radii 0.1 m) at x = 0
// and 0.7 m meet at 1/3 s and stick, as a plain run holds them; from then
// on both move with the centre of mass, V = (m1 v1 + m2 v2) / (m1 + m2),
// x1(T) = (m1 x1 + m2 (x2 − d)) / (m1 + m2) + V T, x2(T) = x1(T) + d
// (momentum conservation, d = 0.2 m), whatever the initial state. Φ(1 s) is
// therefore, with μ_i = m_i / (m1 + m2), the rank-2 matrix whose position
// rows are (μ1, μ2, μ1 T, μ2 T) and velocity rows (0, 0, μ1, μ2).
TEST(Saltation, SpheresStickingInAPlasticImpactMoveWithTheirCentreOfMass) {
  const lm::SpheresOnLine<2> line({1.0, 2.0}, {0.1, 0.1}, 0.0);
  lagrangian::State<2> pair;
  pair.q << 0.0, 0.7;
  pair.qd << 1.0, -0.5;
  const double T = 1.0, mu1 = 1.0 / 3.0, mu2 = 2.0 / 3.0;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(line, pair, tight(T));
  EXPECT_EQ(r.impacts, 1);
  Eigen::MatrixXd expected(4, 4);
  expected << mu1, mu2, mu1 * T, mu2 * T,  //
      mu1, mu2, mu1 * T, mu2 * T,          //
      0.0, 0.0, mu1, mu2,                  //
      0.0, 0.0, mu1, mu2;
  EXPECT_LE((r.sensitivities.back() - expected).cwiseAbs().maxCoeff(), 1e-9) << r.sensitivities.back();
  // The state: V = 0 here, so both rest where they met.
  const Eigen::VectorXd& x = r.states.back();
  EXPECT_NEAR(x[0], 1.0 / 3.0, 1e-9);
  EXPECT_NEAR(x[1] - x[0], 0.2, 1e-9);
  EXPECT_NEAR(x[2], 0.0, 1e-9);
  EXPECT_NEAR(x[3], 0.0, 1e-9);
}

// A model whose number of contacts is chosen at run time (the polygon
// billiard of contact_models.hpp: a point of 0.2 kg, elastic walls at 1 m
// from the origin): with no walls it is a free particle, with four a square
// billiard. In both the flow is free flight, Φ = [[1, t/m], [0, 1]] in
// (q, p) along each axis, and a reflection on a flat wall, e = 1, is an
// orthogonal map of (δq, δp) that keeps phase volume (|det S| = 1): every
// exponent is 0 and so is the sum.
TEST(Saltation, ABilliardWithARunTimeNumberOfWallsHasZeroExponents) {
  lagrangian::State<2> s;
  s.q << 0.2, 0.1;
  s.qd << 1.0, 0.3;
  for (const int walls : {0, 4}) {
    const lagrangian::testing::PolygonBilliard billiard{walls};
    const lagrangian::LyapunovResult r = lagrangian::lyapunov_spectrum(billiard, s, lagrangian_test::lyapunov_options(5.0));
    EXPECT_EQ(r.impacts > 0, walls > 0) << walls;
    ASSERT_EQ(r.spectrum.size(), 4u);
    for (const double l : r.spectrum) EXPECT_NEAR(l, 0.0, 1e-9) << walls;
    EXPECT_NEAR(r.sum, 0.0, 1e-9) << walls;
  }
}

// Three equal spheres on a line, the outer two meeting the middle one at
// one instant: the saltation matrix of two simultaneous impacts is not
// defined by one contact's law, and the run says so.
// The built-in SpheresInBox with one disc (1 kg, r = 0.1 m, box 2 m × 1 m,
// g = 9.81 m/s², e_wall = 0.8) dropped from y = 0.6 m moving at 0.3 m/s:
// it bounces to rest on the floor by the Zeno rule at
// √(2h/g) (1 + e)/(1 − e) = 2.87 s (h = 0.5 m) and slides into the right
// wall (reached at x = W − r = 1.9 m) at 4.67 s, whose impulse, along x,
// leaves the floor's rate alone: the impact is crossed with the disc held
// on the floor (the particle scenes' floor-and-wall test in C++). Along x,
// x(t) = (W − r)(1 + e) − e x0 − e ẋ0 t after it, ẋ = −e ẋ0; y = r and
// ẏ = 0 whatever the start: at 5.5 s, in (x, y, ẋ, ẏ),
//   ∂x/∂x0 = −e, ∂x/∂ẋ0 = −e t, ∂ẋ/∂ẋ0 = −e, every other entry 0,
// and the columns of the parameters: ∂x/∂e_wall = W − r − x0 − ẋ0 t,
// ∂ẋ/∂e_wall = −ẋ0; ∂x/∂W = 1 + e; ∂x/∂r1 = −(1 + e), ∂y/∂r1 = 1; g, H
// and m1: 0.
TEST(Saltation, DiscAtRestOnTheFloorBouncesOffAWallAsTheClosedForm) {
  const lm::SpheresInBox<1> box({1.0}, {0.1}, 2.0, 1.0, 0.8, 1.0, 9.81);
  lagrangian::State<2> s;
  s.q << 0.5, 0.6;
  s.qd << 0.3, 0.0;
  const double t = 5.5, e = 0.8, reach = 1.9, x0 = 0.5, v0 = 0.3;
  const lagrangian::SensitivityResult r =
      lagrangian::sensitivities(box, s, tight(t, {"e_wall", "W", "r1", "g", "H", "m1"}));
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(4, 10);
  expected(0, 0) = -e;
  expected(0, 2) = -e * t;
  expected(2, 2) = -e;
  expected(0, 4) = reach - x0 - v0 * t;
  expected(2, 4) = -v0;
  expected(0, 5) = 1 + e;
  expected(0, 6) = -(1 + e);
  expected(1, 6) = 1.0;
  const Eigen::MatrixXd& got = r.sensitivities.back();
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-9) << got;
  EXPECT_NEAR(r.states.back()[0], reach * (1 + e) - e * x0 - e * v0 * t, 1e-9);
  EXPECT_NEAR(r.states.back()[1], 0.1, 1e-9);
  const lagrangian::LyapunovResult l = lagrangian::lyapunov_spectrum(box, s, lagrangian_test::lyapunov_options(t));
  EXPECT_EQ(l.rests, 1);
  EXPECT_EQ(l.releases, 0);
  EXPECT_GT(l.impacts, 20);
}

// The disc of the test above in C++ against a wall leaning back
// (DiscAndLeaningWall, contact_models.hpp; the closed form is derived at
// TextSaltation.DiscLiftedOffTheFloorByAWallAsTheClosedForm): the wall's
// law alone lifts the disc off the floor at 4.67 s, which the tangent run
// releases as a plain run does, and the disc comes to rest again. At 5.5 s, in (x, y, ẋ, ẏ), ∂x/∂x0 = c,
// ∂x/∂ẋ0 = c t, ∂ẋ/∂ẋ0 = c (c = 1 − 1.8/1.09), every other entry 0. Leaning
// the other way the wall's impulse presses the disc into the floor: the run
// stops at the impact, naming both contacts.
TEST(Saltation, DiscLiftedOffTheFloorByALeaningWallAsTheClosedForm) {
  using lagrangian::testing::DiscAndLeaningWall;
  lagrangian::State<2> s;
  s.q << 0.5, 0.6;
  s.qd << 0.3, 0.0;
  const double t = 5.5, c = 1 - 1.8 / 1.09;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(DiscAndLeaningWall{0.3}, s, tight(t));
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(4, 4);
  expected(0, 0) = c;
  expected(0, 2) = c * t;
  expected(2, 2) = c;
  EXPECT_LT((r.sensitivities.back() - expected).cwiseAbs().maxCoeff(), 1e-9) << r.sensitivities.back();
  const lagrangian::LyapunovResult l =
      lagrangian::lyapunov_spectrum(DiscAndLeaningWall{0.3}, s, lagrangian_test::lyapunov_options(t));
  EXPECT_EQ(l.rests, 2);
  EXPECT_EQ(l.releases, 1);
  try {
    (void)lagrangian::lyapunov_spectrum(DiscAndLeaningWall{-0.3}, s, lagrangian_test::lyapunov_options(t));
    ADD_FAILURE() << "an impact that presses a resting contact was crossed";
  } catch (const lagrangian::SimulationError& error) {
    EXPECT_NE(std::string(error.what()).find("the impulse of contact 'wall' sets resting contact 'floor' moving"),
              std::string::npos)
        << error.what();
    EXPECT_NEAR(error.time(), (1.9 - 0.5) / 0.3, 1e-6);
  }
}

TEST(Saltation, SimultaneousImpactsStopTheRun) {
  const lm::SpheresOnLine<3> line({1.0, 1.0, 1.0}, {0.1, 0.1, 0.1}, 1.0);
  lagrangian::State<3> s;
  s.q << -1.0, 0.0, 1.0;
  s.qd << 1.0, 0.0, -1.0;
  try {
    lagrangian::sensitivities(line, s, tight(2.0));
    FAIL() << "two impacts at one instant were crossed";
  } catch (const lagrangian::SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("close at one instant"), std::string::npos) << e.what();
  }
  // The second and third spheres touching when the first one arrives: the
  // impacts follow one another at one instant.
  s.q << -1.0, 0.0, 0.2;
  s.qd << 1.0, 0.0, 0.0;
  try {
    lagrangian::sensitivities(line, s, tight(2.0));
    FAIL() << "an impact against a row of touching spheres was crossed";
  } catch (const lagrangian::SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("touch at one instant"), std::string::npos) << e.what();
  }
}

namespace {
/// A free particle with a "contact" whose gap runs out with time alone,
/// φ = 1 s − t: it closes at t = 1 s without any direction of q that could
/// open it (G = 0).
struct TimedGap {
  static constexpr int coordinate_count = 1;
  std::string name() const { return "timed_gap"; }
  std::array<double, 1> restitution() const { return {0.5}; }
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>&, const S&) const {
    return S(0.0);
  }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 1>&, const S& t) const {
    return Vec<S, 1>(1.0 - t);
  }
};
}  // namespace

// An impact law needs G M⁻¹ Gᵀ > 0: a gap that no motion of the
// coordinates can open has no impulse, and its impact map says so instead
// of dividing by zero.
TEST(Saltation, AGapThatTheCoordinatesCannotOpenHasNoImpactMap) {
  const TimedGap timed;
  EXPECT_THROW((void)lagrangian::impact_map(timed, Vec<double, 1>(0.0), Vec<double, 1>(0.0), 1.0, 0),
               lagrangian::DynamicsError);
  // In a run the driver reports it as the reason the run stopped.
  lagrangian::State<1> s;
  try {
    lagrangian::sensitivities(timed, s, tight(2.0));
    FAIL() << "an impact without an impulse was crossed";
  } catch (const lagrangian::SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("has G M^-1 G^T = 0"), std::string::npos) << e.what();
    EXPECT_LT(e.time(), 1.0);  // the last step accepted before the gap closes
  }
}



using lagrangian::testing::BouncingBall;
using lagrangian::testing::DoublePendulumAgainstWall;


// A gap that moves with time and a mass matrix and gap gradient that move
// with the coordinates: Φ against central differences of simulate().
TEST(Saltation, MovingTableAndPendulumAgainstAWallMatchDifferencesOfSimulate) {
  {
    const BouncingBall<> ball;
    lagrangian::State<1> s;
    s.q[0] = 0.3;
    const lagrangian::SensitivityResult r = lagrangian::sensitivities(ball, s, tight(1.0));
    EXPECT_EQ(r.impacts, 3);
    const Eigen::MatrixXd fd = differences(ball, s, 1.0, 1e-6);
    EXPECT_LT(worst_relative(r.sensitivities.back(), fd), 1e-6) << r.sensitivities.back() << "\n\n" << fd;
  }
  {
    const DoublePendulumAgainstWall pendulum;
    lagrangian::State<2> s;
    s.q << 0.2, 0.2;
    s.qd << 1.0, 1.5;
    const lagrangian::SensitivityResult r = lagrangian::sensitivities(pendulum, s, tight(1.5));
    EXPECT_EQ(r.impacts, 1);
    const Eigen::MatrixXd fd = differences(pendulum, s, 1.5, 1e-6);
    EXPECT_LT(worst_relative(r.sensitivities.back(), fd), 1e-6) << r.sensitivities.back() << "\n\n" << fd;
  }
}
