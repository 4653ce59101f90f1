#pragma once
// Internal: the Cholesky factors M = L Lᵀ of a mass matrix and solves with
// them, for q̈ = M⁻¹ rhs (dynamics.hpp), the constrained motion's M⁻¹ Cᵀ
// (constrained_accelerations.hpp), impulses (impact.hpp), projections and
// the tangent pass. Plain loops over L's rows (no expression templates):
// the sizes the library's models use are compiled once, in
// src/mechanics/mass_cholesky.cpp, and any other size costs a user's file a
// few small functions, not Eigen's LLT with its blocked kernels.

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include "lagrangian/model.hpp"

namespace lagrangian::detail {

/// Σ a_k b_k over k = 0 … len − 1: a plain loop for short rows, Eigen's
/// vectorised reduction for long ones.
inline double row_dot(const double* a, const double* b, int len) {
  if (len < 8) {
    double s = 0;
    for (int k = 0; k < len; ++k) s += a[k] * b[k];
    return s;
  }
  return Eigen::Map<const Eigen::VectorXd>(a, len).dot(Eigen::Map<const Eigen::VectorXd>(b, len));
}

/// f.template operator()<K>() for K = n, n in [1, kMax]: a size known at
/// run time handed to a kernel compiled for it.
template <int kMax, class F>
decltype(auto) at_run_time_size(int n, F&& f) {
  return [&]<int... K>(std::integer_sequence<int, K...>) {
    using R = decltype(f.template operator()<1>());
    if constexpr (std::is_void_v<R>) {
      (void)((n == K + 1 ? (f.template operator()<K + 1>(), true) : false) || ...);
    } else {
      R r{};
      (void)((n == K + 1 ? (r = f.template operator()<K + 1>(), true) : false) || ...);
      return r;
    }
  }(std::make_integer_sequence<int, kMax>{});
}

/// L Lᵀ = M for K × K M (column-major, its lower triangle read) into L's
/// rows (row-major, lower triangle) and 1 / L_ii: the sums of
/// MassCholesky::compute() in loops of fixed length that the compiler
/// unrolls whole (every bound a constant once the outer loop is unrolled).
template <int K>
bool factor_unrolled(const double* m, double* l, double* inverse, double tolerance) {
  double smallest = 0, largest = 0;
#pragma GCC unroll 16
  for (int j = 0; j < K; ++j) {
    double dot = 0;
#pragma GCC unroll 16
    for (int k = 0; k < j; ++k) dot += l[j * K + k] * l[j * K + k];
    const double s = m[j * K + j] - dot;
    if (!(s > 0) || !(s <= std::numeric_limits<double>::max())) return false;
    const double d = std::sqrt(s);
    l[j * K + j] = d;
    inverse[j] = 1 / d;
    smallest = j == 0 ? s : std::min(smallest, s);
    largest = std::max(largest, s);
#pragma GCC unroll 16
    for (int i = j + 1; i < K; ++i) {
      double t = 0;
#pragma GCC unroll 16
      for (int k = 0; k < j; ++k) t += l[i * K + k] * l[j * K + k];
      l[i * K + j] = (m[j * K + i] - t) * inverse[j];
    }
  }
  return smallest >= tolerance * largest;
}

/// x = (L Lᵀ)⁻¹ b for one right-hand side of K rows (x may be b), unrolled
/// whole as factor_unrolled().
template <int K>
void solve_unrolled(const double* l, const double* inverse, const double* b, double* x) {
  double y[K];
#pragma GCC unroll 16
  for (int i = 0; i < K; ++i) {
    double dot = 0;
#pragma GCC unroll 16
    for (int k = 0; k < i; ++k) dot += l[i * K + k] * y[k];
    y[i] = (b[i] - dot) * inverse[i];
  }
#pragma GCC unroll 16
  for (int i = K - 1; i >= 0; --i) {
    y[i] *= inverse[i];
#pragma GCC unroll 16
    for (int k = 0; k < i; ++k) y[k] -= l[i * K + k] * y[i];
  }
#pragma GCC unroll 16
  for (int i = 0; i < K; ++i) x[i] = y[i];
}

/// L Lᵀ = M for a symmetric positive definite M (its lower triangle read),
/// and x = M⁻¹ b. N may be Dynamic (the size then follows M).
template <int N>
class MassCholesky {
 public:
  /// Factors M. False when M is not positive definite to working
  /// precision: a pivot d_i = L_ii² that is not positive and finite, or
  /// min d / max d below `tolerance`.
  bool compute(const Mat<double, N>& mass, double tolerance);

  /// x = M⁻¹ b for `columns` right-hand sides of n rows each, stored one
  /// column after the other; x may be b.
  void solve(const double* b, double* x, int columns = 1) const;

  /// M⁻¹ B for an n-row matrix B, as a plain matrix of B's shape.
  template <class B>
  auto solve(const Eigen::MatrixBase<B>& b) const {
    constexpr int R = B::RowsAtCompileTime, C = B::ColsAtCompileTime;
    // Column-major (a one-row matrix is row-major, the same layout): column
    // c at c · n.
    Eigen::Matrix<double, R, C, (R == 1 && C != 1) ? Eigen::RowMajor : Eigen::ColMajor, B::MaxRowsAtCompileTime,
                  B::MaxColsAtCompileTime>
        x = b;
    solve(x.data(), x.data(), static_cast<int>(x.cols()));
    return x;
  }

  /// Storage for an n × n M (run-time size), so that compute() allocates
  /// nothing.
  void resize(int n) {
    l_.resize(n, n);
    inverse_.resize(n);
  }

  /// The order n of the last factored M.
  int size() const { return static_cast<int>(inverse_.size()); }

 private:
  /// Largest order whose factorisation and single solve are unrolled whole
  /// (a run-time order up to it takes the kernel of its size).
  static constexpr int kUnrolledMax = 12;

  Eigen::Matrix<double, N, N, (N == 1) ? Eigen::ColMajor : Eigen::RowMajor> l_;  // L, lower triangle
  Vec<double, N> inverse_;                                                         // 1 / L_ii
};

template <int N>
bool MassCholesky<N>::compute(const Mat<double, N>& mass, double tolerance) {
  const int n = static_cast<int>(mass.rows());
  if constexpr (N == Dynamic) {
    if (l_.rows() != n) resize(n);
  }
  const auto unrolled = [&]<int K>() { return factor_unrolled<K>(mass.data(), l_.data(), inverse_.data(), tolerance); };
  if constexpr (N != Dynamic && N <= kUnrolledMax) {
    return unrolled.template operator()<N>();
  } else {  // (the loops below are compiled only for the orders that reach them)
    if constexpr (N == Dynamic) {
      if (n >= 1 && n <= kUnrolledMax) return at_run_time_size<kUnrolledMax>(n, unrolled);
    }
    // L_jj² = M_jj − Σ_{k<j} L_jk², L_ij = (M_ij − Σ_{k<j} L_ik L_jk) / L_jj for i > j.
    double smallest = 0, largest = 0;
    for (int j = 0; j < n; ++j) {
      const double* lj = &l_(j, 0);
      const double s = mass(j, j) - row_dot(lj, lj, j);
      if (!(s > 0) || !(s <= std::numeric_limits<double>::max())) return false;
      const double d = std::sqrt(s);
      l_(j, j) = d;
      inverse_[j] = 1 / d;
      smallest = j == 0 ? s : std::min(smallest, s);
      largest = std::max(largest, s);
      for (int i = j + 1; i < n; ++i) l_(i, j) = (mass(i, j) - row_dot(&l_(i, 0), lj, j)) * inverse_[j];
    }
    return smallest >= tolerance * largest;
  }
}

template <int N>
void MassCholesky<N>::solve(const double* b, double* x, int columns) const {
  // L y = b, then Lᵀ x = y. Four columns at a time through a local block
  // (fixed sizes up to 16), the others one at a time in x's own storage;
  // either way b_i is read before x_i is written, so x may be b. l_ holds
  // L's rows, inverse_ 1 / L_ii.
  const int n = size();
  constexpr int cap = N == Dynamic ? 1 : N;
  const auto sweep = [&]<int W>(const double* bw, double* xw) {
    if constexpr (W == 1) {
      const auto unrolled = [&]<int K>() { solve_unrolled<K>(l_.data(), inverse_.data(), bw, xw); };
      if constexpr (N != Dynamic && N <= kUnrolledMax) {
        return unrolled.template operator()<N>();
      } else {
        if constexpr (N == Dynamic) {
          if (n <= kUnrolledMax) return at_run_time_size<kUnrolledMax>(n, unrolled);
        }
        for (int i = 0; i < n; ++i) xw[i] = (bw[i] - row_dot(&l_(i, 0), xw, i)) * inverse_[i];
        for (int i = n - 1; i >= 0; --i) {
          xw[i] *= inverse_[i];
          const double xi = xw[i];
          const double* li = &l_(i, 0);
          for (int k = 0; k < i; ++k) xw[k] -= li[k] * xi;
        }
      }
    } else {
      double y[cap][W];
      for (int i = 0; i < n; ++i) {
        double s[W];
        for (int w = 0; w < W; ++w) s[w] = bw[w * n + i];
        for (int k = 0; k < i; ++k)
          for (int w = 0; w < W; ++w) s[w] -= l_(i, k) * y[k][w];
        for (int w = 0; w < W; ++w) y[i][w] = s[w] * inverse_[i];
      }
      for (int i = n - 1; i >= 0; --i) {
        for (int w = 0; w < W; ++w) {
          y[i][w] *= inverse_[i];
          xw[w * n + i] = y[i][w];
        }
        for (int k = 0; k < i; ++k)
          for (int w = 0; w < W; ++w) y[k][w] -= l_(i, k) * y[i][w];
      }
    }
  };
  int c = 0;
  if constexpr (N != Dynamic && N <= 16) {
    for (; c + 4 <= columns; c += 4) sweep.template operator()<4>(b + c * n, x + c * n);
  }
  for (; c < columns; ++c) sweep.template operator()<1>(b + c * n, x + c * n);
}

// The sizes of the library's built-in models and of the tangent flow
// (src/mechanics/mass_cholesky.cpp).
extern template class MassCholesky<Dynamic>;
extern template class MassCholesky<1>;
extern template class MassCholesky<2>;
extern template class MassCholesky<3>;
extern template class MassCholesky<4>;
extern template class MassCholesky<5>;
extern template class MassCholesky<6>;
extern template class MassCholesky<7>;
extern template class MassCholesky<8>;
extern template class MassCholesky<9>;
extern template class MassCholesky<10>;

}  // namespace lagrangian::detail
