// The saltation matrix from the impact map's derivatives
// (lagrangian/analysis/saltation.hpp), compiled once.

#include "lagrangian/analysis/saltation.hpp"

#include <Eigen/Core>

namespace lagrangian::detail {

void saltation_from(int n, const double* qd_minus, const double* qdd_minus, const double* qd_plus,
                    const double* qdd_plus, const double* jacobian, const double* gap_gradient, double approach,
                    double* scratch, double* out) {
  using Eigen::Map;
  using Eigen::MatrixXd;
  using Eigen::VectorXd;
  const Map<const VectorXd> dq0(qd_minus, n), a0(qdd_minus, n), dq1(qd_plus, n), a1(qdd_plus, n),
      g(gap_gradient, n);
  const Map<const MatrixXd> j(jacobian, n, 2 * n + 1);
  Map<MatrixXd> s(out, 2 * n, 2 * n);
  // R_x = [[I, 0], [∂q̇⁺/∂q, ∂q̇⁺/∂q̇]].
  s.setZero();
  s.topLeftCorner(n, n).setIdentity();
  s.bottomRows(n) = j.leftCols(2 * n);
  // a = f⁺ − R_x f⁻ − R_t, and S = R_x + a (G, 0) / v.
  Map<VectorXd> a(scratch, 2 * n);
  a.head(n) = dq1 - dq0;
  a.tail(n) = a1 - j.col(2 * n);
  a.tail(n).noalias() -= j.leftCols(n) * dq0;
  a.tail(n).noalias() -= j.middleCols(n, n) * a0;
  s.leftCols(n).noalias() += (a / approach) * g.transpose();
}

}  // namespace lagrangian::detail
