#include "lagrangian/mechanics/detail/min_norm_solver.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/QR>

namespace lagrangian::detail {

namespace {
// A square A whose LU pivots, with full pivoting, stay above this fraction
// of the largest is regular beyond doubt: its unique solution is the
// minimum-norm one, and the LU factors give it in a fraction of the time of
// the orthogonal decomposition, which is kept for everything else.
constexpr double kRegularPivotRatio = 1e-8;
}  // namespace

struct MinNormSolver::Impl {
  Eigen::Index rows, cols;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  // The solve's workspace: Qᵀb (rows), the solution before the column
  // permutation (cols), and a Householder scratch row (cols).
  Eigen::VectorXd qtb, y, scratch;
  // The LU factors of a regular square A (unit lower L below the diagonal,
  // U on and above), and its row and column interchanges in order.
  bool regular = false;
  Eigen::MatrixXd lu;
  std::vector<Eigen::Index> row_swap, col_swap;
  Impl(int r, int c)
      : rows(r), cols(c), cod(r, c), qtb(r), y(c), scratch(std::max(c, 1)), lu(r == c ? r : 0, r == c ? c : 0),
        row_swap(static_cast<std::size_t>(r == c ? r : 0)), col_swap(static_cast<std::size_t>(r == c ? c : 0)) {}

  /// Gaussian elimination with full pivoting of A into `lu`; true when
  /// every pivot exceeds kRegularPivotRatio times the first (the largest).
  bool factorize_regular(const double* a) {
    const Eigen::Index n = rows;
    lu = Eigen::Map<const Eigen::MatrixXd>(a, n, n);
    double first = 0;
    for (Eigen::Index k = 0; k < n; ++k) {
      Eigen::Index p = k, q = k;
      const double pivot = lu.bottomRightCorner(n - k, n - k).cwiseAbs().maxCoeff(&p, &q);
      if (!(pivot > 0) || !std::isfinite(pivot)) return false;
      if (k == 0) first = pivot;
      if (pivot <= kRegularPivotRatio * first) return false;
      p += k;
      q += k;
      row_swap[static_cast<std::size_t>(k)] = p;
      col_swap[static_cast<std::size_t>(k)] = q;
      if (p != k) lu.row(k).swap(lu.row(p));
      if (q != k) lu.col(k).swap(lu.col(q));
      const Eigen::Index m = n - k - 1;
      lu.col(k).tail(m) /= lu(k, k);
      lu.bottomRightCorner(m, m).noalias() -= lu.col(k).tail(m) * lu.row(k).tail(m);
    }
    return true;
  }

  /// x = A⁻¹ b from the LU factors: b with A's row interchanges, L then U
  /// substitution, and the column interchanges undone.
  void solve_regular(const double* b, double* x) const {
    const Eigen::Index n = rows;
    Eigen::Map<Eigen::VectorXd> z(x, n);
    z = Eigen::Map<const Eigen::VectorXd>(b, n);
    for (Eigen::Index k = 0; k < n; ++k) std::swap(z(k), z(row_swap[static_cast<std::size_t>(k)]));
    lu.triangularView<Eigen::UnitLower>().solveInPlace(z);
    lu.triangularView<Eigen::Upper>().solveInPlace(z);
    for (Eigen::Index k = n - 1; k >= 0; --k) std::swap(z(k), z(col_swap[static_cast<std::size_t>(k)]));
  }
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
  s.regular = threshold <= 0 && s.rows == s.cols && s.rows > 0 && s.factorize_regular(a);
  if (s.regular) return static_cast<int>(s.rows);
  s.cod.compute(Eigen::Map<const Eigen::MatrixXd>(a, s.rows, s.cols));  // copied into its own storage
  return static_cast<int>(s.cod.rank());
}

// x = P Z [T⁻¹ (Qᵀb)(0:r); 0] with A P = Q [T 0; 0 0] Zᵀ... written out from
// the factors, as Eigen's CompleteOrthogonalDecomposition::solve does it, but
// on the workspace: Eigen's solve permutes its result in place through a
// temporary mask on the heap, one allocation per solve.
void MinNormSolver::solve(const double* b, double* x) {
  Impl& s = *impl_;
  if (s.regular) {
    s.solve_regular(b, x);
    return;
  }
  const Eigen::Index rows = s.rows, cols = s.cols;
  const Eigen::Index r = rows == 0 ? 0 : s.cod.rank();
  Eigen::Map<Eigen::VectorXd> out(x, cols);
  if (r == 0) {
    out.setZero();
    return;
  }
  const Eigen::MatrixXd& qtz = s.cod.matrixQTZ();
  // Qᵀb: the first r Householder reflectors of the pivoted QR.
  s.qtb = Eigen::Map<const Eigen::VectorXd>(b, rows);
  const Eigen::VectorXd& tau = s.cod.hCoeffs();
  for (Eigen::Index k = 0; k < r; ++k) {
    s.qtb.tail(rows - k).applyHouseholderOnTheLeft(qtz.col(k).tail(rows - k - 1), tau(k), s.scratch.data());
  }
  // T z = (Qᵀb)(0:r), T the leading r × r upper triangle.
  s.y.head(r) = s.qtb.head(r);
  qtz.topLeftCorner(r, r).triangularView<Eigen::Upper>().solveInPlace(s.y.head(r));
  // y = Z^* [z; 0] when A is rank deficient in its columns.
  if (r < cols) {
    s.y.tail(cols - r).setZero();
    const Eigen::VectorXd& zc = s.cod.zCoeffs();
    for (Eigen::Index k = 0; k < r; ++k) {
      if (k != r - 1) std::swap(s.y(k), s.y(r - 1));
      s.y.segment(r - 1, cols - r + 1)
          .applyHouseholderOnTheLeft(qtz.row(k).tail(cols - r).transpose(), zc(k), s.scratch.data());
      if (k != r - 1) std::swap(s.y(k), s.y(r - 1));
    }
  }
  // x = P y.
  const auto& perm = s.cod.colsPermutation().indices();
  for (Eigen::Index i = 0; i < cols; ++i) out(perm(i)) = s.y(i);
}

}  // namespace lagrangian::detail
