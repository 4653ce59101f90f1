// The last step of the tangent pass, q̈ = M⁻¹ r₀ and
// (J V)_c = M⁻¹ (r_{c+1} − ∂M_c q̈) for K directions, two ways in one run:
// `solve_tangent` (analysis/detail/tangent_solve.hpp, the factors and
// solves compiled once per n in src/analysis/tangent_solve.cpp) and the same
// arithmetic with Eigen's fixed-size LLT, instantiated per model and width
// (what the pass compiled before; the same singular-mass test). M changes on
// every call. And the step every q̈ of a model with n > 2 coordinates
// takes, M q̈ = rhs (factor and one solve, the singular-mass test included),
// and a constrained model's M⁻¹ Cᵀ for c rows: MassCholesky
// (mechanics/detail/mass_cholesky.hpp) against Eigen's LLT, fixed and
// run-time size. Usage: bench_tangent_solve [Google Benchmark flags]
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <type_traits>

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

/// M q̈ = rhs and M X = Cᵀ (c columns) with the factors of M; N is n or
/// Dynamic (the size then n).
template <int N, int n, int c, bool eigen>
void MassSolve(benchmark::State& state) {
  const Mat<double, n> fixed = positive_definite<n>(0.1);
  Mat<double, N> mass = fixed;
  Vec<double, N> rhs = Vec<double, n>::Constant(0.3), qdd(n);
  Eigen::Matrix<double, N, c> ct = Eigen::Matrix<double, n, c>::Constant(0.2), x(n, c);
  std::conditional_t<eigen, Eigen::LLT<Mat<double, N>>, lagrangian::detail::MassCholesky<N>> llt;
  if constexpr (!eigen) llt.resize(n);
  for (auto _ : state) {
    mass(0, 0) += 1e-12;
    benchmark::DoNotOptimize(mass.data());
    if constexpr (eigen) {
      llt.compute(mass);
      const auto d = llt.matrixLLT().diagonal();
      if (llt.info() != Eigen::Success ||
          d.minCoeff() * d.minCoeff() < lagrangian::singular_mass_tolerance * d.maxCoeff() * d.maxCoeff())
        state.SkipWithError("not positive definite");
      qdd = llt.solve(rhs);
      if constexpr (c > 0) x = llt.solve(ct);
    } else {
      if (!llt.compute(mass, lagrangian::singular_mass_tolerance)) state.SkipWithError("not positive definite");
      llt.solve(rhs.data(), qdd.data());
      if constexpr (c > 0) {
        x = ct;
        llt.solve(x.data(), x.data(), c);
      }
    }
    benchmark::DoNotOptimize(qdd.data());
    benchmark::DoNotOptimize(x.data());
  }
}

#define LAGRANGIAN_MASS(N, n, c)                                                \
  BENCHMARK(MassSolve<N, n, c, true>)->Name("EigenLlt<" #N ", " #n ", " #c ">"); \
  BENCHMARK(MassSolve<N, n, c, false>)->Name("MassCholesky<" #N ", " #n ", " #c ">");
LAGRANGIAN_MASS(3, 3, 0)
LAGRANGIAN_MASS(4, 4, 0)
LAGRANGIAN_MASS(6, 6, 0)
LAGRANGIAN_MASS(10, 10, 0)
LAGRANGIAN_MASS(20, 20, 0)
LAGRANGIAN_MASS(40, 40, 0)
LAGRANGIAN_MASS(-1, 10, 0)
LAGRANGIAN_MASS(-1, 40, 0)
LAGRANGIAN_MASS(4, 4, 1)
LAGRANGIAN_MASS(6, 6, 3)
LAGRANGIAN_MASS(9, 9, 6)
#undef LAGRANGIAN_MASS

}  // namespace

BENCHMARK_MAIN();
