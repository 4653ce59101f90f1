// The tangent flow of models stated as text (text/fixed_size.hpp,
// text/tangent_flow.hpp): against the same systems written in C++, closed
// forms, Liouville's theorem and Kapitza's criterion.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <complex>
#include <string>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/text/fixed_size.hpp"
#include "lagrangian/text/tangent_flow.hpp"
#include "contact_models.hpp"
#include "text_definitions.hpp"
#include "tangent_options.hpp"

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

TEST(TextTangentFlow, DoublePendulumJacobianIsTheBuiltInModels) {
  const lm::DoublePendulum built_in(1.3, 0.7, 1.1, 0.8, 9.81);
  const text::TextModel model(lagrangian::testing::double_pendulum_text(built_in));
  const text::FixedSizeModel<2> fixed(model);
  for (const auto& [q, qd] : {std::pair{Vec<double, 2>(0.3, -1.2), Vec<double, 2>(0.8, 2.1)},
                              std::pair{Vec<double, 2>(2.0, 2.0), Vec<double, 2>(0.0, 0.0)},
                              std::pair{Vec<double, 2>(-3.0, 1.0), Vec<double, 2>(-4.0, 5.5)}}) {
    Vec<double, 2> qdd_text, qdd_cpp;
    Eigen::Matrix<double, 2, 4> j_text, j_cpp;
    lagrangian::state_jacobian(fixed, q, qd, 0.0, qdd_text, j_text);
    lagrangian::state_jacobian(built_in, q, qd, 0.0, qdd_cpp, j_cpp);
    EXPECT_LE((qdd_text - qdd_cpp).norm(), 1e-13 * (1 + qdd_cpp.norm()));
    EXPECT_LE((j_text - j_cpp).norm(), 1e-12 * (1 + j_cpp.norm())) << "text:\n" << j_text << "\nC++:\n" << j_cpp;
  }
}

/// models::PendulumChain<n> (unit masses and lengths) as text: bob k moves
/// at (Σ_{j≤k} cos q_j q̇_j, Σ_{j≤k} sin q_j q̇_j) and hangs at −Σ_{j≤k} cos q_j.
text::Definition chain_text(int n) {
  text::Definition d;
  std::string vx, vy, y;
  for (int k = 0; k < n; ++k) {
    const std::string q = "q" + std::to_string(k);
    d.coordinates.push_back(q);
    vx += (k ? " + " : "") + std::string("cos(") + q + ")*" + q + "_dot";
    vy += (k ? " + " : "") + std::string("sin(") + q + ")*" + q + "_dot";
    y += " - cos(" + q + ")";
    d.kinetic += (k ? " + " : "") + std::string("0.5*m*((") + vx + ")^2 + (" + vy + ")^2)";
    d.potential += (k ? " + " : "") + std::string("m*g*(") + y + ")";
  }
  d.parameters = {{"m", 1.0}, {"g", 9.81}};
  return d;
}

template <int N>
void expect_chain_agrees() {
  const text::TextModel model(chain_text(N));
  const text::FixedSizeModel<N> fixed(model);
  const lm::PendulumChain<N> built_in;
  Vec<double, N> q, qd;
  for (int k = 0; k < N; ++k) {
    q[k] = std::sin(1.0 + 2.3 * k);
    qd[k] = std::cos(0.4 + 1.7 * k);
  }
  Vec<double, N> qdd_text, qdd_cpp;
  Eigen::Matrix<double, N, 2 * N> j_text, j_cpp;
  lagrangian::state_jacobian(fixed, q, qd, 0.0, qdd_text, j_text);
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
  const text::FixedSizeModel<1> fixed(model);
  for (double t : {0.0, 0.0123, 0.7}) {
    const Vec<double, 1> q(2.9), qd(-0.4);
    Vec<double, 1> qdd_text, qdd_cpp;
    Eigen::Matrix<double, 1, 2> j_text, j_cpp;
    lagrangian::state_jacobian(fixed, q, qd, t, qdd_text, j_text);
    lagrangian::state_jacobian(built_in, q, qd, t, qdd_cpp, j_cpp);
    EXPECT_NEAR(qdd_text[0], qdd_cpp[0], 1e-12 * (1 + std::abs(qdd_cpp[0]))) << "t = " << t;
    EXPECT_LE((j_text - j_cpp).norm(), 1e-12 * (1 + j_cpp.norm())) << "t = " << t << "\n" << j_text << "\n" << j_cpp;
  }
}

TEST(TextTangentFlow, LinearDragGivesMinusBOverMWhetherDissipationOrForces) {
  for (bool as_dissipation : {true, false}) {
    const text::TextModel model(linear_drag_text(as_dissipation));
    const text::FixedSizeModel<2> fixed(model);
    Vec<double, 2> qdd;
    Eigen::Matrix<double, 2, 4> j;
    lagrangian::state_jacobian(fixed, Vec<double, 2>(1.0, 2.0), Vec<double, 2>(3.0, -4.0), 0.0, qdd, j);
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
  rod.holonomic = {"x^2 + y^2 - 1"};
  const text::TextModel held(rod);
  const std::string why = message_of([&] {
    (void)text::floquet_multipliers(held, start({1, 0}, {0, 0}), floquet_over(1.0));
  });
  EXPECT_NE(why.find("floquet: the tangent flow is derived for models without bilateral constraints; this model "
                     "declares 1 holonomic and 0 Pfaffian constraint rows"),
            std::string::npos)
      << why;
  EXPECT_THROW((void)text::FixedSizeModel<2>(held), lagrangian::AnalysisError);

  const text::TextModel pendulum(lagrangian::testing::double_pendulum_text(lm::DoublePendulum()));
  EXPECT_EQ(message_of([&] { (void)text::lyapunov_spectrum(pendulum, start({1}, {0}), lyapunov_over(1.0)); }),
            "lyapunov: the initial state's q and qd have sizes 1 and 1; the model has 2 coordinates");
  EXPECT_THROW((void)text::FixedSizeModel<3>(pendulum), lagrangian::AnalysisError);
}

}  // namespace
