#pragma once
// Minimum-norm least-squares solves of the small dense systems of the
// constrained dynamics (the Schur complement S = C M⁻¹ Cᵀ, the constraint
// Jacobian of a projection) and of the implicit integrators' saddle-point
// (KKT) systems, compiled once in src/mechanics/min_norm_solver.cpp: a complete
// orthogonal decomposition instantiated for every fixed size of every model
// cost several seconds of compile time each.

#include <memory>

namespace lagrangian::detail {

/// x = A⁺ b: the least-squares solution of least norm of A x = b, for A of
/// rows × cols (column-major), by a complete orthogonal decomposition with
/// column pivoting (rank by Eigen's threshold); a square A that Gaussian
/// elimination with full pivoting shows to be well inside the regular
/// matrices (every pivot above 1e-8 of the first) is solved through those LU
/// factors instead, its one solution. Storage is allocated by the
/// constructor; factorize() and solve() allocate nothing.
class MinNormSolver {
 public:
  MinNormSolver(int rows, int cols);
  explicit MinNormSolver(int size) : MinNormSolver(size, size) {}
  ~MinNormSolver();
  MinNormSolver(const MinNormSolver& other);
  MinNormSolver& operator=(const MinNormSolver& other);

  /// Factorises A (rows × cols, column-major) and returns its numerical
  /// rank: pivots above `threshold` · (largest pivot) count, or Eigen's
  /// default threshold when `threshold` ≤ 0.
  int factorize(const double* a, double threshold = 0.0);
  /// x (cols values) = A⁺ b (rows values) for the last factorised A, on the
  /// solver's own workspace (so one solver serves one thread at a time).
  void solve(const double* b, double* x);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lagrangian::detail
