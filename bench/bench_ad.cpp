// q̈ by automatic differentiation against hand-coded equations of motion.
#include <benchmark/benchmark.h>

#include "hand_coded.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/models/pendulums.hpp"

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

template <int N>
void BM_Chain_Hand(benchmark::State& st) {
  const PendulumChain<N> p;
  bench::ChainHand<N> hand;
  Vec<double, N> q = Vec<double, N>::LinSpaced(0.1, 0.9), qd = Vec<double, N>::LinSpaced(-0.5, 0.5), qdd;
  for (auto _ : st) {
    q.array() += 1e-9;
    qd[0] += 1e-9;
    benchmark::DoNotOptimize(q.data());
    benchmark::DoNotOptimize(qd.data());
    hand.qdd(p, q, qd, qdd);
    benchmark::DoNotOptimize(qdd.data());
  }
}
BENCHMARK(BM_Chain_Hand<10>);

template <int N>
void BM_Chain_AD(benchmark::State& st) {
  const PendulumChain<N> p;
  lagrangian::Workspace<N> ws;
  Vec<double, N> q = Vec<double, N>::LinSpaced(0.1, 0.9), qd = Vec<double, N>::LinSpaced(-0.5, 0.5), qdd;
  for (auto _ : st) {
    q.array() += 1e-9;
    qd[0] += 1e-9;
    benchmark::DoNotOptimize(q.data());
    benchmark::DoNotOptimize(qd.data());
    lagrangian::accelerations(p, ws, q, qd, 0.0, qdd);
    benchmark::DoNotOptimize(qdd.data());
  }
}
BENCHMARK(BM_Chain_AD<10>);

}  // namespace

BENCHMARK_MAIN();
