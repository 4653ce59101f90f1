// The last step of the tangent pass, q̈ = M⁻¹ r₀ and
// (J V)_c = M⁻¹ (r_{c+1} − ∂M_c q̈) for K directions, two ways in one run:
// `solve_tangent` (analysis/detail/tangent_solve.hpp, the factors and
// solves compiled once per n in src/analysis/tangent_solve.cpp) and the same
// arithmetic with Eigen's fixed-size LLT, instantiated per model and width
// (what the pass compiled before; the same singular-mass test). M changes on
// every call. Usage: bench_tangent_solve [Google Benchmark flags]
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>

#include <Eigen/Cholesky>

#include "lagrangian/analysis/detail/tangent_solve.hpp"

namespace {

using lagrangian::Mat;
using lagrangian::Vec;

template <int n>
Mat<double, n> positive_definite(double shift) {
  Mat<double, n> a;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) a(i, j) = std::sin(1.3 * i + 0.7 * j + shift);
  return a * a.transpose() + n * Mat<double, n>::Identity();
}

template <int n, int K>
struct Inputs {
  Mat<double, n> mass = positive_definite<n>(0.1);
  Eigen::Matrix<double, n, K + 1> r = Eigen::Matrix<double, n, K + 1>::Constant(0.3);
  std::array<Mat<double, n>, K> dm;
  Vec<double, n> q = Vec<double, n>::Zero(), qdd;
  Eigen::Matrix<double, n, K> jv;
  Inputs() {
    for (int c = 0; c < K; ++c) dm[c] = positive_definite<n>(0.5 + c);
  }
  void step() {
    mass(0, 0) += 1e-12;
    benchmark::DoNotOptimize(mass.data());
  }
};

template <int n, int K>
void EigenFixedSizeLlt(benchmark::State& state) {
  Inputs<n, K> in;
  for (auto _ : state) {
    in.step();
    const Eigen::LLT<Mat<double, n>> llt(in.mass);
    const Vec<double, n> d = llt.matrixL().toDenseMatrix().diagonal();
    if (llt.info() != Eigen::Success ||
        d.minCoeff() * d.minCoeff() < lagrangian::singular_mass_tolerance * d.maxCoeff() * d.maxCoeff())
      state.SkipWithError("not positive definite");
    in.qdd = llt.solve(in.r.col(0));
    Eigen::Matrix<double, n, K> rhs;
    for (int c = 0; c < K; ++c) rhs.col(c) = in.r.col(c + 1) - in.dm[c] * in.qdd;
    in.jv = llt.solve(rhs);
    benchmark::DoNotOptimize(in.jv.data());
  }
}

template <int n, int K>
void SolveTangent(benchmark::State& state) {
  Inputs<n, K> in;
  const auto dmass = [&](int c) -> const Mat<double, n>& { return in.dm[c]; };
  for (auto _ : state) {
    in.step();
    lagrangian::detail::solve_tangent<n, K>(in.mass, in.r, dmass, in.q, in.q, 0.0, in.qdd, in.jv);
    benchmark::DoNotOptimize(in.jv.data());
  }
}

#define LAGRANGIAN_BOTH(n, K)               \
  BENCHMARK(EigenFixedSizeLlt<n, K>);       \
  BENCHMARK(SolveTangent<n, K>);
LAGRANGIAN_BOTH(2, 1)
LAGRANGIAN_BOTH(2, 4)
LAGRANGIAN_BOTH(4, 1)
LAGRANGIAN_BOTH(4, 8)
LAGRANGIAN_BOTH(6, 1)
LAGRANGIAN_BOTH(6, 12)
#undef LAGRANGIAN_BOTH

}  // namespace

BENCHMARK_MAIN();
