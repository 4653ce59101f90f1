#pragma once
/// \file linearisation.hpp
/// L about rest, the ground of the analyses (analysis.hpp): the effective
/// potential U(q) = −L(q, q̇ = 0, t) (J) with its gradient and Hessian, the
/// second-order expansion of L about (q, 0), the holonomic constraints with
/// their Jacobian and Hessians, and the tangent space of the constraint
/// manifold. AnalysisError is the error of every analysis.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/detail/second_derivatives.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// U(q) = −L(q, 0, t), its gradient and Hessian, by one second-order Jet pass.
struct PotentialDerivatives {
  double value = 0;
  Eigen::VectorXd gradient;
  Eigen::MatrixXd hessian;
};

/// The second-order expansion of L about (q, q̇ = 0): M, K = −∂²L/∂q²,
/// C = ∂²L/∂q̇∂q and ∂L/∂q, from one pass with ad::Jet<double, 2n, 2>.
struct QuadraticLagrangian {
  Eigen::MatrixXd mass;       ///< M = ∂²L/∂q̇² (kg, kg·m²)
  Eigen::MatrixXd stiffness;  ///< K = −∂²L/∂q² = ∇²U
  Eigen::MatrixXd mixed;      ///< C_ij = ∂²L/∂q̇_i∂q_j
  Eigen::VectorXd force;      ///< ∂L/∂q = −∇U
  double potential = 0;       ///< U = −L(q, 0)
};

namespace detail {

// (The fixed-size passes, defined below their public callers.)
template <class M>
PotentialDerivatives potential_derivatives_fixed(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                                 double t);
template <class M>
QuadraticLagrangian quadratic_lagrangian_fixed(const M& model, const Vec<double, coordinate_count_v<M>>& q, double t);

/// Orthonormal basis of the null space of G (m×n), by SVD; the identity for m = 0.
Eigen::MatrixXd tangent_basis(const Eigen::MatrixXd& G, int n);

}  // namespace detail

/// U, ∇U and ∇²U at q (U = −L(q, 0, t), J), by ad::Jet<double, n, 2>.
template <class M>
PotentialDerivatives potential_derivatives(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                           double t = 0.0) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
  if constexpr (n == Dynamic) {
    const int size = static_cast<int>(q.size());
    PotentialDerivatives d;
    detail::second_derivatives_by_blocks(
        size, q,
        [&](const auto& qj) {
          using J = typename std::decay_t<decltype(qj)>::Scalar;
          const Vec<J, Dynamic> zero = Vec<J, Dynamic>::Constant(size, J(0.0));
          return detail::lagrangian_of(model, qj, zero, J(t));
        },
        d.value, d.gradient, d.hessian);
    d.value = -d.value;
    d.gradient = -d.gradient;
    d.hessian = -d.hessian;
    return d;
  } else {
    return detail::potential_derivatives_fixed(model, q, t);
  }
}

namespace detail {
template <class M>
PotentialDerivatives potential_derivatives_fixed(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                                 double t) {
  constexpr int n = coordinate_count_v<M>;
  using J = ad::Jet<double, n, 2>;
  Vec<J, n> qj, zero;
  for (int k = 0; k < n; ++k) {
    qj[k] = J::variable(q[k], k);
    zero[k] = J(0.0);
  }
  const J l = detail::lagrangian_of(model, qj, zero, J(t));
  PotentialDerivatives d;
  d.value = -l.v;
  d.gradient.resize(n);
  d.hessian.resize(n, n);
  for (int i = 0; i < n; ++i) {
    d.gradient[i] = -l.g[i];
    for (int j = 0; j < n; ++j) d.hessian(i, j) = -l.hess(i, j);
  }
  return d;
}
}  // namespace detail

/// The second-order expansion of L about (q, 0) (see QuadraticLagrangian).
template <class M>
QuadraticLagrangian quadratic_lagrangian(const M& model, const Vec<double, coordinate_count_v<M>>& q, double t = 0.0) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
  if constexpr (n == Dynamic) {
    // Variables (q, q̇) at q̇ = 0.
    const int size = static_cast<int>(q.size());
    Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * size);
    x.head(size) = q;
    double value = 0;
    Eigen::VectorXd g;
    Eigen::MatrixXd h;
    detail::second_derivatives_by_blocks(
        2 * size, x,
        [&](const auto& xj) {
          using J = typename std::decay_t<decltype(xj)>::Scalar;
          const Vec<J, Dynamic> qj = xj.head(size), qdj = xj.tail(size);
          return detail::lagrangian_of(model, qj, qdj, J(t));
        },
        value, g, h);
    QuadraticLagrangian r;
    r.potential = -value;
    r.force = g.head(size);
    r.mass = h.bottomRightCorner(size, size);
    r.stiffness = -h.topLeftCorner(size, size);
    r.mixed = h.bottomLeftCorner(size, size);
    return r;
  } else {
    return detail::quadratic_lagrangian_fixed(model, q, t);
  }
}

namespace detail {
template <class M>
QuadraticLagrangian quadratic_lagrangian_fixed(const M& model, const Vec<double, coordinate_count_v<M>>& q, double t) {
  constexpr int n = coordinate_count_v<M>;
  using J = ad::Jet<double, 2 * n, 2>;
  Vec<J, n> qj, qdj;
  for (int k = 0; k < n; ++k) {
    qj[k] = J::variable(q[k], k);
    qdj[k] = J::variable(0.0, n + k);
  }
  const J l = detail::lagrangian_of(model, qj, qdj, J(t));
  QuadraticLagrangian r;
  r.potential = -l.v;
  r.mass.resize(n, n);
  r.stiffness.resize(n, n);
  r.mixed.resize(n, n);
  r.force.resize(n);
  for (int i = 0; i < n; ++i) {
    r.force[i] = l.g[i];
    for (int j = 0; j < n; ++j) {
      r.mass(i, j) = l.hess(n + i, n + j);
      r.stiffness(i, j) = -l.hess(i, j);
      r.mixed(i, j) = l.hess(n + i, j);
    }
  }
  return r;
}
}  // namespace detail

namespace detail {

template <class M>
void refuse_for_equilibria(const M& model) {
  if (pfaffian_count(model) > 0)
    throw AnalysisError("equilibria: the model declares " + std::to_string(pfaffian_count(model)) +
                        " Pfaffian (nonholonomic) constraints; only holonomic constraints are supported");
  if (unilateral_count(model) > 0)
    throw AnalysisError("equilibria: the model declares " + std::to_string(unilateral_count(model)) +
                        " unilateral constraints (contacts); resting contacts are not supported");
  if (uses_generalized_forces(model))
    throw AnalysisError("equilibria: the model declares generalized forces Q, which are not derived from a "
                        "potential; equilibria of U = -L(q, 0) would ignore them");
}

/// λ minimising ‖∇U − Gᵀλ‖ (complete orthogonal decomposition).
Eigen::VectorXd least_squares_multipliers(const Eigen::MatrixXd& G, const Eigen::VectorXd& grad);

/// x = A⁺ b, the least-squares solution of least norm (MinNormSolver).
Eigen::VectorXd min_norm_solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b);

/// The eigenvalues of the symmetric matrix S (lower triangle read),
/// ascending; false when the solver fails.
bool symmetric_eigenvalues(const Eigen::MatrixXd& S, Eigen::VectorXd& eigenvalues);
}  // namespace detail

}  // namespace lagrangian
