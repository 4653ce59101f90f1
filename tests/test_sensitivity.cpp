// Forward sensitivities ∂x(t)/∂x(t0) and ∂x(t)/∂p (analysis/sensitivity.hpp)
// against closed forms (the harmonic oscillator, a projectile with and
// without linear drag, its range, the plane pendulum's exact motion, a
// circular orbit in the inverse-square field) and against central
// differences of simulate() (the double, spherical, elastic and driven
// pendulums, the bead on a spinning hoop, the pendulum on a sprung cart);
// the three-link chain from rest against its scaling law.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/models/two_body.hpp"

#include "final_state.hpp"
#include "jet_jacobian.hpp"
#include "named_parameters.hpp"
#include "tangent_options.hpp"

namespace {

namespace lm = lagrangian::models;

lagrangian::SensitivityOptions tight(double t_end, std::vector<std::string> parameters, double interval = -1) {
  return lagrangian_test::sensitivity_options(t_end, std::move(parameters), interval);
}

/// The model M built by its constructor from its parameters' values in the
/// order of its description: independent of parameter_members(), so a list
/// in another order than the names would not agree with itself.
template <class M>
struct ByConstructor {
  template <std::size_t P>
  M operator()(const std::array<double, P>& values) const {
    return std::apply([](auto... v) { return M(v...); }, values);
  }
};

/// Every parameter column of `model` from `s` at t = T against central
/// differences of simulate()'s state at T, each parameter moved by ±1e-5 of
/// itself (truncation ~h², integration noise ~1e-13/h, both far below the
/// bound 1e-6 of the column's largest entry), the moved models made by
/// `build` from the values in the names' order. The parameters named in
/// `absent` cancel from the equations of motion (a mass that multiplies
/// all of L): their columns are 0 to rounding.
template <class M, class Build = ByConstructor<M>>
void expect_parameters_match_central_differences(const M& model, const lagrangian::State<M::coordinate_count>& s,
                                                 double T, const std::vector<std::string>& absent = {},
                                                 Build build = {}) {
  constexpr int n = M::coordinate_count;
  constexpr auto members = M::parameter_members();
  const std::vector<std::string> names = lagrangian::parameter_names_of<M>();
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(model, s, tight(T, names));
  const Eigen::MatrixXd& got = r.sensitivities.back();
  ASSERT_EQ(got.cols(), 2 * n + static_cast<int>(members.size()));
  std::array<double, members.size()> base{};
  for (std::size_t i = 0; i < members.size(); ++i) base[i] = lagrangian::detail::parameter_of(model, members[i]);
  for (std::size_t j = 0; j < members.size(); ++j) {
    const Eigen::VectorXd column = got.col(2 * n + static_cast<int>(j));
    if (std::find(absent.begin(), absent.end(), names[j]) != absent.end()) {
      EXPECT_LE(column.cwiseAbs().maxCoeff(), 1e-12 * (1 + got.leftCols(2 * n).cwiseAbs().maxCoeff()))
          << model.name() << " d/d" << names[j] << "\n" << column;
      continue;
    }
    auto up = base, down = base;
    const double h = 1e-5 * base[j];
    up[j] += h;
    down[j] -= h;
    const Eigen::VectorXd fd =
        (lagrangian::testing::final_state(build(up), s, T) - lagrangian::testing::final_state(build(down), s, T)) /
        (2 * h);
    const double scale = fd.cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 1e-3) << model.name() << " d/d" << names[j];
    std::printf("%s d/d%s: largest entry %.4f, against central differences %.2e of it\n", model.name().c_str(),
                names[j].c_str(), scale, (column - fd).cwiseAbs().maxCoeff() / scale);
    EXPECT_LE((column - fd).cwiseAbs().maxCoeff(), 1e-6 * scale) << model.name() << " d/d" << names[j] << "\n"
                                                                  << column << "\n\n" << fd;
  }
}

}  // namespace

// x = x0 cos ωt + (v0/ω) sin ωt, v = −x0 ω sin ωt + v0 cos ωt, ω = √(k/m):
// Φ = [[cos ωt, sin ωt/ω], [−ω sin ωt, cos ωt]], and through ω
//   ∂x/∂ω = −x0 t sin ωt − (v0/ω²) sin ωt + (v0/ω) t cos ωt,
//   ∂v/∂ω = −x0 sin ωt − x0 ω t cos ωt − v0 t sin ωt,
//   ∂ω/∂m = −ω/(2m),  ∂ω/∂k = 1/(2mω),
// at every sample of a run over several periods.
TEST(Sensitivity, HarmonicOscillatorMatchesItsClosedFormAtEverySample) {
  const double m = 2.0, k = 8.0, w = 2.0, x0 = 0.3, v0 = -0.5;
  const lm::HarmonicOscillator osc(m, k);
  lagrangian::State<1> s;
  s.q[0] = x0;
  s.qd[0] = v0;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(osc, s, tight(7.3, {"k", "m"}, 0.5));
  ASSERT_EQ(r.times.size(), 16u);  // 0, 0.5, …, 7.0 and the end 7.3
  EXPECT_DOUBLE_EQ(r.times.front(), 0.0);
  EXPECT_DOUBLE_EQ(r.times.back(), 7.3);
  ASSERT_EQ(r.parameters, (std::vector<std::string>{"k", "m"}));
  EXPECT_EQ(r.state_columns, 2);
  double worst = 0;
  for (std::size_t i = 0; i < r.times.size(); ++i) {
    const double t = r.times[i], c = std::cos(w * t), sn = std::sin(w * t);
    const double dx_dw = -x0 * t * sn - v0 / (w * w) * sn + v0 / w * t * c;
    const double dv_dw = -x0 * sn - x0 * w * t * c - v0 * t * sn;
    Eigen::Matrix<double, 2, 4> expected;
    expected << c, sn / w, dx_dw / (2 * m * w), dx_dw * (-w / (2 * m)),  //
        -w * sn, c, dv_dw / (2 * m * w), dv_dw * (-w / (2 * m));
    const Eigen::MatrixXd& got = r.sensitivities[i];
    ASSERT_EQ(got.rows(), 2);
    ASSERT_EQ(got.cols(), 4);
    worst = std::max(worst, (got - expected).cwiseAbs().maxCoeff());
    EXPECT_NEAR(r.states[i][0], x0 * c + v0 / w * sn, 1e-11) << "t = " << t;
  }
  std::printf("oscillator: largest error of [Phi | d/dk | d/dm] over %zu samples %.2e\n", r.times.size(), worst);
  EXPECT_LE(worst, 1e-10);
}

// A projectile under linear drag b from (x0, y0) = 0 with (u_x, u_y), k = b/m:
//   x = u_x F,  ẋ = u_x e,  y = (u_y + g/k) F − g t/k,  ẏ = (u_y + g/k) e − g/k,
//   e = e^(−kt), F = (1 − e)/k,  ∂F/∂k = t e/k − F/k;
// b and m act through k (∂k/∂b = 1/m, ∂k/∂m = −b/m²), g directly, and the
// ground's angle β only through the landing event, which the flow does not
// apply: its column is zero.
TEST(Sensitivity, LinearDragProjectileMatchesItsClosedFormInEveryParameter) {
  const double m = 0.5, g = 9.81, b = 0.2, ux = 12.0, uy = 9.0;
  const lm::Projectile<lm::Drag::linear> p(m, g, 0.1, b);
  lagrangian::State<2> s;
  s.q << 0.0, 0.0;
  s.qd << ux, uy;
  const double T = 1.7;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(p, s, tight(T, {"b", "m", "g", "beta"}));
  const Eigen::MatrixXd& got = r.sensitivities.back();
  ASSERT_EQ(got.cols(), 4 + 4);
  const double kk = b / m, e = std::exp(-kk * T), F = (1 - e) / kk, dF = T * e / kk - F / kk;
  const double a = uy + g / kk;
  Eigen::Vector4d d_dk, d_dg;
  d_dk << ux * dF, -g / (kk * kk) * F + a * dF + g * T / (kk * kk), -ux * T * e,
      -g / (kk * kk) * e - a * T * e + g / (kk * kk);
  d_dg << 0, F / kk - T / kk, 0, e / kk - 1 / kk;
  // the state order is (x, y, ẋ, ẏ)
  const Eigen::Vector4d d_db = d_dk / m, d_dm = -b / (m * m) * d_dk;
  std::printf("linear drag: relative errors d/db %.2e, d/dm %.2e, d/dg %.2e\n",
              (got.col(4) - d_db).cwiseAbs().maxCoeff() / d_db.cwiseAbs().maxCoeff(),
              (got.col(5) - d_dm).cwiseAbs().maxCoeff() / d_dm.cwiseAbs().maxCoeff(),
              (got.col(6) - d_dg).cwiseAbs().maxCoeff() / d_dg.cwiseAbs().maxCoeff());
  EXPECT_LE((got.col(4) - d_db).cwiseAbs().maxCoeff(), 1e-9 * d_db.cwiseAbs().maxCoeff()) << got.col(4) << "\n" << d_db;
  EXPECT_LE((got.col(5) - d_dm).cwiseAbs().maxCoeff(), 1e-9 * d_dm.cwiseAbs().maxCoeff()) << got.col(5) << "\n" << d_dm;
  EXPECT_LE((got.col(6) - d_dg).cwiseAbs().maxCoeff(), 1e-9 * d_dg.cwiseAbs().maxCoeff()) << got.col(6) << "\n" << d_dg;
  EXPECT_EQ(got.col(7).cwiseAbs().maxCoeff(), 0.0);
  // Φ of ẋ under drag: ∂ẋ(T)/∂ẋ(0) = e^(−kT).
  EXPECT_NEAR(got(2, 2), e, 1e-12);
}

// Without drag over flat ground the range R = u² sin 2α / g, so
//   ∂R/∂α = 2u² cos 2α / g,   ∂R/∂g = −R/g.
// R = x(t_L) where y(t_L) = 0 at t_L = 2u sin α / g; a change of the
// launch moves the landing time too, so dR = δx − (ẋ/ẏ) δy at t_L, with δx
// = Φ δx0 (δx0 = ∂x0/∂α = (0, 0, −u sin α, u cos α)) or the g column.
TEST(Sensitivity, ProjectileRangeDerivativesMatchTheClosedForm) {
  const double u = 20.0, g = 9.81;
  const lm::Projectile<> p(1.0, g);
  for (const double alpha : {0.3, 0.7853981633974483, 1.2}) {
    const lagrangian::State<2> s = p.launch(u, alpha);
    const double tl = 2 * u * std::sin(alpha) / g;
    const lagrangian::SensitivityResult r = lagrangian::sensitivities(p, s, tight(tl, {"g"}));
    const Eigen::MatrixXd& S = r.sensitivities.back();
    const Eigen::VectorXd& x = r.states.back();
    EXPECT_NEAR(x[1], 0.0, 1e-10);
    const double slope = x[2] / x[3];  // ẋ/ẏ at landing
    Eigen::Vector4d dx0;
    dx0 << 0, 0, -u * std::sin(alpha), u * std::cos(alpha);
    const Eigen::Vector4d dx_dalpha = S.leftCols(4) * dx0;
    const double dR_dalpha = dx_dalpha[0] - slope * dx_dalpha[1];
    const double dR_dg = S(0, 4) - slope * S(1, 4);
    const double R = u * u * std::sin(2 * alpha) / g;
    std::printf("range, alpha = %.4f: dR/dalpha %.12f (closed form %.12f), dR/dg %.12f (%.12f)\n", alpha, dR_dalpha,
                2 * u * u * std::cos(2 * alpha) / g, dR_dg, -R / g);
    EXPECT_NEAR(dR_dalpha, 2 * u * u * std::cos(2 * alpha) / g, 1e-9 * u * u / g) << "alpha = " << alpha;
    EXPECT_NEAR(dR_dg, -R / g, 1e-9 * u * u / (g * g)) << "alpha = " << alpha;
  }
}

using lagrangian::testing::final_state;

// Every parameter of the double pendulum against central differences of
// simulate()'s state at t = 1 s.
TEST(Sensitivity, DoublePendulumParametersMatchCentralDifferencesOfTheFlow) {
  lagrangian::State<2> s;
  s.q << 1.2, -0.4;
  s.qd << 0.3, 0.8;
  expect_parameters_match_central_differences(lm::DoublePendulum(1.3, 0.8, 1.1, 0.7, 9.81), s, 1.0);
}

// The spherical, elastic and driven pendulums (the drive's amplitude and
// rate enter T and V through the pivot's motion) the same way; the bob's
// mass multiplies all of L of the spherical and the driven pendulum.
TEST(Sensitivity, PendulumParametersMatchCentralDifferencesOfTheFlow) {
  lagrangian::State<2> sph;
  sph.q << 0.9, 0.2;
  sph.qd << 0.4, 1.3;
  expect_parameters_match_central_differences(lm::SphericalPendulum(0.7, 1.2, 9.81), sph, 1.5, {"m"});
  lagrangian::State<2> el;
  el.q << 1.1, 0.6;
  el.qd << 0.3, -0.5;
  expect_parameters_match_central_differences(lm::ElasticPendulum(0.9, 35.0, 1.0, 9.81), el, 1.2);
  lagrangian::State<1> dr;
  dr.q << 0.4;
  dr.qd << -0.2;
  expect_parameters_match_central_differences(lm::DrivenPendulum(1.1, 0.8, 0.05, 30.0, 9.81), dr, 1.0, {"m"});
}

// The bead on the spinning hoop (the spin rate enters T) and the pendulum
// on a sprung cart the same way; the bead's mass multiplies all of L.
TEST(Sensitivity, HoopAndCartParametersMatchCentralDifferencesOfTheFlow) {
  lagrangian::State<1> bead;
  bead.q << 0.7;
  bead.qd << 1.1;
  expect_parameters_match_central_differences(lm::BeadOnRotatingHoop(0.4, 0.6, 5.0, 9.81), bead, 1.3, {"m"});
  lagrangian::State<2> cart;
  cart.q << 0.2, 0.9;
  cart.qd << -0.3, 0.5;
  expect_parameters_match_central_differences(lm::CartPendulum(2.5, 0.8, 1.1, 12.0, 9.81), cart, 1.4);
}

// A circular orbit of the inverse-square field in polar coordinates:
// r = a, φ̇ = ω = √(k/(m a³)). With the start held, ℓ = m a² ω stays and
// r̈ = ℓ²/(m² r³) − k/(m r²); along k the linearised motion about the
// orbit is δr̈ = −ω² δr − δk/(m a²) from rest, so
//   ∂r/∂k = −(a/k)(1 − cos ωt),  ∂ṙ/∂k = −(a ω/k) sin ωt,
// and from φ̇ = ℓ/(m r²), δφ̇ = −2ω δr/a:
//   ∂φ/∂k = (2/k)(ωt − sin ωt),  ∂φ̇/∂k = (2ω/k)(1 − cos ωt).
// The motion depends on k/m alone: ∂/∂m = −(k/m) ∂/∂k. Exact for the
// variational equations (they are linear), over three orbits.
TEST(Sensitivity, KeplerPolarCircularOrbitMatchesItsClosedForm) {
  const double m = 1.5, k = 2.4, a = 1.2, w = std::sqrt(k / (m * a * a * a));
  const lm::KeplerPolar model(m, k);
  lagrangian::State<2> s;
  s.q << a, 0.3;
  s.qd << 0.0, w;
  const double T = 3 * 2 * std::acos(-1.0) / w;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(model, s, tight(T, {"k", "m"}, T / 7));
  double worst = 0;
  for (std::size_t i = 0; i < r.times.size(); ++i) {
    const double t = r.times[i], c = std::cos(w * t), sn = std::sin(w * t);
    const Eigen::Vector4d dk(-(a / k) * (1 - c), (2 / k) * (w * t - sn), -(a * w / k) * sn, (2 * w / k) * (1 - c));
    const Eigen::MatrixXd& got = r.sensitivities[i];
    ASSERT_EQ(got.cols(), 4 + 2);
    worst = std::max({worst, (got.col(4) - dk).cwiseAbs().maxCoeff(),
                      (got.col(5) - (-(k / m) * dk)).cwiseAbs().maxCoeff()});
  }
  std::printf("polar Kepler circular orbit: largest error of d/dk, d/dm over %zu samples %.2e (entries up to %.1f)\n",
              r.times.size(), worst, r.sensitivities.back().rightCols(2).cwiseAbs().maxCoeff());
  EXPECT_LE(worst, 1e-9);
}

// The reduced Kepler problem in Cartesian coordinates (RelativeMotion, k in
// its potential) and in polar ones (KeplerPolar, its columns held to a
// closed form above), on an ellipse: one flow, ψ(r, φ, ṙ, φ̇) = (r cos φ,
// r sin φ, ṙ cos φ − r φ̇ sin φ, ṙ sin φ + r φ̇ cos φ) not depending on μ or
// k, so the columns are one, s_c(t) = Dψ(x_p(t)) s_p(t) (Dψ by a Jet).
TEST(Sensitivity, KeplerInCartesianCoordinatesIsThePolarModelAlongMuAndK) {
  const double mu = 0.8, k = 1.7;
  const lm::RelativeMotion<2> cartesian(mu, lm::NewtonianGravity{k});
  const lm::KeplerPolar polar(mu, k);
  const auto psi = [](const Eigen::Vector4d& x) {
    return lagrangian_test::value_and_jacobian<4>(
        [](const auto& a) {
          using S = typename std::decay_t<decltype(a)>::Scalar;
          using std::cos;
          using std::sin;
          const S c = cos(a[1]), sn = sin(a[1]);
          Eigen::Matrix<S, 4, 1> y;
          y << a[0] * c, a[0] * sn, a[2] * c - a[0] * a[3] * sn, a[2] * sn + a[0] * a[3] * c;
          return y;
        },
        x);
  };
  const Eigen::Vector4d x0(1.1, 0.4, 0.2, 0.9);
  lagrangian::State<2> sp;
  sp.q = x0.head<2>();
  sp.qd = x0.tail<2>();
  const Eigen::Vector4d big = psi(x0).first;
  lagrangian::State<2> sc;
  sc.q = big.head<2>();
  sc.qd = big.tail<2>();
  const double T = 6.0;
  lagrangian::SensitivityOptions o = tight(T, {"mu", "k"});
  o.initial_state = false;
  const lagrangian::SensitivityResult rp = lagrangian::sensitivities(polar, sp, tight(T, {"m", "k"}));
  const lagrangian::SensitivityResult rc = lagrangian::sensitivities(cartesian, sc, o);
  ASSERT_EQ(rc.sensitivities.back().cols(), 2);
  const Eigen::Matrix<double, 4, 2> expected = psi(rp.states.back()).second * rp.sensitivities.back().rightCols(2);
  const double error = (rc.sensitivities.back() - expected).cwiseAbs().maxCoeff();
  std::printf("Kepler in Cartesian coordinates, d/dmu and d/dk against the polar model's: %.2e of the largest %.2f\n",
              error, expected.cwiseAbs().maxCoeff());
  EXPECT_GT(expected.cwiseAbs().maxCoeff(), 1.0);
  EXPECT_LE(error, 1e-8 * expected.cwiseAbs().maxCoeff()) << rc.sensitivities.back() << "\n\n" << expected;
}

// The two-body problem (TwoBody: m1, m2, k) along k: the relative
// coordinate r = r2 − r1 moves as the reduced problem of μ = m1 m2/(m1 + m2)
// in the same potential, and the centre of mass uniformly whatever k, so
// the relative rows of the column are RelativeMotion's column of k and
// m1 s_1 + m2 s_2 = 0. Every parameter against central differences of
// simulate() too (m1 and m2 move the centre of mass's start).
TEST(Sensitivity, TwoBodyAlongKIsTheReducedProblemAndMatchesCentralDifferences) {
  const double m1 = 1.3, m2 = 0.6, k = 2.1;
  const lm::TwoBody<2> pair(m1, m2, lm::NewtonianGravity{k});
  lagrangian::State<4> s;
  s.q << -0.3, 0.1, 0.8, -0.2;
  s.qd << 0.1, -0.5, -0.2, 1.1;
  const double T = 2.5;
  lagrangian::SensitivityOptions o = tight(T, {"k"});
  o.initial_state = false;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(pair, s, o);
  const lm::RelativeMotion<2> reduced(lm::reduced_mass(m1, m2), lm::NewtonianGravity{k});
  lagrangian::State<2> rel;
  rel.q = s.q.tail<2>() - s.q.head<2>();
  rel.qd = s.qd.tail<2>() - s.qd.head<2>();
  const lagrangian::SensitivityResult rr = lagrangian::sensitivities(reduced, rel, o);
  const Eigen::VectorXd col = r.sensitivities.back().col(0);
  Eigen::Vector4d relative, centre;
  relative << col.segment<2>(2) - col.segment<2>(0), col.segment<2>(6) - col.segment<2>(4);
  centre << m1 * col.segment<2>(0) + m2 * col.segment<2>(2), m1 * col.segment<2>(4) + m2 * col.segment<2>(6);
  const Eigen::Vector4d expected = rr.sensitivities.back().col(0);
  std::printf("two bodies d/dk: relative rows %.2e from the reduced problem's (largest %.2f), centre of mass %.2e\n",
              (relative - expected).cwiseAbs().maxCoeff(), expected.cwiseAbs().maxCoeff(),
              centre.cwiseAbs().maxCoeff());
  EXPECT_GT(expected.cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LE((relative - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.cwiseAbs().maxCoeff());
  EXPECT_LE(centre.cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());
  expect_parameters_match_central_differences(pair, s, T, {}, [](const std::array<double, 3>& v) {
    return lm::TwoBody<2>(v[0], v[1], lm::NewtonianGravity{v[2]});
  });
}

// The plane pendulum's exact motion (SimplePendulum::reference(), Jacobi's
// elliptic functions) at 1.7 s from 1.1 rad, −0.6 rad/s: the columns of l
// and g against central differences of the closed form (no integration on
// that side; step 1e-6 of each), and θ does not depend on m: 0 to rounding.
TEST(Sensitivity, PlanePendulumParametersMatchItsExactMotion) {
  const lm::SimplePendulum model(0.6, 1.3, 9.81);
  lagrangian::State<1> s;
  s.q << 1.1;
  s.qd << -0.6;
  const double T = 1.7;
  const lagrangian::SensitivityResult r = lagrangian::sensitivities(model, s, tight(T, {"m", "l", "g"}));
  const Eigen::MatrixXd& got = r.sensitivities.back();
  ASSERT_EQ(got.cols(), 2 + 3);
  EXPECT_LE(got.col(2).cwiseAbs().maxCoeff(), 1e-12 * got.leftCols(2).cwiseAbs().maxCoeff()) << got.col(2);
  const auto exact = [&](double l, double g) {
    const lagrangian::State<1> e = lm::SimplePendulum(0.6, l, g).reference(s, T);
    return Eigen::Vector2d(e.q[0], e.qd[0]);
  };
  const Eigen::Vector2d dl = (exact(1.3 + 1.3e-6, 9.81) - exact(1.3 - 1.3e-6, 9.81)) / 2.6e-6;
  const Eigen::Vector2d dg = (exact(1.3, 9.81 + 9.81e-6) - exact(1.3, 9.81 - 9.81e-6)) / 1.962e-5;
  std::printf("plane pendulum d/dl %.3e, d/dg %.3e of the largest entry against the exact motion\n",
              (got.col(3) - dl).cwiseAbs().maxCoeff() / dl.cwiseAbs().maxCoeff(),
              (got.col(4) - dg).cwiseAbs().maxCoeff() / dg.cwiseAbs().maxCoeff());
  EXPECT_LE((got.col(3) - dl).cwiseAbs().maxCoeff(), 1e-7 * dl.cwiseAbs().maxCoeff()) << got.col(3) << "\n" << dl;
  EXPECT_LE((got.col(4) - dg).cwiseAbs().maxCoeff(), 1e-7 * dg.cwiseAbs().maxCoeff()) << got.col(4) << "\n" << dg;
}

// The three-link chain of equal bobs m on equal rods l released from rest
// moves as q(t) = Θ(ωt), ω = √(g/l), with Θ the motion of the
// dimensionless chain (l and g leave T/(m l²) and V/(m g l) and the start
// at rest). Moving every rod together, ∂ω/∂l = −ω/(2l), so
//   ∂q/∂l = −t q̇/(2l),  ∂q̇/∂l = −(q̇ + t q̈)/(2l),
// and ∂ω/∂g = ω/(2g):  ∂q/∂g = t q̇/(2g),  ∂q̇/∂g = (q̇ + t q̈)/(2g),
// with q, q̇, q̈ of the run at t. The columns of l1, l2, l3 (the model's,
// one rod each) sum to the first; those of m1, m2, m3 to zero (only mass
// ratios enter), though each alone moves the chain.
TEST(Sensitivity, PendulumChainFromRestScalesWithItsRodsAndGravity) {
  constexpr int n = 3;
  const double m = 1.3, l = 0.8, g = 9.81, T = 1.5;
  const lm::PendulumChain<n> chain(m, l, g);
  EXPECT_EQ(lagrangian::parameter_names_of<lm::PendulumChain<n>>(),
            (std::vector<std::string>{"m1", "m2", "m3", "l1", "l2", "l3", "g"}));
  lagrangian::State<n> s;
  s.q << 0.5, 0.4, 0.3;
  s.qd.setZero();
  const lagrangian::SensitivityResult r =
      lagrangian::sensitivities(chain, s, tight(T, {"m1", "m2", "m3", "l1", "l2", "l3", "g"}));
  const Eigen::MatrixXd& got = r.sensitivities.back();
  ASSERT_EQ(got.cols(), 2 * n + 7);
  const Eigen::VectorXd x = r.states.back();
  const lagrangian::Vec<double, n> q = x.head(n), qd = x.tail(n);
  const lagrangian::Vec<double, n> qdd = lagrangian::accelerations(chain, q, qd, T);
  Eigen::VectorXd along_l(2 * n), along_g(2 * n);
  along_l << -T * qd / (2 * l), -(qd + T * qdd) / (2 * l);
  along_g << T * qd / (2 * g), (qd + T * qdd) / (2 * g);
  const Eigen::VectorXd masses = got.middleCols(2 * n, n).rowwise().sum();
  const Eigen::VectorXd rods = got.middleCols(3 * n, n).rowwise().sum();
  const double scale = along_l.cwiseAbs().maxCoeff();
  std::printf("pendulum chain from rest: rods %.2e, g %.2e of the largest entry (%.2f) from the scaling law; "
              "the masses' sum %.2e\n",
              (rods - along_l).cwiseAbs().maxCoeff() / scale,
              (got.col(2 * n + 6) - along_g).cwiseAbs().maxCoeff() / along_g.cwiseAbs().maxCoeff(), scale,
              masses.cwiseAbs().maxCoeff());
  EXPECT_LE((rods - along_l).cwiseAbs().maxCoeff(), 1e-9 * scale) << rods << "\n\n" << along_l;
  EXPECT_LE((got.col(2 * n + 6) - along_g).cwiseAbs().maxCoeff(), 1e-9 * along_g.cwiseAbs().maxCoeff())
      << got.col(2 * n + 6) << "\n\n" << along_g;
  EXPECT_LE(masses.cwiseAbs().maxCoeff(), 1e-9 * scale) << masses;
  for (int k = 0; k < n; ++k) {
    EXPECT_GT(got.col(2 * n + k).cwiseAbs().maxCoeff(), 1e-3 * scale) << "m" << k + 1;
    EXPECT_GT(got.col(3 * n + k).cwiseAbs().maxCoeff(), 1e-3 * scale) << "l" << k + 1;
  }
}

// The chain's masses and rods are arrays reached through accessors
// generated per element: each name reaches its own link's value.
TEST(Sensitivity, PendulumChainParametersAreNamedByTheirLinks) {
  lm::PendulumChain<3> chain(1.0, 1.0, 9.5);
  chain.m = {1.1, 1.2, 1.3};
  chain.l = {0.21, 0.22, 0.23};
  lagrangian::testing::expect_parameters_named(
      chain, {{"m1", 1.1}, {"m2", 1.2}, {"m3", 1.3}, {"l1", 0.21}, {"l2", 0.22}, {"l3", 0.23}, {"g", 9.5}});
}

// The parameters' columns alone (no state transition matrix) are the same
// columns: the run's error control differs, so to the tolerance.
TEST(Sensitivity, ParameterColumnsAloneAgreeWithTheFullRun) {
  const lm::DoublePendulum m;
  lagrangian::State<2> s;
  s.q << 0.9, 0.5;
  lagrangian::SensitivityOptions o = tight(2.0, {"l2", "g"});
  const lagrangian::SensitivityResult full = lagrangian::sensitivities(m, s, o);
  o.initial_state = false;
  const lagrangian::SensitivityResult alone = lagrangian::sensitivities(m, s, o);
  ASSERT_EQ(alone.state_columns, 0);
  ASSERT_EQ(alone.sensitivities.back().cols(), 2);
  const Eigen::MatrixXd expected = full.sensitivities.back().rightCols(2);
  std::printf("parameter columns alone against the full run: %.2e of the largest entry\n",
              (alone.sensitivities.back() - expected).cwiseAbs().maxCoeff() / expected.cwiseAbs().maxCoeff());
  EXPECT_LE((alone.sensitivities.back() - expected).cwiseAbs().maxCoeff(), 1e-8 * expected.cwiseAbs().maxCoeff());
}

/// An oscillator whose stiffness is a plain double: T = ½ ẋ², V = ½ k x².
struct PlainOscillator {
  static constexpr int coordinate_count = 1;
  double k = 2.0;
  std::string name() const { return "plain_oscillator"; }
  template <class S>
  S kinetic(const lagrangian::Vec<S, 1>&, const lagrangian::Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const lagrangian::Vec<S, 1>& q, const S&) const {
    return 0.5 * k * q[0] * q[0];
  }
};

TEST(Sensitivity, BadRequestsAreNamed) {
  const lm::DoublePendulum m;
  lagrangian::State<2> s;
  try {
    lagrangian::sensitivities(m, s, tight(1.0, {"mass"}));
    FAIL() << "an unknown parameter was accepted";
  } catch (const lagrangian::OptionError& e) {
    EXPECT_EQ(std::string(e.what()),
              "sensitivity: parameters: 'mass' is not a parameter of the model (m1, m2, l1, l2, g)");
  }
  try {
    lagrangian::sensitivities(m, s, tight(1.0, {"g", "g"}));
    FAIL() << "a repeated parameter was accepted";
  } catch (const lagrangian::OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "sensitivity: parameters: 'g' is listed twice");
  }
  lagrangian::SensitivityOptions none = tight(1.0, {});
  none.initial_state = false;
  try {
    lagrangian::sensitivities(m, s, none);
    FAIL() << "a run with no column was accepted";
  } catch (const lagrangian::OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "sensitivity: nothing to compute: initial_state = false and no parameters");
  }
  lagrangian::SensitivityOptions bad_interval = tight(1.0, {"g"});
  bad_interval.run.output_interval = std::nan("");
  EXPECT_THROW(lagrangian::sensitivities(m, s, bad_interval), lagrangian::OptionError);
  // A model whose parameters are plain doubles offers the initial state only.
  const PlainOscillator plain;
  lagrangian::State<1> p;
  p.q[0] = 0.5;
  EXPECT_EQ(lagrangian::sensitivities(plain, p, tight(1.0, {})).sensitivities.back().cols(), 2);
  try {
    lagrangian::sensitivities(plain, p, tight(1.0, {"k"}));
    FAIL() << "a model without a parameter type was differentiated along a parameter";
  } catch (const lagrangian::AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("does not offer parameter sensitivities"), std::string::npos) << e.what();
  }
}
