// Models stated as text (text/text_model.hpp): the expression reader
// against hand-evaluated values and its errors, and text models against
// the built-in C++ models and closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/text/evaluate.hpp"
#include "lagrangian/text/text_model.hpp"
#include "runtime_chain.hpp"
#include "text_definitions.hpp"

namespace {

using namespace lagrangian;
using text::Definition;
using lagrangian::testing::double_pendulum_text;

double value_of(const std::string& source, std::vector<double> q = {}, std::vector<double> qd = {}, double t = 0.0,
                const std::vector<std::pair<std::string, double>>& parameters = {}) {
  text::Symbols symbols;
  for (std::size_t i = 0; i < q.size(); ++i) symbols.coordinates.push_back(i == 0 ? "x" : "y");
  std::vector<double> values;
  for (const auto& [name, v] : parameters) {
    symbols.parameters.push_back(name);
    values.push_back(v);
  }
  const text::Expression e = text::parse(source, symbols, "f");
  std::vector<double> slots;
  const double free = text::evaluate(e, q, qd, t, slots, values.data());
  // Binding the parameters first folds them; the value is the same.
  const double bound = text::evaluate(text::bind_parameters(e, values), q, qd, t, slots);
  EXPECT_EQ(free, bound) << source;
  return free;
}

TEST(TextExpression, PrecedenceAssociativityAndFunctions) {
  EXPECT_EQ(value_of("1 + 2 * 3"), 7.0);
  EXPECT_EQ(value_of("(1 + 2) * 3"), 9.0);
  EXPECT_EQ(value_of("2 ^ 3 ^ 2"), 512.0);  // right-associative: 2^9
  EXPECT_EQ(value_of("2 ** 3 ** 2"), 512.0);
  EXPECT_EQ(value_of("-2 ^ 2"), -4.0);  // −(2²)
  EXPECT_EQ(value_of("2 ^ -1"), 0.5);
  EXPECT_EQ(value_of("8 / 4 / 2"), 1.0);  // left-associative
  EXPECT_EQ(value_of("10 - 4 - 3"), 3.0);
  EXPECT_EQ(value_of("--3"), 3.0);
  EXPECT_EQ(value_of("2 * -3"), -6.0);
  EXPECT_DOUBLE_EQ(value_of("1.5e2 + 2E-1 + .5"), 150.7);
  EXPECT_DOUBLE_EQ(value_of("pi"), std::numbers::pi);
  EXPECT_DOUBLE_EQ(value_of("atan2(1, -1)"), 0.75 * std::numbers::pi);
  EXPECT_EQ(value_of("min(3, -2) + max(3, -2)"), 1.0);
  EXPECT_EQ(value_of("pow(2, 10)"), 1024.0);
  EXPECT_EQ(value_of("abs(-2.5) + sqrt(16)"), 6.5);
  EXPECT_DOUBLE_EQ(value_of("exp(log(3)) + sinh(0) + cosh(0) + tanh(0)"), 4.0);
  EXPECT_DOUBLE_EQ(value_of("asin(1) + acos(1) + atan(1)"), 0.75 * std::numbers::pi);
  EXPECT_DOUBLE_EQ(value_of("sin(x)^2 + cos(x)^2 + tan(0)", {0.7}), 1.0);
  EXPECT_EQ(value_of("x * y_dot - y * x_dot + t", {2, 3}, {5, 7}, 0.5), 2 * 7 - 3 * 5 + 0.5);
  EXPECT_EQ(value_of("0.5 * m * x_dot^2", {0}, {3}, 0, {{"m", 4.0}}), 18.0);
  EXPECT_EQ(value_of("x^y", {2, 3}, {0, 0}), 8.0);
}

TEST(TextExpression, EqualSubexpressionsAreStoredOnceAndConstantsFolded) {
  text::Symbols s{{"x"}, {"m"}};
  const text::Expression e = text::parse("sin(x)*sin(x) + 2*3*x", s, "f");
  // x, sin x, sin x · sin x, 6, 6x, the sum: six nodes.
  EXPECT_EQ(e.nodes.size(), 6u);
  const text::Expression b = text::bind_parameters(text::parse("0.5*m*x^2", s, "f"), {4.0});
  // m bound: 0.5·4 folds to 2; then x, x², 2, 2·x².
  EXPECT_EQ(b.nodes.size(), 4u);
  EXPECT_FALSE(e.reads_velocities());
  EXPECT_TRUE(text::parse("x_dot", s, "f").reads_velocities());
  EXPECT_TRUE(text::parse("t*x", s, "f").reads_time());
}

std::string error_of(const std::string& source) {
  try {
    text::parse(source, {{"theta"}, {"m", "g"}}, "model.kinetic");
  } catch (const text::ExpressionError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(TextExpression, ErrorsNameTheFieldTheColumnAndTheProblem) {
  EXPECT_EQ(error_of("0.5*m*thta_dot^2"),
            "model.kinetic (column 7): unknown name 'thta_dot', did you mean 'theta_dot'?; the names here are the "
            "coordinates (theta), their "
            "velocities (theta_dot), the parameters (m, g), t and pi");
  EXPECT_EQ(error_of("sin theta"), "model.kinetic (column 1): 'sin' is a function: write sin(...)");
  EXPECT_EQ(error_of("atan2(theta)"), "model.kinetic (column 1): atan2 takes 2 arguments, not 1");
  EXPECT_EQ(error_of("cosine(theta)").substr(0, 58),
            "model.kinetic (column 1): unknown function 'cosine'; the f");
  EXPECT_EQ(error_of("(theta + 1"), "model.kinetic (column 11): ')' expected");
  EXPECT_EQ(error_of("theta +"),
            "model.kinetic (column 8): the expression ends where a number, a name or '(' was expected");
  EXPECT_EQ(error_of("theta $ 2"), "model.kinetic (column 7): unexpected '$'");
  EXPECT_EQ(error_of("  "), "model.kinetic: the expression is empty");
  EXPECT_EQ(error_of("1.2.3"), "model.kinetic (column 1): '1.2.3' is not a number");
}

TEST(TextModel, DoublePendulumAgreesWithTheBuiltInModel) {
  const models::DoublePendulum built_in(1.3, 0.7, 1.1, 0.8, 9.81);
  const text::TextModel text_model(double_pendulum_text(built_in));
  EXPECT_EQ(text_model.size(), 2);
  EXPECT_EQ(text_model.coordinate_names()[1], "th2");
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Workspace<2> ws;
  Workspace<Dynamic> wsx(2);
  for (int k = 0; k < 50; ++k) {
    Vec<double, 2> q(u(rng), u(rng)), qd(u(rng), u(rng));
    const Eigen::VectorXd qx = q, qdx = qd;
    const Vec<double, 2> a = accelerations(built_in, ws, q, qd, 0.0);
    const Eigen::VectorXd b = accelerations(text_model, wsx, qx, qdx, 0.0);
    EXPECT_LE((a - b).lpNorm<Eigen::Infinity>(), 1e-13 * std::max(1.0, a.lpNorm<Eigen::Infinity>()));
    const Vec<double, 2> pa = momenta(built_in, q, qd, 0.0);
    const Eigen::VectorXd pb = momenta(text_model, qx, qdx, 0.0);
    EXPECT_LE((pa - pb).lpNorm<Eigen::Infinity>(), 1e-13 * std::max(1.0, pa.lpNorm<Eigen::Infinity>()));
    const Mat<double, 2> ma = mass_matrix(built_in, q, qd, 0.0);
    const Eigen::MatrixXd mb = mass_matrix(text_model, qx, qdx, 0.0);
    EXPECT_LE((ma - mb).lpNorm<Eigen::Infinity>(), 1e-13 * ma.lpNorm<Eigen::Infinity>());
  }
}

// A run-time size of 2 solves M q̈ = f by Cramer's rule; a singular or
// indefinite M must still stop with the state named. T = ½ (ẋ + ẏ)² has
// M = [[1, 1], [1, 1]] (det 0; neither diagonal), T = ½ ẋ² + 2 ẋ ẏ + ½ ẏ²
// has M = [[1, 2], [2, 1]] (det −3: not positive definite), and a
// positive definite off-diagonal M gives the q̈ of its closed form.
TEST(TextModel, ARunTimeTwoByTwoMassMatrixIsCheckedAndSolved) {
  auto model = [](const std::string& kinetic) {
    Definition d;
    d.coordinates = {"x", "y"};
    d.kinetic = kinetic;
    d.potential = "x + 3*y";
    return text::TextModel(d);
  };
  Workspace<Dynamic> ws(2);
  const Eigen::VectorXd q = Eigen::Vector2d(0.1, 0.2), qd = Eigen::Vector2d(0.3, -0.4);
  for (const char* singular : {"0.5*(x_dot + y_dot)^2", "0.5*x_dot^2 + 2*x_dot*y_dot + 0.5*y_dot^2"}) {
    try {
      accelerations(model(singular), ws, q, qd, 0.0);
      ADD_FAILURE() << singular << ": no error";
    } catch (const DynamicsError& e) {
      EXPECT_NE(std::string(e.what()).find("is singular or not positive definite at t = 0, q = [0.1"),
                std::string::npos)
          << e.what();
    }
  }
  // M = [[2, 1], [1, 3]], f = −∇V = (−1, −3): q̈ = M⁻¹ f = (0, −1).
  const Eigen::VectorXd a = accelerations(model("x_dot^2 + x_dot*y_dot + 1.5*y_dot^2"), ws, q, qd, 0.0);
  EXPECT_NEAR(a[0], 0.0, 1e-15);
  EXPECT_NEAR(a[1], -1.0, 1e-15);
}

// Text models of up to 4 coordinates take numbers of their own width, up to
// 12 numbers of width 12 (the directions past n unused), above that numbers
// of run-time width: chains on each side of those bounds against the same
// chain in C++.
TEST(TextModel, ChainsOfEveryPassWidthAgreeWithTheChainInCpp) {
  std::mt19937_64 rng(20261204);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (const int n : {4, 5, 12, 13}) {
    const text::TextModel text_model(lagrangian::testing::pendulum_chain_text(n));
    const test_models::RuntimeChain chain{n};
    Workspace<Dynamic> ws(n), wsx(n);
    for (int k = 0; k < 5; ++k) {
      Eigen::VectorXd q(n), qd(n);
      for (int i = 0; i < n; ++i) {
        q[i] = u(rng);
        qd[i] = u(rng);
      }
      const Eigen::VectorXd a = accelerations(chain, ws, q, qd, 0.0);
      const Eigen::VectorXd b = accelerations(text_model, wsx, q, qd, 0.0);
      EXPECT_LE((a - b).lpNorm<Eigen::Infinity>(), 1e-11 * a.lpNorm<Eigen::Infinity>()) << "n = " << n;
      const Eigen::MatrixXd ma = mass_matrix(chain, q, qd, 0.0), mb = mass_matrix(text_model, q, qd, 0.0);
      EXPECT_LE((ma - mb).lpNorm<Eigen::Infinity>(), 1e-13 * ma.lpNorm<Eigen::Infinity>()) << "n = " << n;
      const Eigen::VectorXd pa = momenta(chain, q, qd, 0.0), pb = momenta(text_model, q, qd, 0.0);
      EXPECT_LE((pa - pb).lpNorm<Eigen::Infinity>(), 1e-13 * pa.lpNorm<Eigen::Infinity>()) << "n = " << n;
    }
  }
}

TEST(TextModel, SphericalPendulumRunsAsTheBuiltInModelDoes) {
  Definition d;
  d.coordinates = {"theta", "phi"};
  d.kinetic = "0.5*m*l^2*(theta_dot^2 + sin(theta)^2*phi_dot^2)";
  d.potential = "-m*g*l*cos(theta)";
  d.parameters = {{"m", 1.0}, {"l", 1.0}, {"g", 9.81}};
  const text::TextModel text_model(d);
  const models::SphericalPendulum built_in(1.0, 1.0, 9.81);
  SimulationOptions o;
  o.t_end = 10.0;
  o.rtol = 1e-12;
  o.atol = 1e-12;
  o.output_interval = 1.0;
  State<2> s0;
  s0.q << 1.0, 0.0;
  s0.qd << 0.0, 2.0;
  State<Dynamic> x0(2);
  x0.q = s0.q;
  x0.qd = s0.qd;
  Recorder<2> a;
  Recorder<Dynamic> b;
  const RunReport ra = simulate(built_in, s0, o, a);
  const RunReport rb = simulate(text_model, x0, o, b);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  double worst = 0;
  for (std::size_t k = 0; k < a.samples.size(); ++k)
    worst = std::max({worst, (a.samples[k].q - b.samples[k].q).lpNorm<Eigen::Infinity>(),
                      (a.samples[k].qd - b.samples[k].qd).lpNorm<Eigen::Infinity>()});
  EXPECT_LE(worst, 1e-9);
  // p_φ = m l² sin²θ φ̇ is conserved (φ is cyclic), and so is the energy.
  const double p_phi0 = std::sin(1.0) * std::sin(1.0) * 2.0;
  for (const auto& s : b.samples)
    EXPECT_NEAR(std::sin(s.q[0]) * std::sin(s.q[0]) * s.qd[1], p_phi0, 1e-9);
  EXPECT_LE(rb.energy_drift_max, 1e-9);
  EXPECT_TRUE(rb.conservative);
  EXPECT_EQ(ra.steps, rb.steps);
}

// A rheonomic model: the pendulum whose pivot moves as y_p = a cos Ωt, its T
// written from the bob's velocity (ẋ, ẏ) = (l cos θ θ̇, −aΩ sin Ωt +
// l sin θ θ̇), against the built-in DrivenPendulum (T expanded there).
TEST(TextModel, TimeInTAndVRunsAsTheBuiltInDrivenPendulumDoes) {
  const double m = 1.2, l = 0.9, a = 0.05, w = 30.0, g = 9.81;
  Definition d;
  d.coordinates = {"theta"};
  d.kinetic = "0.5*m*((l*cos(theta)*theta_dot)^2 + (-a*Omega*sin(Omega*t) + l*sin(theta)*theta_dot)^2)";
  d.potential = "m*g*(a*cos(Omega*t) - l*cos(theta))";
  d.parameters = {{"m", m}, {"l", l}, {"a", a}, {"Omega", w}, {"g", g}};
  const text::TextModel text_model(d);
  const models::DrivenPendulum built_in(m, l, a, w, g);
  SimulationOptions o;
  o.t_end = 3.0;
  o.rtol = 1e-12;
  o.atol = 1e-12;
  o.output_interval = 0.5;
  State<1> s0;
  s0.q << 2.5;
  State<Dynamic> x0(1);
  x0.q << 2.5;
  Recorder<1> ra;
  Recorder<Dynamic> rb;
  simulate(built_in, s0, o, ra);
  const RunReport r = simulate(text_model, x0, o, rb);
  ASSERT_EQ(ra.samples.size(), rb.samples.size());
  for (std::size_t k = 0; k < ra.samples.size(); ++k) {
    EXPECT_NEAR(ra.samples[k].q[0], rb.samples[k].q[0], 1e-9) << "t = " << ra.samples[k].t;
    EXPECT_NEAR(ra.samples[k].qd[0], rb.samples[k].qd[0], 1e-8) << "t = " << ra.samples[k].t;
  }
  EXPECT_FALSE(r.conservative);  // L depends on t
}

// A damped oscillator, m ẍ = −k x − c ẋ, stated twice: with a Rayleigh
// function D = ½ c ẋ² and with a generalized force Q = −c ẋ. Underdamped,
// from x(0) = x0 at rest: x(t) = x0 e^(−γt) (cos ω_d t + (γ/ω_d) sin ω_d t),
// γ = c/(2m), ω_d = √(k/m − γ²).
TEST(TextModel, DampingAsDissipationAndAsForceFollowTheClosedForm) {
  const double m = 2.0, k = 8.0, c = 0.6, x0 = 0.3;
  const double gamma = c / (2 * m), wd = std::sqrt(k / m - gamma * gamma);
  Definition d;
  d.coordinates = {"x"};
  d.units = {"m"};
  d.kinetic = "0.5*m*x_dot^2";
  d.potential = "0.5*k*x^2";
  d.parameters = {{"m", m}, {"k", k}, {"c", c}};
  Definition with_d = d, with_q = d;
  with_d.dissipation = "0.5*c*x_dot^2";
  with_q.forces = {"-c*x_dot"};
  const text::TextModel by_d(with_d), by_q(with_q);
  EXPECT_TRUE(by_d.uses_dissipation());
  EXPECT_FALSE(by_d.uses_generalized_forces());
  EXPECT_TRUE(by_q.uses_generalized_forces());
  EXPECT_FALSE(by_q.uses_dissipation());
  SimulationOptions o;
  o.t_end = 8.0;
  o.rtol = 1e-12;
  o.atol = 1e-13;
  o.output_interval = 0.5;
  State<Dynamic> s0(1);
  s0.q[0] = x0;
  for (const text::TextModel* model : {&by_d, &by_q}) {
    Recorder<Dynamic> rec;
    const RunReport r = simulate(*model, s0, o, rec);
    EXPECT_FALSE(r.conservative);
    double worst = 0;
    for (const auto& s : rec.samples) {
      const double x = x0 * std::exp(-gamma * s.t) * (std::cos(wd * s.t) + gamma / wd * std::sin(wd * s.t));
      worst = std::max(worst, std::abs(s.q[0] - x));
    }
    EXPECT_LE(worst, 1e-9) << (model == &by_d ? "D" : "Q");
    EXPECT_EQ(rec.samples.size(), 17u);
  }
}

std::string momentum_formula(const std::string& kinetic, const std::vector<std::string>& coordinates, int i) {
  const text::Symbols s{coordinates, {"m", "l", "m1", "m2", "l1", "l2"}};
  return text::to_text(text::derivative(text::parse(kinetic, s, "T"), text::Op::velocity, i), s);
}

TEST(TextFormula, MomentaPrintAsACourseWritesThem) {
  EXPECT_EQ(momentum_formula("0.5*m*l^2*theta_dot^2", {"theta"}, 0), "m*l^2*theta_dot");
  const std::string spherical = "0.5*m*l^2*(theta_dot^2 + sin(theta)^2*phi_dot^2)";
  EXPECT_EQ(momentum_formula(spherical, {"theta", "phi"}, 0), "m*l^2*theta_dot");
  EXPECT_EQ(momentum_formula(spherical, {"theta", "phi"}, 1), "m*l^2*sin(theta)^2*phi_dot");
  EXPECT_EQ(momentum_formula("0.5*m*(x_dot^2 + y_dot^2) - m*x_dot*y_dot", {"x", "y"}, 1), "m*y_dot - m*x_dot");
  EXPECT_EQ(momentum_formula("m*sqrt(1 + x_dot^2)", {"x"}, 0), "m*x_dot/sqrt(1 + x_dot^2)");
  // min and max: a formula while the velocity is not among their arguments.
  EXPECT_EQ(momentum_formula("min(m, l)*x_dot", {"x"}, 0), "min(m, l)");
  EXPECT_THROW(momentum_formula("max(x_dot, 0)*x_dot", {"x"}, 0), text::ExpressionError);
}

// The printed momenta read back and evaluated against p from automatic
// differentiation (two derivations of one quantity), at random states of a
// double pendulum and of a T with every function the derivative knows.
TEST(TextFormula, MomentaFormulasAgreeWithAutomaticDifferentiation) {
  const models::DoublePendulum dp(1.3, 0.7, 1.1, 0.8, 9.81);
  Definition odd;
  odd.coordinates = {"x", "y"};
  odd.kinetic =
      "0.5*m*(x_dot^2 + y_dot^2)*(2 + sin(x)*cos(y)) + exp(0.1*x_dot*y_dot) + log(2 + x_dot^2) + sqrt(1 + y_dot^2)"
      " + tan(0.2*x_dot) + asin(0.1*y_dot) + acos(0.1*x_dot) + atan(x_dot*y) + sinh(0.3*y_dot) + cosh(0.2*x_dot)"
      " + tanh(y_dot) + abs(x_dot + 3) + atan2(y_dot, 2 + x_dot^2) + (1 + x_dot^2)^(1.5 + 0.1*y_dot^2)"
      " + x_dot/(2 + y_dot^2)";
  odd.potential = "m*x^2";
  odd.parameters = {{"m", 1.7}};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Definition& d : {double_pendulum_text(dp), odd}) {
    const text::TextModel model(d);
    const text::Parsed& p = model.parsed();
    std::vector<double> values;
    for (const auto& [name, v] : d.parameters) values.push_back(v);
    for (int k = 0; k < 20; ++k) {
      const Eigen::VectorXd q = Eigen::Vector2d(u(rng), u(rng)), qd = Eigen::Vector2d(u(rng), u(rng));
      const Eigen::VectorXd ad = momenta(model, q, qd, 0.0);
      for (int i = 0; i < 2; ++i) {
        const std::string formula =
            text::to_text(text::derivative(p.kinetic, text::Op::velocity, i), p.symbols);
        const text::Expression back = text::parse(formula, p.symbols, "p");
        std::vector<double> slots;
        const double value = text::evaluate(back, q, qd, 0.0, slots, values.data());
        EXPECT_NEAR(value, ad[i], 1e-12 * std::max(1.0, std::abs(ad[i]))) << formula;
      }
    }
  }
}

// The analyses on a run-time sized model (second derivatives by passes over
// pairs of blocks). Double pendulum, m1 = m2, l1 = l2 = l: the equilibria
// are (0, 0) (stable), (0, π), (π, 0), (π, π), and the modes about (0, 0)
// have ω² = (g/l)(2 ∓ √2).
TEST(TextAnalysis, DoublePendulumEquilibriaAndModesFollowTheClosedForm) {
  const double l = 0.7, g = 9.81;
  const text::TextModel model(double_pendulum_text(models::DoublePendulum(1.0, 1.0, l, l, g)));
  EquilibriumOptions o;
  o.periods = {2 * std::numbers::pi, 2 * std::numbers::pi};
  for (const double a : {0.3, 2.9})
    for (const double b : {-0.4, 3.0}) o.starts.push_back(Eigen::Vector2d(a, b));
  const std::vector<Equilibrium> eq = find_equilibria(model, o);
  ASSERT_EQ(eq.size(), 4u);
  int stable = 0;
  for (const Equilibrium& e : eq) {
    for (int i = 0; i < 2; ++i) {
      const double x = std::abs(e.q[i]);
      EXPECT_TRUE(x < 1e-9 || std::abs(x - std::numbers::pi) < 1e-9) << e.q.transpose();
    }
    if (e.stable) {
      ++stable;
      EXPECT_LT(e.q.norm(), 1e-9);
    }
  }
  EXPECT_EQ(stable, 1);
  const Modes m = small_oscillations(model, Eigen::VectorXd(Eigen::Vector2d(0.0, 0.0)));
  ASSERT_EQ(m.omega_squared.size(), 2);
  EXPECT_NEAR(m.omega_squared[0], g / l * (2 - std::sqrt(2.0)), 1e-10);
  EXPECT_NEAR(m.omega_squared[1], g / l * (2 + std::sqrt(2.0)), 1e-10);
}

// The stationary-action boundary-value problem of an oscillator stated as
// text: x(0) = a, x(T) = b has x(t) = [a sin ω(T − t) + b sin ωt]/sin ωT;
// the midpoint rule's nodes converge to it at second order.
TEST(TextAnalysis, BoundaryValueProblemConvergesToTheClosedForm) {
  Definition d;
  d.coordinates = {"x"};
  d.kinetic = "0.5*m*x_dot^2";
  d.potential = "0.5*k*x^2";
  d.parameters = {{"m", 2.0}, {"k", 8.0}};
  const text::TextModel model(d);
  const double w = 2.0, a = 0.1, b = 0.2, T = 1.0;
  double previous = 0;
  for (const int steps : {50, 100}) {
    BvpOptions o;
    o.steps = steps;
    const BvpResult r = solve_bvp(model, Eigen::VectorXd::Constant(1, a), Eigen::VectorXd::Constant(1, b), 0.0, T, o);
    double worst = 0;
    for (std::size_t k = 0; k < r.t.size(); ++k) {
      const double t = r.t[k];
      worst = std::max(worst, std::abs(r.q(static_cast<Eigen::Index>(k), 0) -
                                       (a * std::sin(w * (T - t)) + b * std::sin(w * t)) / std::sin(w * T)));
    }
    EXPECT_LT(worst, 1e-4);
    if (steps == 100) {
      EXPECT_NEAR(previous / worst, 4.0, 0.2);  // second order
    }
    previous = worst;
  }
}

TEST(TextModel, DefinitionErrorsNameTheField) {
  auto error_of_definition = [](const Definition& d) -> std::string {
    try {
      text::read(d);
    } catch (const text::ExpressionError& e) {
      return e.what();
    }
    return "(no error)";
  };
  Definition d;
  d.field_prefix = "model.";
  d.coordinates = {"x"};
  d.kinetic = "0.5*x_dot^2";
  EXPECT_EQ(error_of_definition(d), "(no error)");
  Definition e = d;
  e.potential = "x_dot";
  EXPECT_EQ(error_of_definition(e), "model.potential: V depends on q and t only; a velocity appears in it");
  e = d;
  e.coordinates = {"x", "x"};
  EXPECT_EQ(error_of_definition(e), "model.coordinates: 'x' is named twice");
  e = d;
  e.coordinates = {"sin"};
  EXPECT_EQ(error_of_definition(e).substr(0, 55), "model.coordinates: 'sin' cannot name a coordinate or pa");
  e = d;
  e.units = {"m", "m"};
  EXPECT_EQ(error_of_definition(e), "model.units: one unit per coordinate: 2 units for 1 coordinates");
  e = d;
  e.forces = {"1", "2"};
  EXPECT_EQ(error_of_definition(e), "model.forces: one generalized force per coordinate: 2 for 1 coordinates");
  e = d;
  e.dissipation = "t*x_dot^2";
  EXPECT_EQ(error_of_definition(e), "model.dissipation: D depends on q and q̇ only; t appears in it");
  e = d;
  e.parameters = {{"x_dot", 1.0}};
  EXPECT_EQ(error_of_definition(e), "model.parameters.x_dot: 'x_dot' is named twice");
  e = d;
  e.parameters = {{"k", std::nan("")}};
  EXPECT_EQ(error_of_definition(e), "model.parameters.k: the value is not finite");
  e = d;
  e.kinetic = "";
  EXPECT_EQ(error_of_definition(e), "model.kinetic: T is missing");
}

}  // namespace
