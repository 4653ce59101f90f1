#pragma once
// Minimum-norm solves of the small saddle-point (KKT) systems of the implicit
// integrators, compiled once in src/kkt.cpp: a complete orthogonal
// decomposition instantiated for every fixed size n + m of every model would
// cost several seconds of compile time each.

#include <memory>

namespace lagrangian::detail {

/// Solves K z = f (K square, column-major, size s) in the least-squares,
/// minimum-norm sense by a complete orthogonal decomposition with column
/// pivoting. Storage is allocated once, by the constructor.
class KktSolver {
 public:
  explicit KktSolver(int size);
  ~KktSolver();
  KktSolver(const KktSolver&) = delete;
  KktSolver& operator=(const KktSolver&) = delete;

  /// Factorises K (s×s, column-major) and returns its numerical rank.
  int factorize(const double* k);
  /// z = K⁺ f for the last factorised K.
  void solve(const double* f, double* z) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lagrangian::detail
