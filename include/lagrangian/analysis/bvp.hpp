#pragma once
/// \file bvp.hpp
/// Boundary-value problems by stationary discrete action: the path with
/// q(t0) = a, q(t1) = b on which the discrete Euler–Lagrange equations hold
/// (Newton on the block-tridiagonal Hessian of S_d), and the same action
/// minimised by NLopt for comparison (see analysis.hpp for the equations).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/analysis/detail/action_model.hpp"
#include "lagrangian/integrate/discrete.hpp"
#include "lagrangian/analysis/linearisation.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// Options of solve_bvp().
struct BvpOptions {
  int steps = 200;                       ///< K intervals (≥ 2)
  DiscreteRule rule = DiscreteRule::midpoint;
  double tolerance = 1e-12;              ///< Newton stops when ‖Δq‖∞ ≤ tolerance · (1 + ‖q‖∞)
  int max_iterations = 50;
  /// The problem is called singular (a conjugate point: the path is not
  /// unique) when the smallest |eigenvalue| of the Hessian of S_d is below
  /// this fraction of the lowest eigenvalue of a free particle of the
  /// smallest mass of M(a) on the same grid, m (4/h) sin²(π/2K).
  double singular_fraction = 1e-2;
  /// Initial guess of the path, (K+1)×n rows q_0 … q_K (only the interior is
  /// used); empty: the straight line from a to b.
  Eigen::MatrixXd guess;
  /// Compute the eigenvalues of the Hessian (dense, O((Kn)³)) when Kn ≤ this;
  /// the Morse index comes from an LDLᵀ factorisation in any case.
  int max_dense_eigen = 2000;
};

/// What minimise_action() found.
struct ActionMinimum {
  Eigen::MatrixXd q;          ///< (K+1)×n: the last iterate q_0 … q_K
  double action = 0;          ///< S_d there (J·s)
  double residual = 0;        ///< ‖∇S_d‖∞ there: zero only at a stationary path
  int evaluations = 0;        ///< evaluations of S_d and its gradient
  int nlopt_result = 0;       ///< NLopt's return code (> 0: it reports success)
  bool converged = false;     ///< NLopt reports success, the action is finite and the residual ≤ 1e-8 (1 + ‖p‖∞)
};

/// A path of stationary discrete action.
struct BvpResult {
  std::vector<double> t;           ///< t_0 … t_K (s)
  Eigen::MatrixXd q;               ///< (K+1)×n: q_k
  Eigen::MatrixXd qd;              ///< (K+1)×n: q̇_k from the discrete momenta p_k = D2 L_d(q_{k−1}, q_k) (p_0 = −D1 L_d(q_0, q_1)), q̇ = M⁻¹(p − p(q, 0))
  Eigen::MatrixXd p;               ///< (K+1)×n: discrete momenta p_k
  std::vector<double> energy;      ///< h = p·q̇ − L at each node (J); constant to O(h²) for autonomous L
  double action = 0;               ///< S_d (J·s)
  int iterations = 0;              ///< Newton iterations
  double residual = 0;             ///< ‖D2 L_d + D1 L_d‖∞ at the solution (momentum units)
  int negative_eigenvalues = 0;    ///< Morse index of the Hessian of S_d (0: a local minimum of the action)
  bool eigenvalues_computed = false;
  double lowest_eigenvalue = 0;    ///< smallest eigenvalue of the Hessian (kg/s, or kg·m²/s) when computed
  double smallest_magnitude = 0;   ///< smallest |eigenvalue| when computed
  double free_reference = 0;       ///< m (4/h) sin²(π/2K), the scale of the singularity test
  bool minimum() const { return negative_eigenvalues == 0; }
};
// -- boundary-value problems -------------------------------------------------------

namespace detail {

template <class M>
void refuse_for_bvp(const M& model) {
  if (has_constraints(model))
    throw AnalysisError("stationary action: the model declares " + std::to_string(constraint_count(model)) +
                        " constraints; boundary-value problems are solved for unconstrained models only");
  if (uses_generalized_forces(model) || uses_dissipation(model))
    throw AnalysisError(std::string("stationary action: the model declares ") +
                        (uses_generalized_forces(model) ? "generalized forces Q" : "a dissipation function D") +
                        ", which no action accounts for; boundary-value problems need a conservative model");
}

/// solve_bvp() and minimise_action() on the ActionModel interface (src/analysis/bvp.cpp).
BvpResult bvp_of(const ActionModel& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b, double t0, double t1,
                 const BvpOptions& options);
ActionMinimum action_minimum_of(const ActionModel& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                double t0, double t1, const BvpOptions& options);

}  // namespace detail

/// The path q(t) with q(t0) = a, q(t1) = b that makes the discrete action
/// stationary (see the file comment), by Newton's method from the straight
/// line (or options.guess). Throws OptionError for bad input (sizes, non-finite
/// values, t1 ≤ t0, steps < 2), AnalysisError for models that have no action
/// principle here (constraints, forces, dissipation), when Newton does not
/// converge, and when the problem is singular (t1 − t0 at a conjugate point,
/// e.g. half a period of a harmonic oscillator): the message gives the
/// smallest eigenvalue and its scale.
template <class M>
BvpResult solve_bvp(const M& model, const Vec<double, coordinate_count_v<M>>& a,
                    const Vec<double, coordinate_count_v<M>>& b, double t0, double t1,
                    const BvpOptions& options = {}) {
  check_model<M>();
  detail::refuse_for_bvp(model);
  return detail::bvp_of(detail::ActionModelOf<M>(model), a, b, t0, t1, options);
}


/// The discrete action minimised over the interior points by NLopt's
/// LD_LBFGS from the straight line (gradient: the discrete Euler–Lagrange
/// residuals). Where the action has a minimum this is the path solve_bvp()
/// finds; beyond a conjugate point S_d has no minimum (it is unbounded below
/// along the negative directions of its Hessian for an oscillator) and the
/// minimiser runs away: ActionMinimum::converged is false and the action is
/// below that of the stationary path. Meant for comparison; solve_bvp() is
/// the solver. Same input checks and refusals as solve_bvp().
template <class M>
ActionMinimum minimise_action(const M& model, const Vec<double, coordinate_count_v<M>>& a,
                              const Vec<double, coordinate_count_v<M>>& b, double t0,
                              double t1, const BvpOptions& options = {}) {
  check_model<M>();
  detail::refuse_for_bvp(model);
  return detail::action_minimum_of(detail::ActionModelOf<M>(model), a, b, t0, t1, options);
}

}  // namespace lagrangian
