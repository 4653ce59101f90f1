#include "lagrangian/detail/min_norm_solver.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

namespace lagrangian::detail {

namespace {
// Right-hand sides and solutions up to 64 values live on the stack, and so do
// the decomposition's temporaries for them: no allocation per solve.
using Small = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 64, 1>;
}  // namespace

struct MinNormSolver::Impl {
  Eigen::Index rows, cols;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  Impl(int r, int c) : rows(r), cols(c), cod(r, c) {}
};

MinNormSolver::MinNormSolver(int rows, int cols) : impl_(new Impl(rows, cols)) {}
MinNormSolver::~MinNormSolver() = default;
MinNormSolver::MinNormSolver(const MinNormSolver& other) : impl_(new Impl(*other.impl_)) {}
MinNormSolver& MinNormSolver::operator=(const MinNormSolver& other) {
  if (this != &other) *impl_ = *other.impl_;
  return *this;
}

int MinNormSolver::factorize(const double* a, double threshold) {
  Impl& s = *impl_;
  if (threshold > 0) {
    s.cod.setThreshold(threshold);
  } else {
    s.cod.setThreshold(Eigen::Default);
  }
  s.cod.compute(Eigen::Map<const Eigen::MatrixXd>(a, s.rows, s.cols));  // copied into its own storage
  return static_cast<int>(s.cod.rank());
}

void MinNormSolver::solve(const double* b, double* x) const {
  const Impl& s = *impl_;
  const Eigen::Index rows = s.rows, cols = s.cols;
  if (rows == 0) {
    Eigen::Map<Eigen::VectorXd>(x, cols).setZero();
    return;
  }
  if (rows <= 64 && cols <= 64) {
    const Small rhs = Eigen::Map<const Eigen::VectorXd>(b, rows);
    Small sol(cols);
    sol = s.cod.solve(rhs);
    Eigen::Map<Eigen::VectorXd>(x, cols) = sol;
  } else {
    Eigen::Map<Eigen::VectorXd>(x, cols) = s.cod.solve(Eigen::Map<const Eigen::VectorXd>(b, rows).eval());
  }
}

}  // namespace lagrangian::detail
