#pragma once
// Internal: a constraint manifold in the tangent runs (tangent_system.hpp,
// lyapunov.cpp, floquet.cpp): bases of its tangent spaces, the projection
// onto it and its reduced canonical coordinates.

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/QR>

#include "lagrangian/analysis/linearisation.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/errors.hpp"
#include "tangent_messages.hpp"

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

/// The constraint manifold h = (g, ġ, φ) = 0 of a TangentModel with
/// holonomic or Pfaffian rows, on the state x of a tangent run (q at x, q̇
/// at x + c): H = ∂h/∂(q, q̇) of its last evaluation and U, an orthonormal
/// basis (n × f) of the configuration's tangent space ker ∂g/∂q (the
/// identity without holonomic rows). Its buffers are sized once.
class TangentManifold {
 public:
  TangentManifold(const TangentModel& model, int coordinates)
      : model_(model), c_(coordinates), residual_(static_cast<std::size_t>(model.manifold)),
        jacobian_(static_cast<std::size_t>(2 * model.n * model.manifold)) {}

  /// ConstraintError naming the first row h_i off zero at x by more than
  /// 1e-9 (1 + ‖q‖∞) or 1e-9 (1 + ‖q̇‖∞), the plain run's test; then H and
  /// U are those of x.
  void check(const double* x, double t) {
    const int n = model_.n, mh = model_.manifold_holonomic;
    evaluate(x, t);
    const Eigen::Map<const Eigen::VectorXd> q(x, n), qd(x + c_, n);
    const double qs = 1.0 + q.lpNorm<Eigen::Infinity>(), vs = 1.0 + qd.lpNorm<Eigen::Infinity>();
    for (int i = 0; i < model_.manifold; ++i) {
      const double h = residual_[static_cast<std::size_t>(i)];
      if (!(std::abs(h) <= 1e-9 * (i < mh ? qs : vs)))
        throw ConstraintError("tangent flow: the initial state violates constraint " +
                              model_.manifold_names[static_cast<std::size_t>(i)] + " (" + short_number(h) +
                              "); use consistent_initial_state() to find the nearest consistent state");
    }
  }
  /// The state of x projected onto the manifold (the model's projection)
  /// and the tangent vectors w onto its tangent space, w ← w − H⁺ (H w):
  /// a renormalisation takes off the drift the integration left (the exact
  /// flow keeps both on it). SimulationError when the projection fails.
  void project(double* x, double t, Eigen::MatrixXd& w) {
    try {
      model_.project(model_.model, x, x + c_, t);
    } catch (const ConstraintError& e) {
      throw SimulationError(std::string("tangent flow: projection onto the constraint manifold failed: ") + e.what(),
                            t);
    }
    evaluate(x, t);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(jacobian());
    w -= cod.solve(jacobian() * w);
  }
  /// H of the last evaluation.
  Eigen::Map<const Eigen::MatrixXd> jacobian() const {
    return Eigen::Map<const Eigen::MatrixXd>(jacobian_.data(), model_.manifold, 2 * model_.n);
  }
  /// The reduced canonical coordinates (Uᵀ δq, Uᵀ δp) of tangent vectors
  /// (the columns of w) of the manifold, δp = (∂p/∂q) δq + M δq̇ (dp =
  /// ∂p/∂(q, q̇) at the state): on the manifold of a holonomic system they
  /// are Darboux coordinates of the symplectic form Σ δq_i ∧ δp_i
  /// restricted to it (δq = U a, Uᵀ δp = b: ω = a₁·b₂ − a₂·b₁), so volumes
  /// in them are phase-space volumes and a Hamiltonian spectrum sums to zero
  /// at every time, as in (q, p) without constraints; they determine a
  /// tangent vector of the manifold (Pfaffian rows too: the map is
  /// injective).
  Eigen::MatrixXd reduced_canonical(const Eigen::MatrixXd& w, const Eigen::Map<const Eigen::MatrixXd>& dp) const {
    const int n = model_.n, f = static_cast<int>(reduce_.cols());
    Eigen::MatrixXd z(2 * f, w.cols());
    z.topRows(f) = reduce_.transpose() * w.topRows(n);
    z.bottomRows(f) = reduce_.transpose() * (dp * w);
    return z;
  }

 private:
  /// h and H at x, and U from H.
  void evaluate(const double* x, double t) {
    const int n = model_.n, mh = model_.manifold_holonomic;
    model_.manifold_rows(model_.model, x, x + c_, t, residual_.data(), jacobian_.data());
    reduce_ = mh == 0 ? Eigen::MatrixXd::Identity(n, n) : tangent_basis(jacobian().topLeftCorner(mh, n), n);
  }

  TangentModel model_;
  int c_;
  std::vector<double> residual_, jacobian_;
  Eigen::MatrixXd reduce_;
};

}  // namespace lagrangian::detail
