#pragma once
// Internal: bases of a constraint manifold's tangent spaces for the tangent
// runs (tangent_system.hpp, lyapunov.cpp, floquet.cpp).

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/analysis/linearisation.hpp"
#include "lagrangian/analysis/lyapunov.hpp"

namespace lagrangian::detail {

/// A basis (2n × d, orthonormal in (q, q̇)) of the tangent space of the
/// constraint manifold of `model` at (q, q̇, t): the null space of
/// H = ∂h/∂(q, q̇), h = (g, ġ, φ), of dimension d = 2n − rank H, the rank
/// as dof_report() judges it (tangent_basis() of linearisation.hpp; 2n for
/// a model without holonomic or Pfaffian constraints: the identity).
inline Eigen::MatrixXd manifold_basis(const TangentModel& model, const double* q, const double* qd, double t) {
  const int n = model.n;
  if (model.manifold == 0) return Eigen::MatrixXd::Identity(2 * n, 2 * n);
  std::vector<double> residual(static_cast<std::size_t>(model.manifold)),
      jacobian(static_cast<std::size_t>(2 * n * model.manifold));
  model.manifold_rows(model.model, q, qd, t, residual.data(), jacobian.data());
  return tangent_basis(Eigen::Map<const Eigen::MatrixXd>(jacobian.data(), model.manifold, 2 * n), 2 * n);
}

/// W R⁻¹ D, D = sign(diag R): the tangent vectors whose reduced canonical
/// coordinates are the orthonormal Q of their QR factors, each keeping its
/// direction (R is the upper triangle of `factors`, QR of the reduced
/// coordinates of W).
inline Eigen::MatrixXd divided_by_r(const Eigen::MatrixXd& w, const Eigen::MatrixXd& factors) {
  const int k = static_cast<int>(w.cols());
  Eigen::MatrixXd wt = w.transpose();
  factors.topLeftCorner(k, k).triangularView<Eigen::Upper>().transpose().solveInPlace(wt);
  Eigen::MatrixXd out = wt.transpose();
  for (int j = 0; j < k; ++j)
    if (factors(j, j) < 0) out.col(j) = -out.col(j);
  return out;
}

}  // namespace lagrangian::detail
