// Models of every size: fixed sizes (one pass; Hessians inline up to 12
// coordinates, pooled above, block passes above 64), the same chains with
// a run-time size, and the hand-coded chain agree with the closed form and
// with each other, derivative by derivative and along a run. Large fixed
// models have not opted in to the structure-preserving methods, and a run
// that asks for one is told how.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <random>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "hand_coded.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "runtime_chain.hpp"

namespace {

using namespace lagrangian;
using test_models::RuntimeChain;

template <int N>
void derivatives_agree() {
  static_assert(!detail::uses_block_passes<models::PendulumChain<N>>);
  const models::PendulumChain<N> fixed(1.0, 1.0, 9.81);
  const RuntimeChain dyn{N};
  std::mt19937_64 rng(7 + N);
  const State<N> s = test_models::random_chain_state<N>(rng);
  const Vec<double, N> q = s.q, qd = s.qd;
  const Eigen::VectorXd qx = q, qdx = qd;
  const Mat<double, N> m = mass_matrix(fixed, q, qd);
  // M of the chain in closed form: M_ij = m l² (N − max(i, j)) cos(θ_i − θ_j).
  double worst = 0;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      worst = std::max(worst, std::abs(m(i, j) - (N - std::max(i, j)) * std::cos(q[i] - q[j])));
  EXPECT_LE(worst, 1e-12 * N) << "n = " << N;
  EXPECT_LE((mass_matrix(dyn, qx, qdx) - m).norm(), 1e-12 * m.norm()) << "n = " << N;
  const Vec<double, N> a = accelerations(fixed, q, qd);
  EXPECT_LE((accelerations(dyn, qx, qdx) - a).template lpNorm<Eigen::Infinity>(),
            1e-10 * a.template lpNorm<Eigen::Infinity>())
      << "n = " << N;
  EXPECT_LE((momenta(dyn, qx, qdx) - momenta(fixed, q, qd)).norm(), 1e-12 * momenta(fixed, q, qd).norm());
  // p = M q̇ for this natural system.
  EXPECT_LE((momenta(fixed, q, qd) - m * qd).norm(), 1e-12 * (m * qd).norm());
}

template <int N>
void simulation_agrees(double t_end) {
  const models::PendulumChain<N> fixed;
  const RuntimeChain dyn{N};
  State<N> x0;
  State<Dynamic> y0(N);
  for (int i = 0; i < N; ++i) x0.q[i] = y0.q[i] = 0.4 * std::sin(0.3 * i + 0.2);
  SimulationOptions o;
  o.t_end = t_end;
  o.output_interval = t_end / 4;
  o.rtol = 1e-10;
  o.atol = 1e-12;
  Recorder<N> a;
  Recorder<Dynamic> b;
  const RunReport ra = simulate(fixed, x0, o, a);
  const RunReport rb = simulate(dyn, y0, o, b);
  ASSERT_EQ(a.samples.size(), 5u);
  ASSERT_EQ(b.samples.size(), 5u);
  for (std::size_t k = 0; k < a.samples.size(); ++k)
    EXPECT_LE((a.samples[k].q - Vec<double, N>(b.samples[k].q)).template lpNorm<Eigen::Infinity>(), 1e-8)
        << "n = " << N << ", t = " << a.samples[k].t;
  // Conservative and autonomous: h = T + V is kept to the tolerance.
  EXPECT_LE(ra.energy_drift_max, 1e-8) << "n = " << N;
  EXPECT_TRUE(ra.conservative);
  EXPECT_GT(ra.steps, 10u);

  o.method = Method::variational;
  try {
    simulate(fixed, x0, o);
    FAIL() << "variational ran a model that did not opt in";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("structure_preserving = true"), std::string::npos) << e.what();
  }
}

// The uniform chain (m = l = 1) in closed form, for any n:
//   M_ij = (n − max(i, j)) cos(θi − θj),
//   f_i = −Σ_j (n − max(i, j)) sin(θi − θj) θ̇j² − (n − i) g sin θi   (M q̈ = f),
//   h = T + V = ½ q̇ᵀ M q̇ − Σ_i (n − i) g cos θi.
struct ClosedFormChain {
  Eigen::MatrixXd mass;
  Eigen::VectorXd force;
  double energy;
  ClosedFormChain(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double g) {
    const int n = static_cast<int>(q.size());
    mass.resize(n, n);
    force.resize(n);
    energy = 0;
    for (int i = 0; i < n; ++i) {
      force[i] = -(n - i) * g * std::sin(q[i]);
      energy -= (n - i) * g * std::cos(q[i]);
      for (int j = 0; j < n; ++j) {
        const double w = n - std::max(i, j);
        mass(i, j) = w * std::cos(q[i] - q[j]);
        force[i] -= w * std::sin(q[i] - q[j]) * qd[j] * qd[j];
      }
    }
    energy += 0.5 * qd.dot(mass * qd);
  }
};

// M, p, h and q̈ of a chain from AD agree with the closed form to 1e-13
// (q̈ as the residual of M q̈ = f: the solve's own rounding grows with M's
// condition number, the residual does not). Returns q̈.
template <class M>
Eigen::VectorXd expect_closed_form(const M& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                   const char* which) {
  const int n = static_cast<int>(q.size());
  const ClosedFormChain exact(q, qd, 9.81);
  const Vec<double, coordinate_count_v<M>> qv = q, qdv = qd;
  const Eigen::MatrixXd m = mass_matrix(model, qv, qdv);
  const Eigen::VectorXd p = momenta(model, qv, qdv);
  const Eigen::VectorXd a = accelerations(model, qv, qdv);
  const double h = energy_function(model, qv, qdv);
  EXPECT_LE((m - exact.mass).lpNorm<Eigen::Infinity>(), 1e-13 * exact.mass.lpNorm<Eigen::Infinity>())
      << which << ", n = " << n;
  const Eigen::VectorXd p_exact = exact.mass * qd;
  EXPECT_LE((p - p_exact).lpNorm<Eigen::Infinity>(), 1e-13 * p_exact.lpNorm<Eigen::Infinity>()) << which << ", n = " << n;
  EXPECT_LE(std::abs(h - exact.energy), 1e-13 * std::abs(exact.energy)) << which << ", n = " << n;
  const double scale = exact.force.lpNorm<Eigen::Infinity>() +
                       exact.mass.lpNorm<Eigen::Infinity>() * a.lpNorm<Eigen::Infinity>();
  EXPECT_LE((exact.mass * a - exact.force).lpNorm<Eigen::Infinity>(), 1e-13 * scale) << which << ", n = " << n;
  return a;
}

// Fixed sizes (one pass; inline Hessians up to 12 coordinates, pooled
// above), the same chain with a run-time size (one pass with numbers of
// fixed width kPaddedWidth up to that many coordinates, at width n above), and the
// hand-coded chain of the benchmarks (M and f by formula, an Eigen LLT).
template <int N>
void every_formulation_agrees() {
  std::mt19937_64 rng(11 + N);
  const State<N> s = test_models::random_chain_state<N>(rng);
  const Eigen::VectorXd q = s.q, qd = s.qd;
  const Eigen::VectorXd fixed = expect_closed_form(models::PendulumChain<N>(1.0, 1.0, 9.81), q, qd, "fixed size");
  const Eigen::VectorXd dyn = expect_closed_form(RuntimeChain{N}, q, qd, "run-time size");
  bench::ChainHand<N> hand;
  Vec<double, N> by_hand;
  hand.qdd(models::PendulumChain<N>(1.0, 1.0, 9.81), s.q, s.qd, by_hand);
  const double tol = 1e-11 * by_hand.template lpNorm<Eigen::Infinity>();
  EXPECT_LE((fixed - Eigen::VectorXd(by_hand)).lpNorm<Eigen::Infinity>(), tol) << "n = " << N;
  EXPECT_LE((dyn - Eigen::VectorXd(by_hand)).lpNorm<Eigen::Infinity>(), tol) << "n = " << N;
}

TEST(ChainsOfEverySize, FixedRunTimeAndHandCodedAgreeWithTheClosedForm) {
  every_formulation_agrees<2>();
  every_formulation_agrees<5>();
  every_formulation_agrees<10>();
  every_formulation_agrees<13>();
  every_formulation_agrees<20>();
  every_formulation_agrees<40>();
}

// Run-time chains of each size at a random state (angles and rates in
// (−1.5, 1.5), the generator seeded with seed + n), against the closed form.
void run_time_chains_agree_with_the_closed_form(std::initializer_list<int> sizes, int seed) {
  for (const int n : sizes) {
    std::mt19937_64 rng(seed + n);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    Eigen::VectorXd q(n), qd(n);
    for (int i = 0; i < n; ++i) {
      q[i] = u(rng);
      qd[i] = u(rng);
    }
    expect_closed_form(RuntimeChain{n}, q, qd, "run-time size");
  }
}

// Run-time sizes up to kRunTimeCapacity take one pass; larger ones the
// block passes, with the same numbers at width 2 kBlock.
TEST(ChainsOfEverySize, RunTimeSizesAroundTheCapacityAgreeWithTheClosedForm) {
  static_assert(detail::kRunTimeCapacity == 64);
  run_time_chains_agree_with_the_closed_form({63, 64, 65, 70}, 5);
}

// Run-time sizes up to kPaddedWidth take numbers of that fixed width, with
// their Hessians inline; above it, numbers of run-time width with pooled
// Hessians. Both sides of the boundary against the closed form.
TEST(ChainsOfEverySize, RunTimeSizesAroundThePaddedWidthAgreeWithTheClosedForm) {
  static_assert(detail::kPaddedWidth == 12);
  run_time_chains_agree_with_the_closed_form({11, 12, 13}, 17);
}

// Small run-time sizes (n = 1, 3, 4: passes with numbers of fixed width
// kPaddedWidth, the directions past n unused) against the library's
// fixed-size chains.
template <int N>
void compare_with_fixed(std::mt19937_64& rng) {
  const models::PendulumChain<N> fixed(1.0, 1.0, 9.81);
  const RuntimeChain dyn{N};
  const State<N> s = test_models::random_chain_state<N>(rng);
  const Vec<double, N> q = s.q, qd = s.qd;
  const Eigen::VectorXd qx = q, qdx = qd;
  const double scale = accelerations(fixed, q, qd).template lpNorm<Eigen::Infinity>();
  EXPECT_LE((accelerations(dyn, qx, qdx) - accelerations(fixed, q, qd)).template lpNorm<Eigen::Infinity>(),
            1e-11 * scale)
      << "n = " << N;
  EXPECT_LE((mass_matrix(dyn, qx, qdx) - mass_matrix(fixed, q, qd)).norm(), 1e-12 * mass_matrix(fixed, q, qd).norm())
      << "n = " << N;
  EXPECT_LE((momenta(dyn, qx, qdx) - momenta(fixed, q, qd)).norm(), 1e-12 * momenta(fixed, q, qd).norm());
  EXPECT_NEAR(energy_function(dyn, qx, qdx), energy_function(fixed, q, qd),
              1e-12 * std::abs(energy_function(fixed, q, qd)));
}

TEST(DynamicSize, SmallSizesMatchTheFixedSize) {
  std::mt19937_64 rng(99);
  compare_with_fixed<1>(rng);
  compare_with_fixed<3>(rng);
  compare_with_fixed<4>(rng);
}

TEST(DynamicSize, SimulationMatchesFixedSize) {
  constexpr int n = 3;  // the library's PendulumChain<3>
  const models::PendulumChain<n> fixed;
  const RuntimeChain dyn{n};
  State<n> x0;
  State<Dynamic> y0(n);
  for (int i = 0; i < n; ++i) {
    x0.q[i] = y0.q[i] = 0.3 - 0.15 * i;
  }
  for (const Method method : {Method::dopri5, Method::rk4, Method::gauss_radau15, Method::rosenbrock4}) {
    SimulationOptions o;
    o.method = method;
    o.t_end = 2.0;
    o.output_interval = 0.5;
    Recorder<n> a;
    Recorder<Dynamic> b;
    const RunReport ra = simulate(fixed, x0, o, a);
    const RunReport rb = simulate(dyn, y0, o, b);
    ASSERT_EQ(a.samples.size(), b.samples.size()) << method;
    for (std::size_t k = 0; k < a.samples.size(); ++k)
      EXPECT_LE((a.samples[k].q - Vec<double, n>(b.samples[k].q)).norm(), 1e-8) << method << " t = " << a.samples[k].t;
    EXPECT_LE(rb.energy_drift_max, 1e-7) << method;
    EXPECT_EQ(rb.coordinates.size(), static_cast<std::size_t>(n));
  }
}

TEST(DynamicSize, DissipationIsDifferentiatedBlockwise) {
  test_models::DampedRuntimeChain dyn{{6}};
  dyn.c = 0.7;
  Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(6, 0.1, 0.6), qd = Eigen::VectorXd::LinSpaced(6, -1.0, 1.5);
  EXPECT_LE((nonconservative_forces(dyn, q, qd) + dyn.c * qd).norm(), 1e-14);
  State<Dynamic> s(6);
  s.q = q;
  s.qd = qd;
  SimulationOptions o;
  o.t_end = 5.0;
  const RunReport r = simulate(dyn, s, o);
  EXPECT_FALSE(r.conservative);
}

TEST(DynamicSize, StateSizeMismatchIsAClearError) {
  const RuntimeChain dyn{4};
  State<Dynamic> s(3);
  try {
    simulate(dyn, s, SimulationOptions{});
    FAIL() << "no error";
  } catch (const OptionError& e) {
    EXPECT_STREQ(e.what(), "initial state has 3 coordinates and 3 velocities; the model has 4");
  }
}

TEST(LargeModels, TwentyCoordinatesDerivativesAgreeWithTheRunTimeSize) { derivatives_agree<20>(); }
TEST(LargeModels, FortyCoordinatesDerivativesAgreeWithTheRunTimeSize) { derivatives_agree<40>(); }
TEST(LargeModels, TwentyCoordinatesSimulateAsTheRunTimeSize) { simulation_agrees<20>(1.0); }
TEST(LargeModels, FortyCoordinatesSimulateAsTheRunTimeSize) { simulation_agrees<40>(0.5); }

}  // namespace
