// The tangent flow per call against q̈ alone (docs/performance.md): the
// double pendulum and pendulum chains of 4 and 6 links, q̈ by
// accelerations(), J v along one direction and the whole J by the library
// (ad::EomJet numbers differentiated along the directions) and by the
// nested-Jet derivation of tests/nested_jet_jacobian.hpp (third derivatives
// of L from a second-order Jet over (q, q̇, t)). Every input changes on every
// call. Usage: bench_tangent [Google Benchmark flags]
#include <benchmark/benchmark.h>

#include <cmath>

#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "nested_jet_jacobian.hpp"

namespace {

using lagrangian::Vec;

template <int n>
struct Inputs {
  Vec<double, n> q, qd;
  Eigen::Matrix<double, 2 * n, 1> v;
  Inputs() {
    for (int i = 0; i < n; ++i) {
      q[i] = 0.7 - 0.3 * i;
      qd[i] = 1.1 - 0.2 * i;
    }
    for (int i = 0; i < 2 * n; ++i) v[i] = std::cos(1.0 + 0.7 * i);
  }
  void step() {
    q[0] += 1e-9;
    q[n - 1] -= 1e-9;
    qd[0] += 1e-9;
    benchmark::DoNotOptimize(q.data());
    benchmark::DoNotOptimize(qd.data());
  }
};

template <class M>
void BM_Accelerations(benchmark::State& st) {
  constexpr int n = M::coordinate_count;
  const M model;
  lagrangian::Workspace<n> ws;
  Inputs<n> in;
  Vec<double, n> qdd;
  for (auto _ : st) {
    in.step();
    lagrangian::accelerations(model, ws, in.q, in.qd, 0.0, qdd);
    benchmark::DoNotOptimize(qdd.data());
  }
}

/// J v along one direction (K = 1) or the whole J (K = 2n), by the library
/// or (Nested) by the nested-Jet derivation.
template <class M, int K, bool Nested>
void BM_Tangent(benchmark::State& st) {
  constexpr int n = M::coordinate_count;
  const M model;
  Inputs<n> in;
  Vec<double, n> qdd;
  Eigen::Matrix<double, n, K> jv;
  Eigen::Matrix<double, 2 * n, K> v;
  if constexpr (K == 1) {
    v = in.v;
  } else {
    v.setIdentity();
  }
  for (auto _ : st) {
    in.step();
    if constexpr (Nested) {
      lagrangian::testing::nested_jet_jvp<K>(model, in.q, in.qd, 0.0, v, qdd, jv);
    } else if constexpr (K == 1) {
      lagrangian::state_jvp<1>(model, in.q, in.qd, 0.0, v, qdd, jv);
    } else {
      lagrangian::state_jacobian(model, in.q, in.qd, 0.0, qdd, jv);
    }
    benchmark::DoNotOptimize(jv.data());
  }
}
template <class M>
void BM_Direction(benchmark::State& st) {
  BM_Tangent<M, 1, false>(st);
}
template <class M>
void BM_Direction_NestedJets(benchmark::State& st) {
  BM_Tangent<M, 1, true>(st);
}
template <class M>
void BM_Jacobian(benchmark::State& st) {
  BM_Tangent<M, 2 * M::coordinate_count, false>(st);
}
template <class M>
void BM_Jacobian_NestedJets(benchmark::State& st) {
  BM_Tangent<M, 2 * M::coordinate_count, true>(st);
}

using lagrangian::models::DoublePendulum;
using lagrangian::models::PendulumChain;
BENCHMARK(BM_Accelerations<DoublePendulum>);
BENCHMARK(BM_Direction<DoublePendulum>);
BENCHMARK(BM_Direction_NestedJets<DoublePendulum>);
BENCHMARK(BM_Jacobian<DoublePendulum>);
BENCHMARK(BM_Jacobian_NestedJets<DoublePendulum>);
BENCHMARK(BM_Accelerations<PendulumChain<4>>);
BENCHMARK(BM_Direction<PendulumChain<4>>);
BENCHMARK(BM_Direction_NestedJets<PendulumChain<4>>);
BENCHMARK(BM_Jacobian<PendulumChain<4>>);
BENCHMARK(BM_Jacobian_NestedJets<PendulumChain<4>>);
BENCHMARK(BM_Accelerations<PendulumChain<6>>);
BENCHMARK(BM_Direction<PendulumChain<6>>);
BENCHMARK(BM_Direction_NestedJets<PendulumChain<6>>);
BENCHMARK(BM_Jacobian<PendulumChain<6>>);
BENCHMARK(BM_Jacobian_NestedJets<PendulumChain<6>>);

}  // namespace

BENCHMARK_MAIN();
