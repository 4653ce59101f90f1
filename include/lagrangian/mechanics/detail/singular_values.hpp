#pragma once
// Singular values of a small dense matrix on storage allocated once: the
// one SVD behind the numerical ranks of the DOF report and the conditioning
// monitor evaluated after every step; compiled once in src/mechanics/singular_values.cpp.

#include <memory>

namespace lagrangian::detail {

/// σ_1 ≥ σ_2 ≥ … ≥ 0 of A (rows × cols, column-major), min(rows, cols)
/// values, by Eigen's two-sided Jacobi SVD. Storage is allocated by the
/// constructor; compute() allocates nothing.
class SingularValues {
 public:
  SingularValues(int rows, int cols);
  ~SingularValues();
  SingularValues(const SingularValues& other);
  SingularValues& operator=(const SingularValues& other);

  /// Computes the singular values of A and returns them (size() values,
  /// descending, valid until the next compute()).
  const double* compute(const double* a);
  /// min(rows, cols).
  int size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lagrangian::detail
