// Fixed-size models of 20 and 40 coordinates compile and simulate: their
// derivatives come from block passes (detail::uses_block_passes), and they
// agree with the same chain written with a run-time size, derivative by
// derivative and along a run. They have not opted in to the
// structure-preserving methods, and a run that asks for one is told how.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "runtime_chain.hpp"

namespace {

using namespace lagrangian;
using test_models::RuntimeChain;

template <int N>
void derivatives_agree() {
  static_assert(detail::uses_block_passes<models::PendulumChain<N>>);
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

  o.method = "variational";
  try {
    simulate(fixed, x0, o);
    FAIL() << "variational ran a model that did not opt in";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("structure_preserving = true"), std::string::npos) << e.what();
  }
}

TEST(LargeModels, TwentyCoordinatesDerivativesAgreeWithTheRunTimeSize) { derivatives_agree<20>(); }
TEST(LargeModels, FortyCoordinatesDerivativesAgreeWithTheRunTimeSize) { derivatives_agree<40>(); }
TEST(LargeModels, TwentyCoordinatesSimulateAsTheRunTimeSize) { simulation_agrees<20>(1.0); }
TEST(LargeModels, FortyCoordinatesSimulateAsTheRunTimeSize) { simulation_agrees<40>(0.5); }

}  // namespace
