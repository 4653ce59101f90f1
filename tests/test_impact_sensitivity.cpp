// Parameter columns across impacts (analysis/sensitivity.hpp): a ball
// dropped onto a floor, and the built-in ball onto a raised floor, against
// the closed form of the motion after the bounce; a ball on a moving table
// and a ball on a tilted plane against central differences of simulate()
// over several bounces; two spheres head-on against their closed form and
// obliquely against central differences, on a line (SpheresOnLine) against
// the same closed form, Newton's cradle with its gaps open against its
// closed form, three discs in a box against central differences; the
// parameters held in arrays named by their bodies; the refusal of a model whose contacts do not follow its
// parameters.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/models/impacts.hpp"

#include "contact_models.hpp"
#include "final_state.hpp"
#include "named_parameters.hpp"
#include "tangent_options.hpp"

namespace {

namespace lm = lagrangian::models;
using lagrangian::testing::BouncingBall;

using lagrangian_test::worst_relative;

/// The parameters' columns alone.
lagrangian::SensitivityOptions tight(double t_end, std::vector<std::string> parameters) {
  lagrangian::SensitivityOptions o = lagrangian_test::sensitivity_options(t_end, std::move(parameters));
  o.initial_state = false;
  return o;
}

/// Central differences of simulate()'s x(T) along each of `values` (steps
/// h (1 + |p|)), one column each, the moved models made by build(values).
template <class Build, int n>
Eigen::MatrixXd central_differences(const Build& build, const std::vector<double>& values,
                                    const lagrangian::State<n>& s, double T, double h) {
  Eigen::MatrixXd out(2 * n, static_cast<int>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::vector<double> up = values, down = values;
    const double step = h * (1 + std::abs(values[i]));
    up[i] += step;
    down[i] -= step;
    out.col(static_cast<int>(i)) =
        (lagrangian::testing::final_state(build(up), s, T) - lagrangian::testing::final_state(build(down), s, T)) /
        (2 * step);
  }
  return out;
}

/// The same along a model's parameters named `names`, moved through its
/// parameter_members().
template <class M>
Eigen::MatrixXd parameter_differences(const M& model, const lagrangian::State<lagrangian::coordinate_count_v<M>>& s,
                                      double T, double h, const std::vector<std::string>& names) {
  using lagrangian::detail::parameter_of;
  const std::vector<std::string> all = lagrangian::parameter_names_of<M>();
  constexpr auto members = M::parameter_members();
  std::vector<std::size_t> index;
  std::vector<double> values;
  for (const std::string& name : names) {
    const std::size_t i = static_cast<std::size_t>(std::find(all.begin(), all.end(), name) - all.begin());
    if (i == all.size()) {
      ADD_FAILURE() << "no parameter " << name;
      return Eigen::MatrixXd::Zero(2 * lagrangian::coordinate_count_v<M>, static_cast<int>(names.size()));
    }
    index.push_back(i);
    values.push_back(parameter_of(model, members[i]));
  }
  const auto build = [&](const std::vector<double>& v) {
    M moved = model;
    for (std::size_t c = 0; c < index.size(); ++c) parameter_of(moved, members[index[c]]) = v[c];
    return moved;
  };
  return central_differences(build, values, s, T, h);
}

// Dropped from rest at height z0 onto the floor z = 0: the bounce comes at
// t1 = √(2 z0/g) with speed v1 = g t1, and after it
//   z = e v1 (t − t1) − ½ g (t − t1)²,  ż = e v1 − g (t − t1),
// so ∂z/∂e = v1 (t − t1), ∂ż/∂e = v1, and with dt1/dg = −t1/(2g),
// dv1/dg = v1/(2g):
//   ∂z/∂g = e v1 t/(2g) − ½ (t − t1)² − ½ t1 (t − t1),
//   ∂ż/∂g = e v1/(2g) − (t − t1) − ½ t1.
// Without the terms the impact adds (R_p and the shift of the impact time)
// the columns would be those of the flight alone, and fail.
TEST(ImpactSensitivity, BallDroppedOnAFloorMatchesItsClosedForm) {
  BouncingBall<> ball;
  ball.amplitude = 0.0;  // a fixed floor
  ball.e = 0.8;
  const double z0 = 1.0, g = ball.g, e = ball.e, T = 0.9;
  lagrangian::State<1> s;
  s.q[0] = z0;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(ball, s, tight(T, {"e", "g"}));
  ASSERT_EQ(r.impacts, 1);
  const double t1 = std::sqrt(2 * z0 / g), v1 = g * t1, u = T - t1;
  Eigen::MatrixXd expected(2, 2);
  expected << v1 * u, e * v1 * T / (2 * g) - 0.5 * u * u - 0.5 * t1 * u,  //
      v1, e * v1 / (2 * g) - u - 0.5 * t1;
  const Eigen::MatrixXd& got = r.sensitivities.back();
  ASSERT_EQ(got.cols(), 2);
  std::printf("dropped ball, columns of e and g: %.2e from the closed form\n", (got - expected).cwiseAbs().maxCoeff());
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-9) << got << "\n\n" << expected;
  // The state itself: z and ż of the closed form.
  EXPECT_NEAR(r.states.back()[0], e * v1 * u - 0.5 * g * u * u, 1e-11);
}

// The built-in ball on a floor at height d (the plane z = d), radius R,
// dropped from rest at z0: it falls H = z0 − d − R, bounces at
// t1 = √(2H/g) with speed v1 = g t1, and then
//   z = d + R + e v1 (t − t1) − ½ g (t − t1)²,  ż = e v1 − g (t − t1).
// d and R move the gap, so the impact time (dt1/dd = −t1/(2H),
// dv1/dd = −v1/(2H)): with u = t − t1,
//   ∂z/∂d = ∂z/∂R = 1 − e v1 u/(2H) + e v1 t1/(2H) − g t1 u/(2H),
//   ∂ż/∂d = ∂ż/∂R = −(e v1 + g t1)/(2H),
// and ∂z/∂e = v1 u, ∂ż/∂e = v1; x and y stay 0. The term of the impact
// time's shift, a ∂φ/∂p / v, is what the d and R columns need.
TEST(ImpactSensitivity, BallOnARaisedFloorMatchesItsClosedForm) {
  const double m = 0.4, R = 0.1, e = 0.6, g = 9.81, d = 0.25, z0 = 1.3, T = 0.9;  // bounces at 0.44 s, 0.97 s
  const lm::BallAndPlane ball(m, R, e, g, {0.0, 0.0, 1.0}, d);
  lagrangian::State<3> s;
  s.q << 0.0, 0.0, z0;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(ball, s, tight(T, {"offset", "R", "e"}));
  ASSERT_EQ(r.impacts, 1);
  const double H = z0 - d - R, t1 = std::sqrt(2 * H / g), v1 = g * t1, u = T - t1;
  const double dz = 1 - e * v1 * u / (2 * H) + e * v1 * t1 / (2 * H) - g * t1 * u / (2 * H);
  const double dzd = -(e * v1 + g * t1) / (2 * H);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(6, 3);
  expected(2, 0) = expected(2, 1) = dz;
  expected(5, 0) = expected(5, 1) = dzd;
  expected(2, 2) = v1 * u;
  expected(5, 2) = v1;
  const Eigen::MatrixXd& got = r.sensitivities.back();
  ASSERT_EQ(got.cols(), 3);
  std::printf("raised floor, columns of d, R and e: %.2e from the closed form\n",
              (got - expected).cwiseAbs().maxCoeff());
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-9) << got << "\n\n" << expected;
  EXPECT_NEAR(r.states.back()[2], d + R + e * v1 * u - 0.5 * g * u * u, 1e-11);
}

// The table moves, z_table = A sin ωt: the gap depends on A and ω, the
// approach speed on them through ∂φ/∂t. Three bounces in 1 s.
TEST(ImpactSensitivity, BallOnAMovingTableMatchesDifferencesOfSimulate) {
  const BouncingBall<> ball;
  lagrangian::State<1> s;
  s.q[0] = 0.3;
  const std::vector<std::string> names = {"g", "e", "amplitude", "omega"};
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(ball, s, tight(1.0, names));
  EXPECT_EQ(r.impacts, 3);
  const Eigen::MatrixXd fd = parameter_differences(ball, s, 1.0, 1e-6, names);
  std::printf("moving table: %.2e relative from central differences\n", worst_relative(r.sensitivities.back(), fd));
  EXPECT_LT(worst_relative(r.sensitivities.back(), fd), 1e-6) << r.sensitivities.back() << "\n\n" << fd;
}

// A ball on a tilted plane in 3-D (the built-in BallAndPlane): every
// parameter, the normal's components and the offset included, over two
// bounces (the normal's columns through its normalisation); the mass
// cancels from the motion (its column is 0).
TEST(ImpactSensitivity, BallOnATiltedPlaneMatchesDifferencesOfSimulate) {
  const lm::BallAndPlane ball(1.3, 0.1, 0.7, 9.81, {0.3, 0.1, 1.0}, 0.05);
  lagrangian::State<3> s;
  s.q << 0.2, -0.1, 0.9;
  s.qd << 0.4, 0.2, 0.0;
  const double T = 1.2;
  const std::vector<std::string> names = {"R", "e", "g", "nx", "ny", "nz", "offset"};
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(ball, s, tight(T, names));
  EXPECT_EQ(r.impacts, 2);
  // Steps 1e-5 (1 + |p|): at 1e-6 the runs' own errors (rtol 1e-13)
  // divided by the step reach 4e-7 in the normal's columns.
  const Eigen::MatrixXd fd = parameter_differences(ball, s, T, 1e-5, names);
  std::printf("tilted plane: %.2e relative from central differences\n", worst_relative(r.sensitivities.back(), fd));
  EXPECT_LT(worst_relative(r.sensitivities.back(), fd), 1e-6) << r.sensitivities.back() << "\n\n" << fd;
  const lagrangian::SensitivityResult mass = lagrangian::sensitivities(ball, s, tight(T, {"m"}));
  EXPECT_LT(mass.sensitivities.back().cwiseAbs().maxCoeff(), 1e-12) << mass.sensitivities.back();
}

// Two spheres head-on along x: sphere 1 from x = 0 at u1, sphere 2 from
// x = X at u2 < u1. They touch at tc = (X − r1 − r2)/(u1 − u2) and leave
// with (Newton's law)
//   v1 = u1 − m2 (1 + e)(u1 − u2)/(m1 + m2),  v2 = u2 + m1 (1 + e)(u1 − u2)/(m1 + m2),
// then x_i(t) = x_i(tc) + v_i (t − tc). So ∂x_i/∂e = ∂v_i/∂e (t − tc) with
// ∂v1/∂e = −m2 (u1 − u2)/M, ∂v2/∂e = m1 (u1 − u2)/M (M = m1 + m2); a
// radius moves the impact, ∂tc/∂r = −1/(u1 − u2), so ∂x_i/∂r = (u_i − v_i)
// ∂tc/∂r; and ∂v1/∂m1 = ∂v2/∂m1 = m2 (1 + e)(u1 − u2)/M²,
// ∂v1/∂m2 = ∂v2/∂m2 = −m1 (1 + e)(u1 − u2)/M².
struct HeadOn {
  double m1 = 1.2, m2 = 0.7, r1 = 0.15, r2 = 0.1, e = 0.6, X = 1.0, u1 = 1.5, u2 = -0.4, T = 1.3;
  /// Rows (x1, x2, ẋ1, ẋ2) at T; columns m1, m2, r1, r2, e.
  Eigen::MatrixXd columns() const {
    const double M = m1 + m2, w = u1 - u2, tc = (X - r1 - r2) / w;
    const double v1 = u1 - m2 * (1 + e) * w / M, v2 = u2 + m1 * (1 + e) * w / M;
    EXPECT_LT(tc, T);
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(4, 5);
    const auto column = [&](int c, double dv1, double dv2, double dtc) {
      out(0, c) = dv1 * (T - tc) + (u1 - v1) * dtc;
      out(1, c) = dv2 * (T - tc) + (u2 - v2) * dtc;
      out(2, c) = dv1;
      out(3, c) = dv2;
    };
    column(0, m2 * (1 + e) * w / (M * M), m2 * (1 + e) * w / (M * M), 0.0);
    column(1, -m1 * (1 + e) * w / (M * M), -m1 * (1 + e) * w / (M * M), 0.0);
    column(2, 0.0, 0.0, -1 / w);
    column(3, 0.0, 0.0, -1 / w);
    column(4, -m2 * w / M, m1 * w / M, 0.0);
    return out;
  }
};

// The built-in TwoSpheres<2> in the plane: nothing moves along y.
TEST(ImpactSensitivity, TwoSpheresHeadOnMatchTheirClosedForm) {
  const HeadOn h;
  const lm::TwoSpheres<2> spheres(h.m1, h.m2, h.r1, h.r2, h.e);
  lagrangian::State<4> s;
  s.q << 0.0, 0.0, h.X, 0.0;
  s.qd << h.u1, 0.0, h.u2, 0.0;
  const lagrangian::SensitivityResult r =
      lagrangian::sensitivities(spheres, s, tight(h.T, {"m1", "m2", "r1", "r2", "e"}));
  EXPECT_EQ(r.impacts, 1);
  // Rows (x1, y1, x2, y2, ẋ1, ẏ1, ẋ2, ẏ2).
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(8, 5);
  const Eigen::MatrixXd line = h.columns();
  for (int k = 0; k < 4; ++k) expected.row(2 * k) = line.row(k);
  const double error = (r.sensitivities.back() - expected).cwiseAbs().maxCoeff();
  std::printf("two spheres head-on: columns of m1, m2, r1, r2, e %.2e from the closed form\n", error);
  EXPECT_LE(error, 1e-9) << r.sensitivities.back() << "\n\n" << expected;
}

// The same impact on the line (SpheresOnLine<2>, the scene direct_impact):
// its parameters are arrays of masses and radii, offered as m1, m2, r1, r2.
TEST(ImpactSensitivity, TwoSpheresOnALineMatchTheClosedForm) {
  const HeadOn h;
  const lm::SpheresOnLine<2> spheres({h.m1, h.m2}, {h.r1, h.r2}, h.e);
  EXPECT_EQ(lagrangian::parameter_names_of<lm::SpheresOnLine<2>>(),
            (std::vector<std::string>{"m1", "m2", "r1", "r2", "e"}));
  lagrangian::State<2> s;
  s.q << 0.0, h.X;
  s.qd << h.u1, h.u2;
  const lagrangian::SensitivityResult r =
      lagrangian::sensitivities(spheres, s, tight(h.T, {"m1", "m2", "r1", "r2", "e"}));
  EXPECT_EQ(r.impacts, 1);
  const Eigen::MatrixXd expected = h.columns();
  const double error = (r.sensitivities.back() - expected).cwiseAbs().maxCoeff();
  std::printf("two spheres on a line: columns of m1, m2, r1, r2, e %.2e from the closed form\n", error);
  EXPECT_LE(error, 1e-9) << r.sensitivities.back() << "\n\n" << expected;
}

// Newton's cradle with its gaps open (SpheresOnLine<5>, equal masses m and
// radii r, e = 1): sphere 1 arrives at v, and each impact hands the whole
// velocity on, so sphere i ≤ 4 stops after crossing its gap
// g_i = x_{i+1} − x_i − r_i − r_{i+1}: x_i(T) = x_i(0) + g_i, and sphere 5
// leaves at v at t_last = Σ g_i / v: x_5(T) = x_5(0) + v (T − t_last). So
// ∂x_i/∂r_k = ∂g_i/∂r_k (−1 for the two spheres of gap i) for i ≤ 4,
// ∂x_5/∂r_k = −Σ_i ∂g_i/∂r_k (1 for the end spheres, 2 for the inner ones),
// and no velocity changes. A mass moved alone changes every impact; all
// five moved together change nothing (only mass ratios enter), so the m_i
// columns sum to zero, as the scene's one m (registry) reports. Along e,
// an impact of equal masses leaves the striker at (1 − e)/2 and the struck
// at (1 + e)/2 of the striker's speed: sphere j + 1 crosses gap j + 1 at
// ((1 + e)/2)^j v, so at e = 1 the impact time t_i of gap i (0-based)
// moves by −Σ_{j≤i} g_j j/(2v); sphere i ≤ 3 then drifts back at −v/2 per
// unit e, ∂x_i/∂e = −(v/2)(T − t_i), and sphere 4 leaves at ((1 + e)/2)⁴ v,
// ∂ẋ_4/∂e = 2v, ∂x_4/∂e = 2v (T − t_3) − v ∂t_3/∂e.
TEST(ImpactSensitivity, NewtonsCradleWithOpenGapsMatchesItsClosedForm) {
  constexpr int n = 5;
  const double m = 0.1, rad = 0.02, v = 1.0, T = 0.6;
  const lm::SpheresOnLine<n> cradle({m, m, m, m, m}, {rad, rad, rad, rad, rad}, 1.0);
  lagrangian::State<n> s;
  s.q << 0.0, 0.11, 0.23, 0.32, 0.45;
  s.qd << v, 0, 0, 0, 0;
  std::vector<std::string> names;
  for (int k = 1; k <= n; ++k) names.push_back("m" + std::to_string(k));
  for (int k = 1; k <= n; ++k) names.push_back("r" + std::to_string(k));
  names.push_back("e");
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(cradle, s, tight(T, names));
  EXPECT_EQ(r.impacts, n - 1);
  const Eigen::MatrixXd& got = r.sensitivities.back();
  Eigen::MatrixXd radii = Eigen::MatrixXd::Zero(2 * n, n);
  for (int gap = 0; gap < n - 1; ++gap)
    for (int k : {gap, gap + 1}) {
      radii(gap, k) -= 1.0;
      radii(n - 1, k) += 1.0;
    }
  Eigen::VectorXd along_e = Eigen::VectorXd::Zero(2 * n);
  double t_i = 0, dt_i = 0;
  for (int i = 0; i < n - 1; ++i) {
    const double gap = s.q[i + 1] - s.q[i] - 2 * rad;
    t_i += gap / v;
    dt_i -= gap * i / (2 * v);
    along_e[i] = -0.5 * v * (T - t_i);
    along_e[n + i] = -0.5 * v;
  }
  along_e[n - 1] = 2 * v * (T - t_i) - v * dt_i;
  along_e[2 * n - 1] = 2 * v;
  const double radius_error = (got.middleCols(n, n) - radii).cwiseAbs().maxCoeff();
  const double e_error = (got.col(2 * n) - along_e).cwiseAbs().maxCoeff();
  const Eigen::VectorXd all_masses = got.leftCols(n).rowwise().sum();
  std::printf("Newton's cradle: radii's columns %.2e and e's %.2e from the closed form; the masses' sum %.2e (each up "
              "to %.2f)\n",
              radius_error, e_error, all_masses.cwiseAbs().maxCoeff(), got.leftCols(n).cwiseAbs().maxCoeff());
  EXPECT_LE(radius_error, 1e-9) << got.middleCols(n, n) << "\n\n" << radii;
  EXPECT_LE(e_error, 1e-9) << got.col(2 * n) << "\n\n" << along_e;
  for (int k = 0; k < n; ++k) EXPECT_GT(got.col(k).cwiseAbs().maxCoeff(), 0.01) << "m" << k + 1;
  EXPECT_LE(all_masses.cwiseAbs().maxCoeff(), 1e-9) << all_masses;
}

// An oblique impact of the same spheres (the common normal turns with the
// offset of the centres): every parameter against central differences of
// simulate().
TEST(ImpactSensitivity, TwoSpheresObliqueMatchDifferencesOfSimulate) {
  const lm::TwoSpheres<2> spheres(1.2, 0.7, 0.15, 0.1, 0.6);
  lagrangian::State<4> s;
  s.q << 0.0, 0.0, 1.0, 0.12;
  s.qd << 1.5, 0.1, -0.4, -0.05;
  const double T = 1.3;
  const std::vector<std::string> names = {"m1", "m2", "r1", "r2", "e"};
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(spheres, s, tight(T, names));
  EXPECT_EQ(r.impacts, 1);
  const Eigen::MatrixXd fd = parameter_differences(spheres, s, T, 1e-5, names);
  std::printf("two spheres oblique: %.2e relative from central differences\n",
              worst_relative(r.sensitivities.back(), fd));
  EXPECT_GT(fd.cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LT(worst_relative(r.sensitivities.back(), fd), 1e-6) << r.sensitivities.back() << "\n\n" << fd;
}

// The models with a mass or radius per body reach them through accessors
// generated per element: each name must reach its own body's value (set
// here apart from every other; the chain's in test_sensitivity.cpp).
TEST(ImpactSensitivity, ParametersHeldInArraysAreNamedByTheirBodies) {
  using lagrangian::testing::expect_parameters_named;
  expect_parameters_named(lm::SpheresOnLine<3>({1.1, 1.2, 1.3}, {0.21, 0.22, 0.23}, 0.7),
                          {{"m1", 1.1}, {"m2", 1.2}, {"m3", 1.3}, {"r1", 0.21}, {"r2", 0.22}, {"r3", 0.23}, {"e", 0.7}});
  expect_parameters_named(lm::SpheresInBox<2>({1.1, 1.2}, {0.21, 0.22}, 3.0, 4.0, 0.6, 0.7, 5.0),
                          {{"m1", 1.1}, {"m2", 1.2}, {"r1", 0.21}, {"r2", 0.22}, {"W", 3.0}, {"H", 4.0},
                           {"e_wall", 0.6}, {"e_pair", 0.7}, {"g", 5.0}});
}

// Three discs of their own masses and radii in a box under gravity, over
// several impacts with the walls and each other: every parameter against
// central differences of simulate(), the moved boxes built by their
// constructor (independent of the accessors).
TEST(ImpactSensitivity, DiscsInABoxMatchDifferencesOfSimulate) {
  using Box = lm::SpheresInBox<3>;
  const std::vector<double> p = {1.0, 1.5, 0.8, 0.1, 0.12, 0.09, 2.0, 1.0, 0.9, 0.8, 1.5};
  const auto build = [](const std::vector<double>& v) {
    return Box({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, v[6], v[7], v[8], v[9], v[10]);
  };
  lagrangian::State<6> s;
  s.q << 0.4, 0.5, 1.0, 0.3, 1.6, 0.7;
  s.qd << 1.0, 0.5, -0.7, 0.8, 0.3, -1.0;
  const double T = 1.0;
  const std::vector<std::string> names = lagrangian::parameter_names_of<Box>();
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(build(p), s, tight(T, names));
  EXPECT_GE(r.impacts, 3);
  const Eigen::MatrixXd fd = central_differences(build, p, s, T, 1e-5);
  std::printf("three discs in a box (%d impacts): %.2e relative from central differences\n", r.impacts,
              worst_relative(r.sensitivities.back(), fd));
  EXPECT_GT(fd.cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LT(worst_relative(r.sensitivities.back(), fd), 1e-6) << r.sensitivities.back() << "\n\n" << fd;
}

/// The moving table with a restitution() of doubles: its coefficient (and
/// so perhaps its gaps) does not follow its parameters.
template <class P = double>
struct TableWithFixedRestitution : BouncingBall<P> {
  template <class Q>
  using with_parameter_type = TableWithFixedRestitution<Q>;
  static constexpr std::array<P TableWithFixedRestitution::*, 4> parameter_members() {
    return {&TableWithFixedRestitution::g, &TableWithFixedRestitution::e, &TableWithFixedRestitution::amplitude,
            &TableWithFixedRestitution::omega};
  }
  std::array<double, 1> restitution() const { return {lagrangian::ad::value_of(this->e)}; }
};

TEST(ImpactSensitivity, ContactsThatDoNotFollowTheParametersAreRefused) {
  const TableWithFixedRestitution<> ball;
  lagrangian::State<1> s;
  s.q[0] = 0.3;
  lagrangian::SensitivityOptions o = tight(1.0, {"g"});
  try {
    (void)lagrangian::sensitivities(ball, s, o);
    FAIL() << "a parameter column crossed impacts whose law does not follow the parameters";
  } catch (const lagrangian::AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("do not follow its parameters"), std::string::npos) << e.what();
  }
  // The initial state's columns still cross.
  o.initial_state = true;
  o.parameters.clear();
  EXPECT_EQ(lagrangian::sensitivities(ball, s, o).impacts, 3);
}

}  // namespace
