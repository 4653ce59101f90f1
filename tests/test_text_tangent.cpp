// The tangent flow of models stated as text (text/fixed_size.hpp,
// text/tangent_flow.hpp): against the same systems written in C++, closed
// forms, Liouville's theorem and Kapitza's criterion; with holonomic and
// Pfaffian constraints, on their manifold.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/text/fixed_size.hpp"
#include "lagrangian/text/tangent_flow.hpp"
#include "contact_models.hpp"
#include "text_definitions.hpp"
#include "tangent_options.hpp"
#include "final_state.hpp"
#include "plane_slide.hpp"

namespace {

using lagrangian::Vec;
namespace lm = lagrangian::models;
namespace text = lagrangian::text;

/// Kapitza's pendulum as text, as in examples/scenes/text/driven_pendulum.toml:
/// the pivot at y = a cos Ωt, so T and V depend on t.
text::Definition kapitza_text(double omega) {
  text::Definition d;
  d.coordinates = {"theta"};
  d.kinetic = "0.5*m*((l*cos(theta)*theta_dot)^2 + (-a*Omega*sin(Omega*t) + l*sin(theta)*theta_dot)^2)";
  d.potential = "m*g*(a*cos(Omega*t) - l*cos(theta))";
  d.parameters = {{"m", 1.0}, {"l", 1.0}, {"a", 0.05}, {"Omega", omega}, {"g", 9.81}};
  return d;
}

/// A particle of mass m in a uniform field under linear drag b, the drag
/// given as a Rayleigh function or as generalized forces.
text::Definition linear_drag_text(bool as_dissipation) {
  text::Definition d;
  d.coordinates = {"x", "y"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2)";
  d.potential = "m*g*y";
  if (as_dissipation) {
    d.dissipation = "0.5*b*(x_dot^2 + y_dot^2)";
  } else {
    d.forces = {"-b*x_dot", "-b*y_dot"};
  }
  d.parameters = {{"m", 2.0}, {"g", 9.81}, {"b", 0.5}};
  return d;
}

lagrangian::State<lagrangian::Dynamic> start(std::initializer_list<double> q, std::initializer_list<double> qd) {
  lagrangian::State<lagrangian::Dynamic> s(static_cast<int>(q.size()));
  int i = 0;
  for (double x : q) s.q[i++] = x;
  i = 0;
  for (double x : qd) s.qd[i++] = x;
  return s;
}

/// x(o.t_end) of a plain run of the text model `d` with its parameter
/// `name` set to `value` (central differences along a parameter).
Eigen::VectorXd final_state_with(const text::Definition& d, const std::string& name, double value,
                                 const lagrangian::State<lagrangian::Dynamic>& s, const lagrangian::SimulationOptions& o) {
  text::Definition moved = d;
  for (auto& [key, v] : moved.parameters)
    if (key == name) v = value;
  return lagrangian::testing::final_state(text::TextModel(moved), s, o);
}

TEST(TextTangentFlow, DoublePendulumJacobianIsTheBuiltInModels) {
  const lm::DoublePendulum built_in(1.3, 0.7, 1.1, 0.8, 9.81);
  const text::TextModel model(lagrangian::testing::double_pendulum_text(built_in));
  for (const auto& [q, qd] : {std::pair{Vec<double, 2>(0.3, -1.2), Vec<double, 2>(0.8, 2.1)},
                              std::pair{Vec<double, 2>(2.0, 2.0), Vec<double, 2>(0.0, 0.0)},
                              std::pair{Vec<double, 2>(-3.0, 1.0), Vec<double, 2>(-4.0, 5.5)}}) {
    Eigen::VectorXd qdd_text;
    Eigen::MatrixXd j_text;
    Vec<double, 2> qdd_cpp;
    Eigen::Matrix<double, 2, 4> j_cpp;
    text::state_jacobian(model, q, qd, 0.0, qdd_text, j_text);
    lagrangian::state_jacobian(built_in, q, qd, 0.0, qdd_cpp, j_cpp);
    EXPECT_LE((qdd_text - qdd_cpp).norm(), 1e-13 * (1 + qdd_cpp.norm()));
    EXPECT_LE((j_text - j_cpp).norm(), 1e-12 * (1 + j_cpp.norm())) << "text:\n" << j_text << "\nC++:\n" << j_cpp;
  }
  Eigen::VectorXd qdd;
  Eigen::MatrixXd j;
  EXPECT_THROW(text::state_jacobian(model, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0, qdd, j),
               lagrangian::OptionError);
}

template <int N>
void expect_chain_agrees() {
  const text::TextModel model(lagrangian::testing::pendulum_chain_text(N));
  const lm::PendulumChain<N> built_in;
  Vec<double, N> q, qd;
  for (int k = 0; k < N; ++k) {
    q[k] = std::sin(1.0 + 2.3 * k);
    qd[k] = std::cos(0.4 + 1.7 * k);
  }
  Eigen::VectorXd qdd_text;
  Eigen::MatrixXd j_text;
  Vec<double, N> qdd_cpp;
  Eigen::Matrix<double, N, 2 * N> j_cpp;
  text::state_jacobian(model, q, qd, 0.0, qdd_text, j_text);
  lagrangian::state_jacobian(built_in, q, qd, 0.0, qdd_cpp, j_cpp);
  EXPECT_LE((qdd_text - qdd_cpp).norm(), 1e-12 * (1 + qdd_cpp.norm())) << N << " links";
  EXPECT_LE((j_text - j_cpp).norm(), 1e-11 * (1 + j_cpp.norm())) << N << " links\n" << j_text << "\n" << j_cpp;
}

TEST(TextTangentFlow, ChainsOfThreeToSixLinksHaveTheBuiltInChainsJacobian) {
  // Five and six coordinates take the EomJet numbers' sparse storage.
  expect_chain_agrees<3>();
  expect_chain_agrees<4>();
  expect_chain_agrees<5>();
  expect_chain_agrees<6>();
}

TEST(TextTangentFlow, TimeDependentEnergiesGiveTheBuiltInDrivenPendulums) {
  // T depends on t through the pivot's velocity: the mixed term ∂²L/∂θ̇∂t
  // and its derivatives enter J.
  const lm::DrivenPendulum built_in(1.0, 1.0, 0.05, 200.0, 9.81);
  const text::TextModel model(kapitza_text(200.0));
  for (double t : {0.0, 0.0123, 0.7}) {
    const Vec<double, 1> q(2.9), qd(-0.4);
    Eigen::VectorXd qdd_text;
    Eigen::MatrixXd j_text;
    Vec<double, 1> qdd_cpp;
    Eigen::Matrix<double, 1, 2> j_cpp;
    text::state_jacobian(model, q, qd, t, qdd_text, j_text);
    lagrangian::state_jacobian(built_in, q, qd, t, qdd_cpp, j_cpp);
    EXPECT_NEAR(qdd_text[0], qdd_cpp[0], 1e-12 * (1 + std::abs(qdd_cpp[0]))) << "t = " << t;
    EXPECT_LE((j_text - j_cpp).norm(), 1e-12 * (1 + j_cpp.norm())) << "t = " << t << "\n" << j_text << "\n" << j_cpp;
  }
}

TEST(TextTangentFlow, LinearDragGivesMinusBOverMWhetherDissipationOrForces) {
  for (bool as_dissipation : {true, false}) {
    const text::TextModel model(linear_drag_text(as_dissipation));
    Eigen::VectorXd qdd;
    Eigen::MatrixXd j;
    text::state_jacobian(model, Eigen::Vector2d(1.0, 2.0), Eigen::Vector2d(3.0, -4.0), 0.0, qdd, j);
    Eigen::Matrix<double, 2, 4> expected = Eigen::Matrix<double, 2, 4>::Zero();
    expected(0, 2) = expected(1, 3) = -0.5 / 2.0;  // ∂q̈/∂q̇ = −b/m I
    EXPECT_LE((j - expected).norm(), 1e-15) << (as_dissipation ? "D" : "Q") << "\n" << j;
    EXPECT_NEAR(qdd[0], -0.25 * 3.0, 1e-15);
    EXPECT_NEAR(qdd[1], -9.81 + 0.25 * 4.0, 1e-14);
  }
}

lagrangian::LyapunovOptions lyapunov_over(double t_end) {
  lagrangian::LyapunovOptions o;
  o.run.t_end = t_end;
  o.run.rtol = 1e-10;
  o.run.atol = 1e-12;
  return o;
}

TEST(TextLyapunov, ChaoticDoublePendulumHasTheBuiltInModelsSpectrum) {
  const lm::DoublePendulum built_in;
  const text::TextModel model(lagrangian::testing::double_pendulum_text(built_in));
  lagrangian::State<2> s;
  s.q << 2.0, 2.0;
  // Over 10 s the two runs' trajectories (q̈ equal to rounding) stay within
  // rounding grown by e^(λt), λ ≈ 1.5 1/s: about 1e-9.
  const lagrangian::LyapunovResult cpp = lagrangian::lyapunov_spectrum(built_in, s, lyapunov_over(10.0));
  const lagrangian::LyapunovResult txt =
      text::lyapunov_spectrum(model, start({2.0, 2.0}, {0.0, 0.0}), lyapunov_over(10.0));
  ASSERT_EQ(txt.spectrum.size(), 4u);
  EXPECT_GT(txt.spectrum[0], 0.5);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(txt.spectrum[i], cpp.spectrum[i], 1e-6) << "exponent " << i;
  EXPECT_NEAR(txt.megno, cpp.megno, 1e-6);
  EXPECT_LE(std::abs(txt.sum), 1e-9);  // canonical coordinates keep phase-space volume
  // The largest exponent alone (one direction per step, no Jacobian).
  lagrangian::LyapunovOptions one = lyapunov_over(10.0);
  one.exponents = 1;
  const lagrangian::LyapunovResult a = text::lyapunov_spectrum(model, start({2.0, 2.0}, {0.0, 0.0}), one);
  const lagrangian::LyapunovResult b = lagrangian::lyapunov_spectrum(built_in, s, one);
  ASSERT_EQ(a.spectrum.size(), 1u);
  EXPECT_NEAR(a.spectrum[0], b.spectrum[0], 1e-6);
}

TEST(TextLyapunov, LinearDragContractsPhaseSpaceAtMinusTwoBOverM) {
  // Liouville: tr J = −2b/m at every state, so the exponents sum to −2b/m
  // at every time, with the drag given either way.
  for (bool as_dissipation : {true, false}) {
    const text::TextModel model(linear_drag_text(as_dissipation));
    for (double t_end : {1.0, 7.0}) {
      const lagrangian::LyapunovResult r =
          text::lyapunov_spectrum(model, start({0.0, 0.0}, {14.0, 14.0}), lyapunov_over(t_end));
      ASSERT_EQ(r.spectrum.size(), 4u);
      EXPECT_NEAR(r.sum, -2 * 0.5 / 2.0, 1e-8) << (as_dissipation ? "D" : "Q") << ", t_end = " << t_end;
    }
  }
}

lagrangian::FloquetOptions floquet_over(double period) { return lagrangian_test::floquet_options(period); }

TEST(TextFloquet, KapitzaPendulumIsUprightStableAboveTheCriterionOnly) {
  // Upright (θ = π) is stable when a²Ω² > 2 g l = 19.62 m²/s²: Ω = 200 rad/s
  // gives 100, Ω = 60 rad/s 9.
  const text::TextModel fast(kapitza_text(200.0)), slow(kapitza_text(60.0));
  const lagrangian::FloquetResult r =
      text::floquet_multipliers(fast, start({M_PI}, {0.0}), floquet_over(2 * M_PI / 200));
  EXPECT_TRUE(r.stable) << "largest |mu| = " << r.largest_modulus;
  EXPECT_NEAR(r.monodromy.determinant(), 1.0, 1e-9);  // Hamiltonian: det Φ = 1
  for (const std::complex<double>& mu : r.multipliers) EXPECT_NEAR(std::abs(mu), 1.0, 1e-8);
  const lagrangian::FloquetResult u =
      text::floquet_multipliers(slow, start({M_PI}, {0.0}), floquet_over(2 * M_PI / 60));
  EXPECT_FALSE(u.stable);
  EXPECT_GT(u.largest_modulus, 1.01);
  // The same monodromy matrix as the C++ model's.
  lagrangian::State<1> upright;
  upright.q[0] = M_PI;
  const lagrangian::FloquetResult c = lagrangian::floquet_multipliers(lm::DrivenPendulum(1.0, 1.0, 0.05, 60.0, 9.81),
                                                                      upright, floquet_over(2 * M_PI / 60));
  EXPECT_LE((u.monodromy - c.monodromy).norm(), 1e-9 * c.monodromy.norm()) << u.monodromy << "\n" << c.monodromy;
}

TEST(TextSensitivity, OscillatorStateTransitionAndParametersFollowTheClosedForm) {
  // y″ = −ω² y, ω = √(k/m): Φ(t) = [[cos ωt, sin ωt / ω], [−ω sin ωt, cos ωt]];
  // y = y0 cos ωt + (v0/ω) sin ωt depends on k and m through ω, with
  // ∂ω/∂k = 1/(2mω) and ∂ω/∂m = −ω/(2m).
  text::Definition d;
  d.coordinates = {"y"};
  d.kinetic = "0.5*m*y_dot^2";
  d.potential = "0.5*k*y^2";
  d.parameters = {{"m", 2.0}, {"k", 8.0}};
  const text::TextModel model(d);
  lagrangian::SensitivityOptions o;
  o.run.t_end = 3.0;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  o.parameters = {"k", "m"};
  const double y0 = 0.3, v0 = 0.1, m = 2.0, w = 2.0, t = 3.0, c = std::cos(w * t), s = std::sin(w * t);
  const lagrangian::SensitivityResult r = text::sensitivities(model, start({y0}, {v0}), o);
  Eigen::Matrix<double, 2, 4> expected;
  expected.leftCols(2) << c, s / w, -w * s, c;
  const Eigen::Vector2d d_omega(-y0 * t * s - v0 / (w * w) * s + v0 / w * t * c,   // ∂y/∂ω
                                -y0 * s - y0 * w * t * c - v0 * t * s);             // ∂ẏ/∂ω
  expected.col(2) = d_omega / (2 * m * w);
  expected.col(3) = d_omega * (-w / (2 * m));
  ASSERT_EQ(r.parameters, (std::vector<std::string>{"k", "m"}));
  ASSERT_EQ(r.sensitivities.back().cols(), 4);
  EXPECT_LE((r.sensitivities.back() - expected).norm(), 1e-9) << r.sensitivities.back() << "\n" << expected;
  o.parameters = {"omega"};
  EXPECT_THROW((void)text::sensitivities(model, start({y0}, {v0}), o), lagrangian::OptionError);
}

TEST(TextSensitivity, DoublePendulumParameterColumnsAreTheBuiltInModels) {
  // The built-in model's columns are checked against differences of
  // simulate() (test_sensitivity); the text model's must be the same.
  const lm::DoublePendulum built_in(1.3, 0.8, 1.1, 0.7, 9.81);
  const text::TextModel model(lagrangian::testing::double_pendulum_text(built_in));
  lagrangian::SensitivityOptions o;
  o.run.t_end = 1.0;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  o.parameters = {"m1", "m2", "l1", "l2", "g"};
  lagrangian::State<2> s;
  s.q << 1.2, -0.4;
  s.qd << 0.3, 0.8;
  const lagrangian::SensitivityResult cpp = lagrangian::sensitivities(built_in, s, o);
  const lagrangian::SensitivityResult txt = text::sensitivities(model, start({1.2, -0.4}, {0.3, 0.8}), o);
  ASSERT_EQ(txt.sensitivities.back().cols(), 9);
  for (int col = 0; col < 9; ++col) {
    const Eigen::VectorXd a = txt.sensitivities.back().col(col), b = cpp.sensitivities.back().col(col);
    EXPECT_LE((a - b).norm(), 1e-9 * b.norm()) << "column " << col << ": " << a.transpose() << " / " << b.transpose();
  }
}

TEST(TextSensitivity, DragParameterEntersThroughDissipationAndForcesAlike) {
  // Linear drag b on m from (0, 0) at (u, v0), τ = m/b, E = e^(−t/τ):
  //   x = τu(1 − E),  y = τ(v0 + gτ)(1 − E) − gτt,  ẋ = uE,  ẏ = (v0 + gτ)E − gτ;
  // their derivatives in b (dτ/db = −τ/b, dE/db = −(t/m)E):
  const double m = 2.0, g = 9.81, b = 0.5, u = 14.0, v0 = 14.0, t = 1.5, tau = m / b, e = std::exp(-t / tau);
  Eigen::Vector4d expected;
  expected << -(m * u / (b * b)) * (1 - e) + (u * t / b) * e,
      (-tau / b) * ((v0 + 2 * g * tau) * (1 - e) - g * t) + tau * (v0 + g * tau) * (t / m) * e, -u * (t / m) * e,
      (-tau / b) * g * (e - 1) - (v0 + g * tau) * (t / m) * e;
  for (bool as_dissipation : {true, false}) {
    const text::TextModel model(linear_drag_text(as_dissipation));
    lagrangian::SensitivityOptions o;
    o.run.t_end = t;
    o.run.rtol = 1e-12;
    o.run.atol = 1e-14;
    o.initial_state = false;
    o.parameters = {"b"};
    const lagrangian::SensitivityResult r = text::sensitivities(model, start({0.0, 0.0}, {u, v0}), o);
    ASSERT_EQ(r.sensitivities.back().cols(), 1);
    const Eigen::Vector4d column = r.sensitivities.back().col(0);
    EXPECT_LE((column - expected).norm(), 1e-9 * expected.norm())
        << (as_dissipation ? "D" : "Q") << ": " << column.transpose() << " / " << expected.transpose();
  }
}

TEST(TextSensitivity, AParameterExponentKeepsTheOtherColumnsFinite) {
  // V = ½ k y^n with n = 2 a parameter, started at y < 0: the run folds y^2
  // into y·y; the column of k must be the oscillator's (∂ω/∂k = 1/(2mω)),
  // not NaN from y^n = exp(n log y).
  text::Definition d;
  d.coordinates = {"y"};
  d.kinetic = "0.5*m*y_dot^2";
  d.potential = "0.5*k*y^n";
  d.parameters = {{"m", 2.0}, {"k", 8.0}, {"n", 2.0}};
  const text::TextModel model(d);
  lagrangian::SensitivityOptions o;
  o.run.t_end = 3.0;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  o.initial_state = false;
  o.parameters = {"k"};
  const double y0 = -0.3, m = 2.0, w = 2.0, t = 3.0, c = std::cos(w * t), s = std::sin(w * t);
  const lagrangian::SensitivityResult r = text::sensitivities(model, start({y0}, {0.0}), o);
  const Eigen::Vector2d expected = Eigen::Vector2d(-y0 * t * s, -y0 * s - y0 * w * t * c) / (2 * m * w);
  EXPECT_LE((r.sensitivities.back().col(0) - expected).norm(), 1e-9) << r.sensitivities.back().transpose();
  // The exponent's own column, ∂(y^n)/∂n = y^n log y, has no value at y < 0:
  // the run stops there instead of returning NaN.
  o.parameters = {"n"};
  EXPECT_THROW((void)text::sensitivities(model, start({y0}, {0.0}), o), lagrangian::SimulationError);
}

template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const lagrangian::Error& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

// A ball on a tilted plane stated as text (its contact a gap expression)
// against the built-in BallAndPlane: the same impacts crossed by the same
// saltation matrices, Φ to 1e-9; and Liouville across impacts: the six
// exponents of a ball bouncing twice on a floor in 1 s sum to 4 ln e.
TEST(TextSaltation, BallOnAPlaneCrossesItsImpactsAsTheBuiltInModel) {
  const double e = 0.75, nx = 0.4 / std::sqrt(1.16), nz = 1.0 / std::sqrt(1.16);
  text::Definition d;
  d.coordinates = {"x", "y", "z"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2 + z_dot^2)";
  d.potential = "m*g*z";
  d.contacts = {{"plane", "nx*x + nz*z - R", e, "m"}};
  d.parameters = {{"m", 1.0}, {"g", 9.81}, {"R", 0.1}, {"nx", nx}, {"nz", nz}};
  const text::TextModel ball(d);
  const lm::BallAndPlane builtin(1.0, 0.1, e, 9.81, {0.4, 0.0, 1.0}, 0.0);
  lagrangian::State<3> s;
  s.q << 0.3, 0.1, 1.2;
  s.qd << -0.5, 0.2, 0.4;
  lagrangian::SensitivityOptions o;
  o.run.t_end = 1.4;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  const lagrangian::SensitivityResult got = text::sensitivities(ball, start({0.3, 0.1, 1.2}, {-0.5, 0.2, 0.4}), o);
  const lagrangian::SensitivityResult want = lagrangian::sensitivities(builtin, s, o);
  EXPECT_EQ(got.impacts, 2);
  EXPECT_EQ(want.impacts, 2);
  EXPECT_LE((got.sensitivities.back() - want.sensitivities.back()).cwiseAbs().maxCoeff(), 1e-9)
      << got.sensitivities.back() << "\n\n"
      << want.sensitivities.back();

  d.contacts = {{"floor", "z - R", 0.5, "m"}};
  const text::TextModel dropped(d);
  lagrangian::LyapunovOptions l = lyapunov_over(1.0);
  const lagrangian::LyapunovResult r = text::lyapunov_spectrum(dropped, start({0.0, 0.0, 1.1}, {0.3, 0.0, 0.0}), l);
  EXPECT_EQ(r.impacts, 2);
  EXPECT_NEAR(r.sum, 4 * std::log(0.5), 1e-8);
}

// The tilted-plane ball as text with e = 0.5: its bounces accumulate, the
// Zeno rule rests it at t∞ ≈ 1.5 s (the gap held as a holonomic row of the
// text model, FixedSizeModel::hold()) and it slides down the plane. Along
// the frictionless plane it falls freely whatever the bounces, and every
// start comes to rest on it: at 2.2 s Φ = [[P, t P], [0, P]], P = I − n̂n̂ᵀ.
TEST(TextSaltation, BallComingToRestOnAPlaneHasTheClosedFormFlow) {
  const double nx = 0.4 / std::sqrt(1.16), nz = 1.0 / std::sqrt(1.16), t = 2.2;
  text::Definition d;
  d.coordinates = {"x", "y", "z"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2 + z_dot^2)";
  d.potential = "m*g*z";
  d.contacts = {{"plane", "nx*x + nz*z - R", 0.5, "m"}};
  d.parameters = {{"m", 1.0}, {"g", 9.81}, {"R", 0.1}, {"nx", nx}, {"nz", nz}};
  lagrangian::SensitivityOptions o;
  o.run.t_end = t;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  const lagrangian::SensitivityResult r =
      text::sensitivities(text::TextModel(d), start({0.3, 0.1, 1.2}, {-0.5, 0.2, 0.4}), o);
  const Eigen::MatrixXd expected = lagrangian_test::flow_sliding_on_a_plane(Eigen::Vector3d(nx, 0.0, nz), t);
  EXPECT_LE((r.sensitivities.back() - expected).cwiseAbs().maxCoeff(), 1e-9) << r.sensitivities.back();
  EXPECT_GT(r.impacts, 10);
  const Eigen::VectorXd& x = r.states.back();
  EXPECT_NEAR(nx * x[0] + nz * x[2], 0.1, 1e-9);
  EXPECT_NEAR(nx * x[3] + nz * x[5], 0.0, 1e-9);
  const lagrangian::LyapunovResult l = text::lyapunov_spectrum(text::TextModel(d), start({0.3, 0.1, 1.2}, {-0.5, 0.2, 0.4}), lyapunov_over(t));
  EXPECT_EQ(l.rests, 1);
  EXPECT_EQ(std::count(l.spectrum.begin(), l.spectrum.end(), -HUGE_VAL), 2);

  // Its parameter columns through the bounces and the rest (the seeded
  // twins hold the gap as the model does): the state at 2.2 s is the closed
  // form of tests/plane_slide.hpp on the plane nx x + nz z = R, whatever m;
  // its derivatives in g, R, nx and nz by central differences of it, 0 in m.
  o.parameters = {"m", "g", "R", "nx", "nz"};
  const Eigen::Vector3d r0(0.3, 0.1, 1.2), v0(-0.5, 0.2, 0.4);
  const lagrangian::SensitivityResult p =
      text::sensitivities(text::TextModel(d), start({0.3, 0.1, 1.2}, {-0.5, 0.2, 0.4}), o);
  ASSERT_EQ(p.sensitivities.back().cols(), 6 + 5);
  const auto closed_form = [&](std::array<double, 5> v) {  // (m, g, R, nx, nz)
    return lagrangian_test::state_sliding_on_a_plane(r0, v0, Eigen::Vector3d(v[3], 0.0, v[4]), v[2], v[1], t);
  };
  const std::array<double, 5> at = {1.0, 9.81, 0.1, nx, nz};
  const Eigen::MatrixXd columns = lagrangian_test::central_differences(closed_form, at);
  for (int j = 0; j < 5; ++j) {
    const Eigen::VectorXd expected = columns.col(j), got = p.sensitivities.back().col(6 + j);
    EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), 1e-8) << o.parameters[static_cast<std::size_t>(j)] << "\n"
                                                              << got.transpose() << "\n"
                                                              << expected.transpose();
  }
  EXPECT_GT(p.sensitivities.back().col(6 + 1).cwiseAbs().maxCoeff(), 0.5);
}

// A ball on a spring (k = 20 N/m, rest length 0.5 m, anchored 1 m above the
// floor) as text, e = 0: it lands where the spring's pull is below m g,
// rests (the gap a held row), slides out and lifts off where its
// multiplier, from the held rows and the free motion, falls through 0;
// Φ(1 s), in the air, against central differences of simulate() on the
// same text model (step 1e-6).
TEST(TextSaltation, BallLiftingOffAFloorMatchesCentralDifferences) {
  text::Definition d;
  d.coordinates = {"x", "y", "z"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2 + z_dot^2)";
  d.potential = "m*g*z + 0.5*k*(sqrt(x^2 + y^2 + (z - H)^2) - L)^2";
  d.contacts = {{"floor", "z - R", 0.0, "m"}};
  d.parameters = {{"m", 1.0}, {"g", 9.81}, {"R", 0.1}, {"k", 20.0}, {"H", 1.0}, {"L", 0.5}};
  const text::TextModel ball(d);
  const auto s = start({-0.5, 0.05, 0.3}, {2.0, 0.4, 0.0});
  lagrangian::SensitivityOptions o;
  o.run.t_end = 1.0;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  const lagrangian::SensitivityResult r = text::sensitivities(ball, s, o);
  const lagrangian::LyapunovResult l = text::lyapunov_spectrum(ball, s, lyapunov_over(1.0));
  EXPECT_EQ(l.rests, 1);
  EXPECT_EQ(l.releases, 1);
  EXPECT_GT(l.q_final[2], 0.1 + 1e-3);
  const Eigen::MatrixXd& phi = r.sensitivities.back();
  const auto final_state = [&](int j, double shift) {
    lagrangian::State<lagrangian::Dynamic> moved = s;
    (j < 3 ? moved.q : moved.qd)[j % 3] += shift;
    return lagrangian::testing::final_state(ball, moved, o.run);
  };
  double worst = 0;
  for (int j = 0; j < 6; ++j) {
    const Eigen::VectorXd fd = (final_state(j, 1e-6) - final_state(j, -1e-6)) / 2e-6;
    worst = std::max(worst, (fd - phi.col(j)).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(worst, 1e-6 * phi.cwiseAbs().maxCoeff()) << phi;

  // The columns of k, H and g across the landing, the rest and the lift-off
  // (where λ = 0 and both motions' rates agree: no jump), against central
  // differences of simulate() with each parameter moved by ±1e-6 of itself.
  o.parameters = {"k", "H", "g"};
  const lagrangian::SensitivityResult pr = text::sensitivities(ball, s, o);
  const Eigen::MatrixXd& columns = pr.sensitivities.back();
  ASSERT_EQ(columns.cols(), 6 + 3);
  const std::array<double, 3> values = {20.0, 1.0, 9.81};
  for (int j = 0; j < 3; ++j) {
    const std::string& name = o.parameters[static_cast<std::size_t>(j)];
    const double value = values[static_cast<std::size_t>(j)], h = 1e-6 * value;
    const Eigen::VectorXd fd =
        (final_state_with(d, name, value + h, s, o.run) - final_state_with(d, name, value - h, s, o.run)) / (2 * h);
    EXPECT_LE((fd - columns.col(6 + j)).cwiseAbs().maxCoeff(), 1e-6 * columns.col(6 + j).cwiseAbs().maxCoeff())
        << name << "\n"
        << fd.transpose() << "\n"
        << columns.col(6 + j).transpose();
    EXPECT_GT(columns.col(6 + j).cwiseAbs().maxCoeff(), 1e-2) << name;
  }
}

/// A disc (m = 1 kg, r = 0.1 m) in a box 2 m × 1 m as text, every wall
/// with e = 0.8, the right wall's gap `right` (the test's choice of wall).
text::Definition disc_in_a_box_text(const std::string& right) {
  text::Definition d;
  d.coordinates = {"x", "y"};
  d.units = {"m", "m"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2)";
  d.potential = "m*g*y";
  d.contacts = {{"floor", "y - r", 0.8, "m"},
                {"left", "x - r", 0.8, "m"},
                {"right", right, 0.8, "m"},
                {"ceiling", "H - r - y", 0.8, "m"}};
  d.parameters = {{"m", 1.0}, {"g", 9.81}, {"r", 0.1}, {"W", 2.0}, {"H", 1.0}};
  return d;
}

/// The disc's four exponents: y's pair removed at a rest (−∞), x's two
/// summing to `sum` (1/s) to 1e-8.
void expect_two_removed_and_sum(const std::vector<double>& spectrum, double sum) {
  ASSERT_EQ(spectrum.size(), 4u);
  EXPECT_EQ(std::count(spectrum.begin(), spectrum.end(), -HUGE_VAL), 2);
  double finite = 0;
  for (const double lambda : spectrum)
    if (std::isfinite(lambda)) finite += lambda;
  EXPECT_NEAR(finite, sum, 1e-8);
}

// The disc of Saltation.DiscAtRestOnTheFloorBouncesOffAWallAsTheClosedForm
// (test_saltation.cpp; there SpheresInBox) stated as text. Dropped from
// y = 0.6 m moving at 0.3 m/s, it bounces to rest on the floor by the Zeno
// rule at √(2h/g) (1 + e)/(1 − e) = 2.87 s (h = 0.5 m), held there as a
// row of the text model, and slides into the right wall at x = W − r =
// 1.9 m at 4.67 s. The wall's law is the closing contact's alone, the
// floor opened for it (its held row would otherwise be a row of the law);
// the wall's impulse, along x, leaves the floor's rate alone, so the impact
// is crossed with the disc still held on the floor. Along x,
// x(t) = (W − r)(1 + e) − e x0 − e ẋ0 t after it, ẋ = −e ẋ0; y = r and
// ẏ = 0 whatever the start: at 5.5 s, in (x, y, ẋ, ẏ),
//   ∂x/∂x0 = −e, ∂x/∂ẋ0 = −e t, ∂ẋ/∂ẋ0 = −e, every other entry 0,
// and the parameters' columns ∂x/∂W = 1 + e, ∂x/∂r = −(1 + e),
// ∂y/∂r = 1; g, H and m: 0.
TEST(TextSaltation, DiscAtRestOnTheFloorBouncesOffAWallAsTheClosedForm) {
  const text::TextModel box(disc_in_a_box_text("W - r - x"));
  const auto s = start({0.5, 0.6}, {0.3, 0.0});
  const double t = 5.5, e = 0.8, reach = 1.9, x0 = 0.5, v0 = 0.3;
  const lagrangian::SensitivityResult r =
      text::sensitivities(box, s, lagrangian_test::sensitivity_options(t, {"W", "r", "g", "H", "m"}));
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(4, 9);
  expected(0, 0) = -e;
  expected(0, 2) = -e * t;
  expected(2, 2) = -e;
  expected(0, 4) = 1 + e;
  expected(0, 5) = -(1 + e);
  expected(1, 5) = 1.0;
  const Eigen::MatrixXd& got = r.sensitivities.back();
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-9) << got;
  EXPECT_NEAR(r.states.back()[0], reach * (1 + e) - e * x0 - e * v0 * t, 1e-9);
  EXPECT_NEAR(r.states.back()[1], 0.1, 1e-9);
  const lagrangian::LyapunovResult l = text::lyapunov_spectrum(box, s, lagrangian_test::lyapunov_options(t));
  EXPECT_EQ(l.rests, 1);
  EXPECT_EQ(l.releases, 0);
  EXPECT_GT(l.impacts, 20);
  // Along x the flow is Φ_x above, det Φ_x = e², so the two finite
  // exponents sum to 2 ln e / t; y's pair was removed at the rest (−∞).
  expect_two_removed_and_sum(l.spectrum, 2 * std::log(e) / t);
}

// The same disc against a right wall leaning back, gap
// φ = W − r − x + 0.3 (y − r), ∇φ = (−1, 0.3), reached where the floor holds
// the disc (y = r) at the same place and time t_w = (1.9 − x0)/ẋ0. The
// wall's law alone (e = 0.8, approach rate −ẋ0):
//   q̇⁺ = q̇ + Λ ∇φ / m,  Λ = (1 + e) m ẋ0 / |∇φ|²,
// so ẋ⁺ = c ẋ0 with c = 1 − (1 + e)/1.09 and ẏ⁺ = 0.3 (1 + e) ẋ0 / 1.09
// = 0.149 m/s: the impulse lifts the disc off the floor, which a plain run
// releases, and so does the tangent run. The disc bounces back to rest by
// the Zeno rule about 0.15 s later; the floor does not act along x, so
// x(t) = 1.9 + c ẋ0 (t − t_w) = 1.9 + c ẋ0 t − c (W − r − x0): at 5.5 s,
//   ∂x/∂x0 = c, ∂x/∂ẋ0 = c t, ∂ẋ/∂ẋ0 = c, every other entry 0,
// ∂x/∂W = 1 − c, ∂x/∂r = −(1 − c), ∂y/∂r = 1; g, H and m: 0. The two
// finite exponents sum to ln(det Φ_x)/t = 2 ln|c| / t.
TEST(TextSaltation, DiscLiftedOffTheFloorByAWallAsTheClosedForm) {
  const text::TextModel box(disc_in_a_box_text("W - r - x + 0.3*(y - r)"));
  const auto s = start({0.5, 0.6}, {0.3, 0.0});
  const double t = 5.5, c = 1 - 1.8 / 1.09, x0 = 0.5, v0 = 0.3;
  const lagrangian::SensitivityResult r =
      text::sensitivities(box, s, lagrangian_test::sensitivity_options(t, {"W", "r", "g", "H", "m"}));
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(4, 9);
  expected(0, 0) = c;
  expected(0, 2) = c * t;
  expected(2, 2) = c;
  expected(0, 4) = 1 - c;
  expected(0, 5) = -(1 - c);
  expected(1, 5) = 1.0;
  const Eigen::MatrixXd& got = r.sensitivities.back();
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-9) << got;
  EXPECT_NEAR(r.states.back()[0], 1.9 + c * v0 * t - c * (1.9 - x0), 1e-9);
  EXPECT_NEAR(r.states.back()[1], 0.1, 1e-9);
  const lagrangian::LyapunovResult l = text::lyapunov_spectrum(box, s, lagrangian_test::lyapunov_options(t));
  EXPECT_EQ(l.rests, 2);
  EXPECT_EQ(l.releases, 1);
  expect_two_removed_and_sum(l.spectrum, 2 * std::log(std::abs(c)) / t);
}

// The wall leaning the other way, gap W − r − x − 0.3 (y − r): its impulse
// presses the disc into the floor it rests on (a plain run resolves a floor
// impact at the same instant: impacts in sequence), which the tangent flow
// does not derive: the run stops at the wall, naming both contacts.
TEST(TextSaltation, ImpulseThatPressesARestingContactIsRefused) {
  const text::TextModel box(disc_in_a_box_text("W - r - x - 0.3*(y - r)"));
  try {
    (void)text::lyapunov_spectrum(box, start({0.5, 0.6}, {0.3, 0.0}), lagrangian_test::lyapunov_options(5.5));
    ADD_FAILURE() << "an impact that moves a resting contact was crossed";
  } catch (const lagrangian::SimulationError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("the impulse of contact 'right' sets resting contact 'floor' moving (its rate changes by "
                        "-0.148624; a plain run resolves it as another impact at the same instant)"),
              std::string::npos)
        << error.what();
    EXPECT_NEAR(error.time(), (1.9 - 0.5) / 0.3, 1e-6);
  }
}

// Gaps that move with t and with the coordinates, as text and in C++
// (tests/contact_models.hpp): a ball on a table moving as 0.05 sin 10t m
// (three bounces in 1 s) and the double pendulum against a wall at
// x = 0.9 m (one impact in 1.5 s). ∂q̇⁺/∂q, R_t and the gap's γ all enter
// the saltation matrices here, on the interpreter's nested numbers.
TEST(TextSaltation, MovingAndTurningGapsCrossAsTheCppModels) {
  lagrangian::SensitivityOptions o;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  {
    text::Definition d;
    d.coordinates = {"z"};
    d.kinetic = "0.5*z_dot^2";
    d.potential = "g*z";
    d.contacts = {{"table", "z - A*sin(w*t)", 0.8, "m"}};
    d.parameters = {{"g", 9.81}, {"A", 0.05}, {"w", 10.0}};
    o.run.t_end = 1.0;
    lagrangian::State<1> s;
    s.q[0] = 0.3;
    const lagrangian::SensitivityResult got = text::sensitivities(text::TextModel(d), start({0.3}, {0.0}), o);
    const lagrangian::SensitivityResult want = lagrangian::sensitivities(lagrangian::testing::BouncingBall<>(), s, o);
    EXPECT_EQ(got.impacts, 3);
    EXPECT_EQ(want.impacts, 3);
    EXPECT_LE((got.sensitivities.back() - want.sensitivities.back()).cwiseAbs().maxCoeff(), 1e-8)
        << got.sensitivities.back() << "\n\n"
        << want.sensitivities.back();
    // The parameters' columns cross the same impacts: the gap moves with A
    // and w (test_impact_sensitivity holds the C++ model's columns against
    // central differences of simulate()).
    lagrangian::SensitivityOptions p = o;
    p.initial_state = false;
    p.parameters = {"g", "A", "w"};
    const lagrangian::SensitivityResult got_p = text::sensitivities(text::TextModel(d), start({0.3}, {0.0}), p);
    p.parameters = {"g", "amplitude", "omega"};
    const lagrangian::SensitivityResult want_p =
        lagrangian::sensitivities(lagrangian::testing::BouncingBall<>(), s, p);
    ASSERT_EQ(got_p.sensitivities.back().cols(), 3);
    EXPECT_GT(want_p.sensitivities.back().cwiseAbs().minCoeff(), 1e-3) << want_p.sensitivities.back();
    EXPECT_LE((got_p.sensitivities.back() - want_p.sensitivities.back()).cwiseAbs().maxCoeff(), 1e-8)
        << got_p.sensitivities.back() << "\n\n"
        << want_p.sensitivities.back();
  }
  {
    text::Definition d = lagrangian::testing::double_pendulum_text(lm::DoublePendulum());
    d.contacts = {{"wall", "0.9 - (l1*sin(th1) + l2*sin(th2))", 0.9, "m"}};
    o.run.t_end = 1.5;
    lagrangian::State<2> s;
    s.q << 0.2, 0.2;
    s.qd << 1.0, 1.5;
    const lagrangian::SensitivityResult got =
        text::sensitivities(text::TextModel(d), start({0.2, 0.2}, {1.0, 1.5}), o);
    const lagrangian::SensitivityResult want =
        lagrangian::sensitivities(lagrangian::testing::DoublePendulumAgainstWall(), s, o);
    EXPECT_EQ(got.impacts, 1);
    EXPECT_EQ(want.impacts, 1);
    EXPECT_LE((got.sensitivities.back() - want.sensitivities.back()).cwiseAbs().maxCoeff(), 1e-8)
        << got.sensitivities.back() << "\n\n"
        << want.sensitivities.back();
  }
}

// Constrained models as text: the C++ models of models/constrained.hpp
// written out. The double pendulum in Cartesian coordinates held by two
// rods (holonomic), a knife edge that cannot slip sideways (Pfaffian), a
// bead on a horizontal wire spinning at ω (holonomic, depending on t).
text::Definition cartesian_double_pendulum_text(const lm::CartesianDoublePendulum& p) {
  text::Definition d;
  d.coordinates = {"x1", "y1", "x2", "y2"};
  d.kinetic = "0.5*m1*(x1_dot^2 + y1_dot^2) + 0.5*m2*(x2_dot^2 + y2_dot^2)";
  d.potential = "m1*g*y1 + m2*g*y2";
  d.holonomic = {"sqrt(x1^2 + y1^2) - l1", "sqrt((x2 - x1)^2 + (y2 - y1)^2) - l2"};
  d.parameters = {{"m1", p.m1}, {"m2", p.m2}, {"l1", p.l1}, {"l2", p.l2}, {"g", p.g}};
  return d;
}

text::Definition knife_edge_text(double m, double inertia) {
  text::Definition d;
  d.coordinates = {"x", "y", "phi"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2) + 0.5*I*phi_dot^2";
  d.potential = "0";
  d.pfaffian = {"x_dot*sin(phi) - y_dot*cos(phi)"};
  d.parameters = {{"m", m}, {"I", inertia}};
  return d;
}

text::Definition spinning_wire_text(double m, double omega) {
  text::Definition d;
  d.coordinates = {"x", "y"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2)";
  d.potential = "0";
  d.holonomic = {"x*sin(omega*t) - y*cos(omega*t)"};
  d.parameters = {{"m", m}, {"omega", omega}};
  return d;
}

/// J = ∂q̈/∂(q, q̇) of the text model (text::state_jacobian(): the
/// library's passes at its size) and of the C++ model
/// at (q, q̇, t), and their q̈: equal to rounding (relative to |J|).
template <int N, class M>
void expect_same_jacobian(const text::TextModel& model, const M& cpp, const Vec<double, N>& q, const Vec<double, N>& qd,
                          double t) {
  Eigen::VectorXd a_text;
  Eigen::MatrixXd j_text;
  Vec<double, N> a_cpp;
  Eigen::Matrix<double, N, 2 * N> j_cpp;
  text::state_jacobian(model, q, qd, t, a_text, j_text);
  lagrangian::state_jacobian(cpp, q, qd, t, a_cpp, j_cpp);
  EXPECT_LE((a_text - a_cpp).norm(), 1e-13 * (1 + a_cpp.norm())) << a_text.transpose() << "\n" << a_cpp.transpose();
  EXPECT_LE((j_text - j_cpp).norm(), 1e-13 * (1 + j_cpp.norm())) << "text:\n" << j_text << "\nC++:\n" << j_cpp;
}

TEST(TextConstrainedTangent, JacobiansAreTheCppModels) {
  const lm::CartesianDoublePendulum rods(1.3, 0.7, 1.0, 0.8, 9.81);
  const text::TextModel rods_text(cartesian_double_pendulum_text(rods));
  // On the rods (θ = (0.4, −1.1) rad, θ̇ = (1.7, −0.6) rad/s) and off them.
  const double s1 = std::sin(0.4), c1 = std::cos(0.4), s2 = std::sin(-1.1), c2 = std::cos(-1.1);
  const Vec<double, 4> q(s1, -c1, s1 + 0.8 * s2, -c1 - 0.8 * c2);
  const Vec<double, 4> qd(1.7 * c1, 1.7 * s1, 1.7 * c1 - 0.6 * 0.8 * c2, 1.7 * s1 - 0.6 * 0.8 * s2);
  expect_same_jacobian<4>(rods_text, rods, q, qd, 0.0);
  expect_same_jacobian<4>(rods_text, rods, Vec<double, 4>(0.3, -0.9, 0.9, -1.2), Vec<double, 4>(0.5, 0.1, -0.2, 0.7),
                          0.0);

  const lm::KnifeEdge knife(1.7, 0.3);
  const text::TextModel knife_text(knife_edge_text(1.7, 0.3));
  expect_same_jacobian<3>(knife_text, knife, Vec<double, 3>(0.4, -0.2, 0.3), Vec<double, 3>(1.2, -0.4, 0.9), 0.0);
  expect_same_jacobian<3>(knife_text, knife, Vec<double, 3>(0.4, -0.2, 2.1), Vec<double, 3>(-0.5, 0.8, -1.3), 0.0);

  const lm::BeadOnRotatingWire bead(0.8, 1.5, 10.0);
  const text::TextModel bead_text(spinning_wire_text(0.8, 1.5));
  expect_same_jacobian<2>(bead_text, bead, Vec<double, 2>(0.3, 0.2), Vec<double, 2>(0.1, -0.4), 0.7);
}

// A skate on a ramp: a holonomic row g = z − s x and a Pfaffian one (no
// sideslip, φ_a = ẋ sin φ − ẏ cos φ), written here in C++ and as text.
// The manifold's rows are h = (g, ġ, φ_a) (the holonomic rows, their rates,
// then the Pfaffian rows), of gradients in (q, q̇), q = (x, y, z, φ):
//   ∇g = (−s, 0, 1, 0; 0), ∇ġ = (0; −s, 0, 1, 0),
//   ∇φ_a = (0, 0, 0, ẋ cos φ + ẏ sin φ; sin φ, −cos φ, 0, 0).
// J agrees with the C++ model's; the sensitivities Φ(t) P0 have rank
// d = 8 − 3 = 5, P0 maps each gradient at the start to 0, and the flow
// keeps tangent vectors tangent: ∇h(x(t))ᵀ Φ(t) P0 = 0.
struct SkateOnRamp {
  static constexpr int coordinate_count = 4;
  double m = 1.3, I = 0.2, g = 9.81, s = 0.5;
  std::string name() const { return "skate_on_ramp"; }
  template <class S>
  S kinetic(const Vec<S, 4>&, const Vec<S, 4>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1] + qd[2] * qd[2]) + 0.5 * I * qd[3] * qd[3];
  }
  template <class S>
  S potential(const Vec<S, 4>& q, const S&) const {
    return m * g * q[2];
  }
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 4>& q, const S&) const {
    return Vec<S, 1>(q[2] - s * q[0]);
  }
  template <class S>
  Vec<S, 1> pfaffian(const Vec<S, 4>& q, const Vec<S, 4>& qd, const S&) const {
    using std::cos;
    using std::sin;
    return Vec<S, 1>(qd[0] * sin(q[3]) - qd[1] * cos(q[3]));
  }
};

text::Definition skate_on_ramp_text() {
  text::Definition d;
  d.coordinates = {"x", "y", "z", "phi"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2 + z_dot^2) + 0.5*I*phi_dot^2";
  d.potential = "m*g*z";
  d.holonomic = {"z - s*x"};
  d.pfaffian = {"x_dot*sin(phi) - y_dot*cos(phi)"};
  d.parameters = {{"m", 1.3}, {"I", 0.2}, {"g", 9.81}, {"s", 0.5}};
  return d;
}

/// The gradients of the skate's rows h = (g, ġ, φ_a) at the state x, as rows.
Eigen::Matrix<double, 3, 8> skate_row_gradients(const Eigen::VectorXd& x, double slope) {
  Eigen::Matrix<double, 3, 8> h = Eigen::Matrix<double, 3, 8>::Zero();
  h(0, 0) = -slope;
  h(0, 2) = 1.0;
  h(1, 4) = -slope;
  h(1, 6) = 1.0;
  const double phi = x[3], xd = x[4], yd = x[5];
  h(2, 3) = xd * std::cos(phi) + yd * std::sin(phi);
  h(2, 4) = std::sin(phi);
  h(2, 5) = -std::cos(phi);
  return h;
}

TEST(TextConstrainedSensitivity, HolonomicAndPfaffianRowsKeepToTheManifold) {
  const SkateOnRamp cpp;
  const text::TextModel skate(skate_on_ramp_text());
  const double phi = 0.3, u = 1.1, x = 0.2;
  const Vec<double, 4> q(x, -0.1, 0.5 * x, phi), qd(u * std::cos(phi), u * std::sin(phi), 0.5 * u * std::cos(phi), 0.4);
  expect_same_jacobian<4>(skate, cpp, q, qd, 0.0);
  lagrangian::SensitivityOptions o;
  o.run = lagrangian_test::lyapunov_options(2.0, 1e-12).run;
  o.run.output_interval = 1.0;
  const lagrangian::SensitivityResult r =
      text::sensitivities(skate, start({q[0], q[1], q[2], q[3]}, {qd[0], qd[1], qd[2], qd[3]}), o);
  ASSERT_EQ(r.times.size(), 3u);
  EXPECT_EQ(r.state_columns, 8);
  const Eigen::MatrixXd& p0 = r.sensitivities.front();
  EXPECT_NEAR(p0.trace(), 5.0, 1e-12);  // an orthogonal projector of rank d = 5
  EXPECT_LE((p0 * p0 - p0).norm(), 1e-12);
  EXPECT_LE((p0 * skate_row_gradients(r.states.front(), 0.5).transpose()).norm(), 1e-12);
  for (std::size_t i = 1; i < r.times.size(); ++i) {
    const Eigen::MatrixXd& s = r.sensitivities[i];
    EXPECT_LE((skate_row_gradients(r.states[i], 0.5) * s).norm(), 1e-8 * s.norm()) << "t = " << r.times[i];
    EXPECT_GT(s.norm(), 1.0);
  }

  // A state off both rows, projected: on the ramp, ġ = 0 and no sideslip.
  const text::FixedSizeModel<4> fixed(skate);
  double qp[4] = {0.3, 0.1, 0.4, 0.7}, qdp[4] = {0.5, -0.2, 0.9, 0.1};
  fixed.project_state(qp, qdp, 0.0);
  EXPECT_NEAR(qp[2] - 0.5 * qp[0], 0.0, 1e-12);
  EXPECT_NEAR(qdp[2] - 0.5 * qdp[0], 0.0, 1e-12);
  EXPECT_NEAR(qdp[0] * std::sin(qp[3]) - qdp[1] * std::cos(qp[3]), 0.0, 1e-12);
}

// The bead on the wire spinning at ω = 1 rad/s, as the C++ model's test
// (test_constrained_tangent.cpp) states it: in the wire's frame r̈ = ω² r,
// so the two exponents on the manifold sum to 0 and T λ₁(T) grows by
// ω (T₂ − T₁) between T₁ and T₂.
TEST(TextConstrainedLyapunov, BeadOnASpinningWireClosedForm) {
  const double omega = 1.0;
  const text::TextModel bead(spinning_wire_text(0.8, omega));
  const auto s = start({0.1, 0.0}, {0.05, omega * 0.1});
  const double t1 = 10, t2 = 20;
  const lagrangian::LyapunovResult a = text::lyapunov_spectrum(bead, s, lagrangian_test::lyapunov_options(t1));
  const lagrangian::LyapunovResult b = text::lyapunov_spectrum(bead, s, lagrangian_test::lyapunov_options(t2));
  ASSERT_EQ(b.spectrum.size(), 2u);
  EXPECT_NEAR(a.sum, 0.0, 1e-8);
  EXPECT_NEAR(b.sum, 0.0, 1e-8);
  EXPECT_NEAR((t2 * b.spectrum[0] - t1 * a.spectrum[0]) / (t2 - t1), omega, 1e-6);
  EXPECT_NEAR((t2 * b.spectrum[1] - t1 * a.spectrum[1]) / (t2 - t1), -omega, 1e-6);
  const double r = 0.1 * std::cosh(omega * t2) + 0.05 / omega * std::sinh(omega * t2);
  EXPECT_NEAR(std::hypot(b.q_final[0], b.q_final[1]) / r, 1.0, 1e-8);
}

// The knife edge from 1 m/s turning at 0.5 rad/s: five exponents (three
// coordinates, one Pfaffian row), summing to 0, none growing faster than
// polynomially (test_constrained_tangent.cpp gives the reasons); the speed
// stays 1 m/s without sideslip.
TEST(TextConstrainedLyapunov, KnifeEdgeHasFiveExponentsThatVanish) {
  const text::TextModel knife(knife_edge_text(1.0, 0.1));
  const lagrangian::LyapunovResult r =
      text::lyapunov_spectrum(knife, start({0, 0, 0}, {1.0, 0.0, 0.5}), lagrangian_test::lyapunov_options(50.0));
  ASSERT_EQ(r.spectrum.size(), 5u);
  EXPECT_NEAR(r.sum, 0.0, 1e-8);
  for (double l : r.spectrum) EXPECT_LE(50.0 * std::abs(l), 2 * std::log(50.0));
  EXPECT_NEAR(std::hypot(r.qd_final[0], r.qd_final[1]), 1.0, 1e-9);
  EXPECT_NEAR(r.qd_final[0] * std::sin(r.q_final[2]) - r.qd_final[1] * std::cos(r.q_final[2]), 0.0, 1e-9);
}

// The Atwood machine of examples/scenes/text/atwood_machine.toml (3 and
// 1 kg, y1 + y2 = c) falls with a uniform acceleration, so its
// sensitivities on the manifold are [[P, t P], [0, P]] at every sample,
// P = ½ [[1, −1], [−1, 1]] (test_constrained_tangent.cpp), and its
// parameters' columns are those of the C++ model's test: ∂y1/∂p = ½ t² ∂a/∂p,
// ∂y2/∂p = −∂y1/∂p, a = −(m1 − m2) g/(m1 + m2). The string's constant c
// moves the manifold past the start: refused, naming it.
TEST(TextConstrainedSensitivity, AtwoodMachineClosedFormAndParameterRefusal) {
  text::Definition d;
  d.coordinates = {"y1", "y2"};
  d.kinetic = "0.5*m1*y1_dot^2 + 0.5*m2*y2_dot^2";
  d.potential = "m1*g*y1 + m2*g*y2";
  d.holonomic = {"y1 + y2 - c"};
  d.parameters = {{"m1", 3.0}, {"m2", 1.0}, {"g", 9.81}, {"c", 1.0}};
  const text::TextModel atwood(d);
  lagrangian::SensitivityOptions o;
  o.run = lagrangian_test::lyapunov_options(0.5, 1e-12).run;
  o.run.output_interval = 0.125;
  const lagrangian::SensitivityResult r = text::sensitivities(atwood, start({0.7, 0.3}, {0.3, -0.3}), o);
  ASSERT_EQ(r.times.size(), 5u);
  EXPECT_EQ(r.state_columns, 4);
  Eigen::Matrix2d p;
  p << 0.5, -0.5, -0.5, 0.5;
  for (std::size_t i = 0; i < r.times.size(); ++i) {
    Eigen::Matrix4d expected = Eigen::Matrix4d::Zero();
    expected.topLeftCorner<2, 2>() = p;
    expected.topRightCorner<2, 2>() = r.times[i] * p;
    expected.bottomRightCorner<2, 2>() = p;
    EXPECT_LE((r.sensitivities[i] - expected).norm(), 1e-10) << "t = " << r.times[i] << "\n" << r.sensitivities[i];
  }
  const double a = -(3.0 - 1.0) * 9.81 / 4.0, t = r.times.back();
  EXPECT_NEAR(r.states.back()[0], 0.7 + 0.3 * t + 0.5 * a * t * t, 1e-10);

  o.parameters = {"m1", "m2", "g"};
  const lagrangian::SensitivityResult rp = text::sensitivities(atwood, start({0.7, 0.3}, {0.3, -0.3}), o);
  const double da[3] = {-2 * 1.0 * 9.81 / 16.0, 2 * 3.0 * 9.81 / 16.0, -2.0 / 4.0};
  double worst = 0;
  for (std::size_t i = 0; i < rp.times.size(); ++i) {
    const double ti = rp.times[i];
    ASSERT_EQ(rp.sensitivities[i].cols(), 4 + 3);
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector4d expected(0.5 * ti * ti * da[j], -0.5 * ti * ti * da[j], ti * da[j], -ti * da[j]);
      worst = std::max(worst, (rp.sensitivities[i].col(4 + j) - expected).norm());
      EXPECT_LE((rp.sensitivities[i].col(4 + j) - expected).norm(), 1e-10)
          << "d/d" << rp.parameters[static_cast<std::size_t>(j)] << " at t = " << ti;
    }
  }
  std::printf("Atwood machine (text), columns of m1, m2, g against the closed form: %.1e\n", worst);
  o.parameters = {"c"};
  EXPECT_EQ(message_of([&] { (void)text::sensitivities(atwood, start({0.7, 0.3}, {0.3, -0.3}), o); }),
            "sensitivity: parameter 'c' moves the constraint manifold past the start: d(g0)/dc = -1 there, so the "
            "start would leave the constraints when c changes; ask for other parameters, or start where the "
            "constraints do not depend on it");
}

// A bead sent from the centre of a wire spinning at ω (the row
// x sin ωt − y cos ωt = 0 depends on ω and t): r̈ = ω² r from r(0) = 0,
// ṙ(0) = v, so r = (v/ω) sinh ωt, x = r cos ωt, y = r sin ωt. The start is
// on the wire for every ω (g = 0 and ġ = x ω − ẏ = 0 there), so ∂x/∂ω is a
// column, here against a Jet over ω of that closed form. T contains no ω:
// the column comes through the row's derivative along ω (C and γ) alone.
// Sent from x = 0.2 instead, ġ changes with ω (∂ġ/∂ω = x): refused.
TEST(TextConstrainedSensitivity, SpinningWireRateEntersThroughTheRowClosedForm) {
  const double omega = 1.5, v = 0.4;
  const text::TextModel bead(spinning_wire_text(0.8, omega));
  lagrangian::SensitivityOptions o;
  o.run = lagrangian_test::lyapunov_options(2.0, 1e-12).run;
  o.run.output_interval = 1.0;
  o.parameters = {"omega", "m"};
  const lagrangian::SensitivityResult r = text::sensitivities(bead, start({0.0, 0.0}, {v, 0.0}), o);
  ASSERT_EQ(r.times.size(), 3u);
  using J = lagrangian::ad::Jet<double, 1, 1>;
  J w(omega);
  w.g[0] = 1.0;
  double worst = 0;
  for (std::size_t i = 0; i < r.times.size(); ++i) {
    const double t = r.times[i];
    using std::cos, std::cosh, std::sin, std::sinh;
    const J radius = v / w * sinh(w * t), rate = v * cosh(w * t);
    const J x = radius * cos(w * t), y = radius * sin(w * t);
    const J xd = rate * cos(w * t) - radius * w * sin(w * t), yd = rate * sin(w * t) + radius * w * cos(w * t);
    const Eigen::Vector4d expected(x.g[0], y.g[0], xd.g[0], yd.g[0]);
    ASSERT_EQ(r.sensitivities[i].cols(), 4 + 2);
    worst = std::max(worst, (r.sensitivities[i].col(4) - expected).norm() / (1 + expected.norm()));
    EXPECT_LE((r.sensitivities[i].col(4) - expected).norm(), 1e-9 * (1 + expected.norm()))
        << "t = " << t << "\n" << r.sensitivities[i].col(4).transpose() << "\n" << expected.transpose();
    EXPECT_LE(r.sensitivities[i].col(5).norm(), 1e-12);  // m: the motion does not depend on it
  }
  std::printf("bead on the spinning wire (text), column of omega against the closed form: %.1e relative (|s| = %.2f "
              "at 2 s); m: %.1e\n",
              worst, r.sensitivities.back().col(4).norm(), r.sensitivities.back().col(5).norm());
  EXPECT_GT(r.sensitivities.back().col(4).norm(), 1.0);
  o.parameters = {"omega"};
  EXPECT_EQ(message_of([&] { (void)text::sensitivities(bead, start({0.2, 0.0}, {v, 0.3}), o); }),
            "sensitivity: parameter 'omega' moves the constraint manifold past the start: d(g0 (rate))/domega = 0.2 "
            "there, so the start would leave the constraints when omega changes; ask for other parameters, or start "
            "where the constraints do not depend on it");
}

// The double pendulum with two rods as text, its masses and g against
// central differences of simulate()'s state at t = 1 s (each parameter
// moved by ±1e-5 of itself, as test_sensitivity.cpp does for the angle
// model); a rod's length moves the manifold past the start: refused.
TEST(TextConstrainedSensitivity, CartesianDoublePendulumParametersMatchCentralDifferences) {
  const lm::CartesianDoublePendulum p(1.3, 0.7, 1.0, 0.8, 9.81);
  const text::Definition d = cartesian_double_pendulum_text(p);
  const double a1 = 1.2, a2 = -0.4, w1 = 0.3, w2 = 0.8;  // angles and rates
  const double x1 = p.l1 * std::sin(a1), y1 = -p.l1 * std::cos(a1);
  const double x2 = x1 + p.l2 * std::sin(a2), y2 = y1 - p.l2 * std::cos(a2);
  const double u1 = p.l1 * std::cos(a1) * w1, v1 = p.l1 * std::sin(a1) * w1;
  const double u2 = u1 + p.l2 * std::cos(a2) * w2, v2 = v1 + p.l2 * std::sin(a2) * w2;
  const auto s = start({x1, y1, x2, y2}, {u1, v1, u2, v2});
  lagrangian::SensitivityOptions o;
  o.run.t_end = 1.0;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  o.initial_state = false;
  o.parameters = {"m1", "m2", "g"};
  const lagrangian::SensitivityResult r = text::sensitivities(text::TextModel(d), s, o);
  const Eigen::MatrixXd& got = r.sensitivities.back();
  ASSERT_EQ(got.cols(), 3);
  lagrangian::SimulationOptions so;
  so.t_end = 1.0;
  so.rtol = 1e-13;
  so.atol = 1e-15;
  const auto final_state = [&](const std::string& name, double value) { return final_state_with(d, name, value, s, so); };
  for (int j = 0; j < 3; ++j) {
    const std::string& name = r.parameters[static_cast<std::size_t>(j)];
    double value = 0;
    for (const auto& [n, v] : d.parameters)
      if (n == name) value = v;
    const double h = 1e-5 * value;
    const Eigen::VectorXd fd = (final_state(name, value + h) - final_state(name, value - h)) / (2 * h);
    const double scale = fd.cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 1e-2) << name;
    std::printf("Cartesian double pendulum (text) d/d%s: largest entry %.4f, against central differences %.2e of it\n",
                name.c_str(), scale, (got.col(j) - fd).cwiseAbs().maxCoeff() / scale);
    EXPECT_LE((got.col(j) - fd).cwiseAbs().maxCoeff(), 1e-6 * scale) << name << "\n" << got.col(j) << "\n\n" << fd;
  }
  o.parameters = {"l2"};
  EXPECT_EQ(message_of([&] { (void)text::sensitivities(text::TextModel(d), s, o); }),
            "sensitivity: parameter 'l2' moves the constraint manifold past the start: d(g1)/dl2 = -1 there, so the "
            "start would leave the constraints when l2 changes; ask for other parameters, or start where the "
            "constraints do not depend on it");
}

// Floquet multipliers on the manifold: the wire spinning at ω repeats after
// T = 2π/ω and r̈ = ω² r is linear, so the multipliers are e^{±2π}.
TEST(TextConstrainedFloquet, BeadOnASpinningWireHasMultipliersExpOfPlusMinusTwoPi) {
  const double omega = 1.5;
  const text::TextModel bead(spinning_wire_text(0.8, omega));
  const lagrangian::FloquetResult r =
      text::floquet_multipliers(bead, start({0.2, 0.0}, {0.0, omega * 0.2}), floquet_over(2 * M_PI / omega));
  ASSERT_EQ(r.multipliers.size(), 2u);
  EXPECT_FALSE(r.stable);
  const double big = std::exp(2 * M_PI);
  EXPECT_NEAR(std::abs(r.multipliers[0]) / big, 1.0, 1e-6);
  EXPECT_NEAR(std::abs(r.multipliers[1]) * big, 1.0, 1e-6);
}

TEST(TextTangentFlow, RefusesWhatItIsNotDerivedFor) {
  text::Definition seven;
  for (int i = 0; i < 7; ++i) seven.coordinates.push_back("x" + std::to_string(i));
  seven.kinetic = "0.5*(x0_dot^2 + x1_dot^2 + x2_dot^2 + x3_dot^2 + x4_dot^2 + x5_dot^2 + x6_dot^2)";
  const text::TextModel big(seven);
  lagrangian::State<lagrangian::Dynamic> s7(7);
  EXPECT_EQ(message_of([&] { (void)text::lyapunov_spectrum(big, s7, lyapunov_over(1.0)); }),
            "lyapunov: the tangent flow is derived for models of at most 6 coordinates; this text model has 7");

  text::Definition rod;  // a particle on a circle, held by a holonomic constraint
  rod.coordinates = {"x", "y"};
  rod.kinetic = "0.5*(x_dot^2 + y_dot^2)";
  rod.potential = "9.81*y";
  rod.holonomic.assign(8, "x^2 + y^2 - 1");  // the most rows taken, each the same circle: d = 2
  const text::TextModel eight(rod);
  EXPECT_EQ(text::lyapunov_spectrum(eight, start({1, 0}, {0, 1}), lyapunov_over(1.0)).spectrum.size(), 2u);
  rod.holonomic.assign(9, "x^2 + y^2 - 1");
  const text::TextModel nine(rod);
  EXPECT_EQ(message_of([&] { (void)text::lyapunov_spectrum(nine, start({1, 0}, {0, 0}), lyapunov_over(1.0)); }),
            "lyapunov: the tangent flow takes at most 8 holonomic and Pfaffian rows counted at run time; this model "
            "declares 9");

  const text::TextModel pendulum(lagrangian::testing::double_pendulum_text(lm::DoublePendulum()));
  EXPECT_EQ(message_of([&] { (void)text::lyapunov_spectrum(pendulum, start({1}, {0}), lyapunov_over(1.0)); }),
            "lyapunov: the initial state's q and qd have sizes 1 and 1; the model has 2 coordinates");
  EXPECT_THROW((void)text::FixedSizeModel<3>(pendulum), lagrangian::AnalysisError);
}

// A holonomic row and a contact stated as text: the rod pendulum against a
// wall (RodPendulumAgainstWall of contact_models.hpp, its row written as
// x² + y² − 1 here: the same circle, rows of another scale). Its exponents
// sum to 2 ln e · impacts / T (test_constrained_tangent.cpp), and the
// spectrum and Φ are the C++ model's.
TEST(TextTangentFlow, RodPendulumAgainstAWallIsTheCppModel) {
  text::Definition d;
  d.coordinates = {"x", "y"};
  d.parameters = {{"g", 9.81}};
  d.kinetic = "0.5*(x_dot^2 + y_dot^2)";
  d.potential = "g*y";
  d.holonomic = {"x^2 + y^2 - 1"};
  d.contacts = {{"wall", "0.5 - x", 0.8, "m"}};
  const text::TextModel model(d);
  const lagrangian::testing::RodPendulumAgainstWall cpp;
  lagrangian::State<2> s;
  s.q << 0.0, -1.0;
  s.qd << 2.0, 0.0;
  const double t_end = 6.0;
  const lagrangian::LyapunovResult a = text::lyapunov_spectrum(model, start({0.0, -1.0}, {2.0, 0.0}), lyapunov_over(t_end));
  const lagrangian::LyapunovResult b = lagrangian::lyapunov_spectrum(cpp, s, lyapunov_over(t_end));
  ASSERT_EQ(a.spectrum.size(), 2u);
  EXPECT_GE(a.impacts, 3);
  EXPECT_EQ(a.impacts, b.impacts);
  EXPECT_NEAR(a.sum, 2 * std::log(0.8) * a.impacts / t_end, 1e-8);
  for (std::size_t i = 0; i < 2; ++i) EXPECT_NEAR(a.spectrum[i], b.spectrum[i], 1e-7) << "exponent " << i;
  const lagrangian::SensitivityOptions o = lagrangian_test::sensitivity_options(3.0, {}, -1.0);
  const lagrangian::SensitivityResult sa = text::sensitivities(model, start({0.0, -1.0}, {2.0, 0.0}), o);
  const lagrangian::SensitivityResult sb = lagrangian::sensitivities(cpp, s, o);
  EXPECT_GE(sa.impacts, 1);
  EXPECT_LE(lagrangian_test::worst_relative(sa.sensitivities.back(), sb.sensitivities.back()), 1e-8)
      << sa.sensitivities.back() << "\n\n" << sb.sensitivities.back();
}

// The parameter columns of that model, g and the wall's place a (gap
// a − x), across its impacts (the impact law under the row along a
// parameter, and the gap moving with a), against central differences of
// simulate() on the same text model.
TEST(TextSaltation, RodAgainstAWallParameterColumnsMatchCentralDifferences) {
  const auto rod_against_wall = [](double g, double a) {
    text::Definition d;
    d.coordinates = {"x", "y"};
    d.parameters = {{"g", g}, {"a", a}};
    d.kinetic = "0.5*(x_dot^2 + y_dot^2)";
    d.potential = "g*y";
    d.holonomic = {"x^2 + y^2 - 1"};
    d.contacts = {{"wall", "a - x", 0.8, "m"}};
    return text::TextModel(d);
  };
  const double g = 9.81, a = 0.5;
  const auto s = start({0.0, -1.0}, {2.0, 0.0});
  lagrangian::SensitivityOptions o;
  o.run.t_end = 3.0;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  o.initial_state = false;
  o.parameters = {"g", "a"};
  const lagrangian::SensitivityResult r = text::sensitivities(rod_against_wall(g, a), s, o);
  ASSERT_EQ(r.sensitivities.back().cols(), 2);
  EXPECT_GE(r.impacts, 2);
  const auto final_state = [&](double gg, double aa) {
    lagrangian::SimulationOptions so = o.run;
    so.output_interval = -1;
    lagrangian::Recorder<lagrangian::Dynamic> rec;
    const lagrangian::RunReport report = lagrangian::simulate(rod_against_wall(gg, aa), s, so, rec);
    EXPECT_EQ(static_cast<int>(report.impacts), r.impacts);
    Eigen::VectorXd x(4);
    x << rec.samples.back().q, rec.samples.back().qd;
    return x;
  };
  Eigen::MatrixXd fd(4, 2);
  fd.col(0) = (final_state(g + 1e-5, a) - final_state(g - 1e-5, a)) / 2e-5;
  fd.col(1) = (final_state(g, a + 1e-6) - final_state(g, a - 1e-6)) / 2e-6;
  const Eigen::MatrixXd& columns = r.sensitivities.back();
  EXPECT_GT(columns.col(1).norm(), 0.1);
  EXPECT_LE((fd - columns).cwiseAbs().maxCoeff(), 1e-6 * columns.cwiseAbs().maxCoeff())
      << "columns:\n" << columns << "\ncentral differences:\n" << fd;
  std::printf("rod against a wall, %d impacts: |columns - central differences| = %.1e of %.3g\n", r.impacts,
              (fd - columns).cwiseAbs().maxCoeff(), columns.cwiseAbs().maxCoeff());
}

}  // namespace
