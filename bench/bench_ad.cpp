// q̈ by automatic differentiation against hand-coded equations of motion.
#include <benchmark/benchmark.h>

#include "hand_coded.hpp"
#include "lagrangian/mechanics/detail/constant_mass.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/two_body.hpp"
#include "lagrangian/text/text_model.hpp"
#include "runtime_chain.hpp"
#include "text_double_pendulum.hpp"

namespace {

using lagrangian::Vec;
using lagrangian::models::DoublePendulum;
using lagrangian::models::PendulumChain;

// Every input changes every iteration and passes through DoNotOptimize, so
// no part of either computation can be hoisted out of the loop.
void BM_DoublePendulum_Hand(benchmark::State& st) {
  const DoublePendulum p;
  double q[2] = {0.7, -0.4}, qd[2] = {1.1, 0.3}, qdd[2];
  for (auto _ : st) {
    q[0] += 1e-9;
    q[1] -= 1e-9;
    qd[0] += 1e-9;
    benchmark::DoNotOptimize(q);
    benchmark::DoNotOptimize(qd);
    bench::double_pendulum_qdd(p, q, qd, qdd);
    benchmark::DoNotOptimize(qdd);
  }
}
BENCHMARK(BM_DoublePendulum_Hand);

// Hand-coded M and f, solved with the same fixed-size LLT the chain uses.
void BM_DoublePendulum_HandLLT(benchmark::State& st) {
  const PendulumChain<2> p;
  bench::ChainHand<2> hand;
  Vec<double, 2> q(0.7, -0.4), qd(1.1, 0.3), qdd;
  for (auto _ : st) {
    q[0] += 1e-9;
    q[1] -= 1e-9;
    qd[0] += 1e-9;
    benchmark::DoNotOptimize(q.data());
    benchmark::DoNotOptimize(qd.data());
    hand.qdd(p, q, qd, qdd);
    benchmark::DoNotOptimize(qdd.data());
  }
}
BENCHMARK(BM_DoublePendulum_HandLLT);

void BM_DoublePendulum_AD(benchmark::State& st) {
  const DoublePendulum p;
  lagrangian::Workspace<2> ws;
  Vec<double, 2> q(0.7, -0.4), qd(1.1, 0.3), qdd;
  for (auto _ : st) {
    q[0] += 1e-9;
    q[1] -= 1e-9;
    qd[0] += 1e-9;
    benchmark::DoNotOptimize(q.data());
    benchmark::DoNotOptimize(qd.data());
    lagrangian::accelerations(p, ws, q, qd, 0.0, qdd);
    benchmark::DoNotOptimize(qdd.data());
  }
}
BENCHMARK(BM_DoublePendulum_AD);

// The same T and V stated as text (text::TextModel: run-time size, the
// expressions walked on the AD numbers at every call).
void BM_DoublePendulum_Text(benchmark::State& st) {
  const lagrangian::text::TextModel p(bench::double_pendulum_text());
  lagrangian::Workspace<lagrangian::Dynamic> ws(2);
  Eigen::VectorXd q = Eigen::Vector2d(0.7, -0.4), qd = Eigen::Vector2d(1.1, 0.3), qdd(2);
  for (auto _ : st) {
    q[0] += 1e-9;
    q[1] -= 1e-9;
    qd[0] += 1e-9;
    benchmark::DoNotOptimize(q.data());
    benchmark::DoNotOptimize(qd.data());
    lagrangian::accelerations(p, ws, q, qd, 0.0, qdd);
    benchmark::DoNotOptimize(qdd.data());
  }
}
BENCHMARK(BM_DoublePendulum_Text);

// Two bodies in Cartesian coordinates (n = 4, M diagonal): q̈ as a run
// takes it (the model declares constant_mass_matrix: M factored once, then
// ∇V alone), as accelerations() gives it (the AD pass for M, ∂L/∂q and the
// mixed term, a diagonal M divided out), and by the general path (the same
// pass, M factored and solved).
lagrangian::models::TwoBody<2> two_body() { return {1.0, 1e-3, lagrangian::models::NewtonianGravity{1e-3}}; }

enum class Path { run, accelerations, general };

template <Path P>
void two_body_qdd(benchmark::State& st) {
  const auto model = two_body();
  lagrangian::Workspace<4> ws;
  Vec<double, 4> q(-2e-4, 0.1, 0.5, -0.2), qd(0.01, -0.03, -1.2, 0.8), qdd;
  lagrangian::detail::ConstantMassAccelerations<lagrangian::models::TwoBody<2>> constant_mass;
  constant_mass.prepare(model, ws, q, qd, 0.0);
  for (auto _ : st) {
    q[0] += 1e-9;
    q[3] -= 1e-9;
    qd[1] += 1e-9;
    benchmark::DoNotOptimize(q.data());
    benchmark::DoNotOptimize(qd.data());
    if constexpr (P == Path::run) {
      constant_mass(model, ws, q, qd, 0.0, qdd);
    } else if constexpr (P == Path::accelerations) {
      lagrangian::accelerations(model, ws, q, qd, 0.0, qdd);
    } else {
      lagrangian::evaluate(model, ws, q, qd, 0.0);
      lagrangian::detail::factor_mass_matrix(ws, q, qd, 0.0);
      qdd = ws.cholesky.solve(ws.rhs);
    }
    benchmark::DoNotOptimize(qdd.data());
  }
}
void BM_TwoBody_ConstantMass(benchmark::State& st) { two_body_qdd<Path::run>(st); }
void BM_TwoBody_AD(benchmark::State& st) { two_body_qdd<Path::accelerations>(st); }
void BM_TwoBody_AD_GeneralSolve(benchmark::State& st) { two_body_qdd<Path::general>(st); }
BENCHMARK(BM_TwoBody_ConstantMass);
BENCHMARK(BM_TwoBody_AD);
BENCHMARK(BM_TwoBody_AD_GeneralSolve);

// N-link pendulum chains: hand-coded M, f + LLT; AD with N fixed at compile
// time; AD with N chosen at run time (the same chain, dof = Dynamic).
template <int N>
Vec<double, N> chain_q() {
  return Vec<double, N>::LinSpaced(N, 0.1, 0.9);
}
template <int N>
Vec<double, N> chain_qd() {
  return Vec<double, N>::LinSpaced(N, -0.5, 0.5);
}

template <int N>
void BM_Chain_Hand(benchmark::State& st) {
  const PendulumChain<N> p;
  bench::ChainHand<N> hand;
  Vec<double, N> q = chain_q<N>(), qd = chain_qd<N>(), qdd;
  for (auto _ : st) {
    q.array() += 1e-9;
    qd[0] += 1e-9;
    benchmark::DoNotOptimize(q.data());
    benchmark::DoNotOptimize(qd.data());
    hand.qdd(p, q, qd, qdd);
    benchmark::DoNotOptimize(qdd.data());
  }
}

// q̈ by AD of the chain `p` with q, q̇ of type V (fixed or run-time size).
template <class Model, class V, int N>
void chain_ad_loop(benchmark::State& st, const Model& p,
                   lagrangian::Workspace<lagrangian::coordinate_count_v<Model>>& ws) {
  V q = chain_q<N>(), qd = chain_qd<N>(), qdd(N);
  for (auto _ : st) {
    q.array() += 1e-9;
    qd[0] += 1e-9;
    benchmark::DoNotOptimize(q.data());
    benchmark::DoNotOptimize(qd.data());
    lagrangian::accelerations(p, ws, q, qd, 0.0, qdd);
    benchmark::DoNotOptimize(qdd.data());
  }
}

template <int N>
void BM_Chain_AD(benchmark::State& st) {
  const PendulumChain<N> p;
  lagrangian::Workspace<N> ws;
  chain_ad_loop<PendulumChain<N>, Vec<double, N>, N>(st, p, ws);
}

template <int N>
void BM_Chain_AD_RunTimeSize(benchmark::State& st) {
  const lagrangian::test_models::RuntimeChain p{N};
  lagrangian::Workspace<lagrangian::Dynamic> ws(N);
  chain_ad_loop<lagrangian::test_models::RuntimeChain, Eigen::VectorXd, N>(st, p, ws);
}

#define LAGRANGIAN_CHAIN_BENCHMARKS(N)           \
  BENCHMARK(BM_Chain_Hand<N>);                   \
  BENCHMARK(BM_Chain_AD<N>);                     \
  BENCHMARK(BM_Chain_AD_RunTimeSize<N>)
LAGRANGIAN_CHAIN_BENCHMARKS(2);
LAGRANGIAN_CHAIN_BENCHMARKS(5);
LAGRANGIAN_CHAIN_BENCHMARKS(10);
LAGRANGIAN_CHAIN_BENCHMARKS(20);
LAGRANGIAN_CHAIN_BENCHMARKS(40);

}  // namespace

BENCHMARK_MAIN();
