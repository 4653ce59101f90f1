#pragma once
/// \file analysis.hpp
/// Analysis beyond simulation: equilibria, small oscillations about them, and
/// boundary-value problems solved by making the discrete action stationary.
///
/// **Effective potential.** Everything here starts from the Lagrangian at
/// rest, U(q) = −L(q, q̇ = 0, t) (J). For a natural system (T quadratic in
/// q̇) U = V; when T has a part T₀ that does not depend on q̇ (a bead on a
/// spinning hoop) U = V − T₀, the potential of the centrifugal field included.
/// q* is an equilibrium (q(t) = q* is a motion) exactly when ∂L/∂q(q*, 0) = 0,
/// i.e. ∇U(q*) = 0; with holonomic constraints g(q) = 0 (m rows, Jacobian G)
///   ∇U(q*) = Gᵀ λ,   g(q*) = 0,
/// where Gᵀλ is the generalized constraint force holding the system at rest
/// (the sign convention of constraints.hpp: M q̈ = f + Cᵀλ).
///
/// **Stability.** With Z an orthonormal basis of the tangent space (the null
/// space of G), the Hessian of U on the constraint manifold is
///   K_t = Zᵀ (∇²U − Σ_i λ_i ∇²g_i) Z      (J per unit², e.g. J/rad², N/m),
/// the constraint curvature term included. K_t positive definite ⇒ q* is a
/// strict minimum of U on the manifold and, by Lagrange–Dirichlet, stable
/// (for natural systems; gyroscopic terms can stabilise more, never less);
/// a negative eigenvalue ⇒ unstable for natural systems.
///
/// **Small oscillations.** Expanding L to second order about (q*, 0) gives
///   M q̈ + G_y q̇ + K q = 0,  M = ∂²L/∂q̇²,  K = −∂²L/∂q² (+ constraint curvature),
///   G_y = C − Cᵀ,  C_ij = ∂²L/∂q̇_i∂q_j    (gyroscopic, zero for natural systems),
/// in tangent coordinates ξ (q = q* + Z ξ). Without G_y the motion is a sum
/// of normal modes: K_t v = ω² M_t v (generalized symmetric eigenproblem),
/// ω in rad/s, shapes v normalised vᵀ M_t v = 1 and reported in the
/// original coordinates Z v. The linear model x = [ξ; ξ̇], ẋ = A x,
///   A = [[0, I], [−M_t⁻¹ K_t, −M_t⁻¹ G_t]]   (1/s, 1/s²),
/// is given for users who want it, with its eigenvalues (growth rates and
/// frequencies with gyroscopic terms).
///
/// **Stationary action.** Given q(t₀) = a and q(t₁) = b, the path on a
/// uniform grid t_k = t₀ + k h, h = (t₁ − t₀)/K, whose discrete action
/// S_d = Σ_k L_d(q_k, q_{k+1}) (J·s, discrete.hpp) is stationary in the
/// interior points q_1 … q_{K−1}: the discrete Euler–Lagrange equations
///   D2 L_d(q_{k−1}, q_k) + D1 L_d(q_k, q_{k+1}) = 0,
/// a block-tridiagonal system solved by Newton's method (its Jacobian is the
/// Hessian of S_d, from D11, D12, D22). Newton finds any stationary point,
/// minimum or saddle; the number of negative eigenvalues of the Hessian (its
/// Morse index) says which. Second-order accurate in h.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <nlopt.h>

#include "lagrangian/ad.hpp"
#include "lagrangian/constraints.hpp"
#include "lagrangian/discrete.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// An analysis cannot be done: the model does not suit it (non-conservative
/// forces for a stationary-action problem, Pfaffian constraints for
/// equilibria), a boundary-value problem is singular, Newton's method did not
/// converge. The message says which and gives the numbers.
class AnalysisError : public Error {
 public:
  using Error::Error;
};

// -- equilibria -------------------------------------------------------------------

/// What kind of stationary point of U (on the constraint manifold) an equilibrium is.
enum class EquilibriumKind {
  minimum,     ///< every eigenvalue of K_t > 0: stable
  saddle,      ///< eigenvalues of both signs: unstable
  maximum,     ///< every eigenvalue < 0: unstable
  degenerate,  ///< no negative eigenvalue but some zero (neutral directions, e.g. a free translation)
};

/// "minimum", "saddle", "maximum", "degenerate".
const char* to_string(EquilibriumKind kind);

/// An equilibrium q* with ∇U(q*) = Gᵀλ, g(q*) = 0.
struct Equilibrium {
  Eigen::VectorXd q;            ///< coordinates (units of each coordinate; periodic ones wrapped to [−P/2, P/2))
  double potential = 0;         ///< U(q*) = −L(q*, 0, t) (J)
  Eigen::VectorXd multipliers;  ///< λ (N for a length constraint), empty when unconstrained
  Eigen::VectorXd hessian_eigenvalues;  ///< of K_t, ascending (J/unit²)
  double residual = 0;          ///< ‖∇U − Gᵀλ‖∞ (N or N·m) at q*
  double constraint_residual = 0;  ///< ‖g(q*)‖∞
  EquilibriumKind kind = EquilibriumKind::degenerate;
  bool stable = false;          ///< kind == minimum
  int zero_eigenvalues = 0;     ///< eigenvalues of K_t counted as zero
  std::string found_by;         ///< "minimisation" (NLopt, then Newton) or "Newton" (on ∇U = Gᵀλ)
};

/// Options of find_equilibria().
struct EquilibriumOptions {
  std::vector<Eigen::VectorXd> starts;  ///< initial guesses (at least one)
  /// Period of each coordinate (2π for an angle), 0 for none; empty: none.
  std::vector<double> periods;
  double t = 0;                     ///< time at which L and g are frozen (s)
  bool minimise = true;             ///< run NLopt (LD_LBFGS, or LD_SLSQP with constraints) from each start
  bool newton = true;               ///< run Newton's method on ∇U = Gᵀλ, g = 0 from each start (finds saddles and maxima)
  double dedupe_tolerance = 1e-6;   ///< equilibria closer than this (∞-norm, relative to 1 + ‖q‖) are one
  double zero_tolerance = 1e-8;     ///< |eigenvalue| ≤ this × max |eigenvalue| counts as zero
  int max_iterations = 100;         ///< Newton iterations per start
};

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

// -- small oscillations -----------------------------------------------------------

/// The linearisation about a configuration q* (see the file comment).
struct Modes {
  Eigen::VectorXd q;               ///< the configuration linearised about
  Eigen::VectorXd multipliers;     ///< λ from ∇U = Gᵀλ (least squares)
  double residual = 0;             ///< ‖∇U − Gᵀλ‖∞: 0 at an equilibrium; otherwise q is not one
  Eigen::MatrixXd mass;            ///< M(q*) in the original coordinates (n×n)
  Eigen::MatrixXd stiffness;       ///< ∇²U − Σλ_i∇²g_i in the original coordinates (n×n)
  Eigen::MatrixXd gyroscopic;      ///< G_y = C − Cᵀ (n×n)
  Eigen::MatrixXd basis;           ///< Z: n×d, orthonormal columns spanning the tangent space (identity without constraints)
  Eigen::MatrixXd tangent_mass;    ///< M_t = Zᵀ M Z (d×d)
  Eigen::MatrixXd tangent_stiffness;  ///< K_t = Zᵀ K Z (d×d)
  Eigen::VectorXd omega_squared;   ///< ω² of K_t v = ω² M_t v, ascending (1/s²); negative: unstable direction
  Eigen::VectorXd omega;           ///< ω = √ω² (rad/s) where ω² ≥ 0 (zero modes exactly 0), NaN where ω² < 0
  Eigen::MatrixXd shapes;          ///< n×d: column j is Z v_j, v_jᵀ M_t v_j = 1
  Eigen::MatrixXd state_matrix;    ///< A (2d×2d), state [ξ; ξ̇] with q = q* + Z ξ
  Eigen::VectorXcd state_eigenvalues;  ///< eigenvalues of A (1/s): ±iω for normal modes
  bool gyroscopic_terms = false;   ///< G_y ≠ 0: the normal modes above ignore it; A and its eigenvalues include it
  int zero_modes = 0;              ///< |ω²| ≤ zero_tolerance · max |ω²|
};

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

/// A table of equilibria for a terminal: U, q, kind, the eigenvalues of K_t
/// and λ; `names` and `units` label the coordinates (units may be empty).
std::string format_equilibria(const std::vector<Equilibrium>& equilibria, const std::vector<std::string>& names,
                              const std::vector<std::string>& units);

/// The normal modes for a terminal: ω (rad/s), frequency (Hz), period (s)
/// and the M-normalised shapes, plus warnings (not an equilibrium, unstable
/// directions, gyroscopic terms).
std::string format_modes(const Modes& modes, const std::vector<std::string>& names,
                         const std::vector<std::string>& units);

namespace detail {

template <class M>
void require_static_size() {
  static_assert(M::dof != Dynamic, "lagrangian: the analyses need a compile-time number of coordinates");
}

/// Wraps periodic coordinates into [−P/2, P/2).
inline void wrap_periodic(Eigen::VectorXd& q, const std::vector<double>& periods) {
  for (int i = 0; i < q.size() && static_cast<std::size_t>(i) < periods.size(); ++i) {
    const double p = periods[static_cast<std::size_t>(i)];
    if (p > 0) {
      q[i] -= p * std::floor(q[i] / p + 0.5);
      if (q[i] >= 0.5 * p) q[i] -= p;
    }
  }
}

/// Orthonormal basis of the null space of G (m×n), by SVD; the identity for m = 0.
inline Eigen::MatrixXd tangent_basis(const Eigen::MatrixXd& G, int n) {
  if (G.rows() == 0) return Eigen::MatrixXd::Identity(n, n);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeFullV);
  const auto& s = svd.singularValues();
  int rank = 0;
  for (int i = 0; i < s.size(); ++i)
    if (s[i] > rank_tolerance * s[0] && s[0] > 0) ++rank;
  return svd.matrixV().rightCols(n - rank);
}

}  // namespace detail

/// U, ∇U and ∇²U at q (U = −L(q, 0, t), J), by ad::Jet<double, n, 2>.
template <class M>
PotentialDerivatives potential_derivatives(const M& model, const Vec<double, M::dof>& q, double t = 0.0) {
  check_model<M>();
  detail::require_static_size<M>();
  constexpr int n = M::dof;
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

/// The second-order expansion of L about (q, 0) (see QuadraticLagrangian).
template <class M>
QuadraticLagrangian quadratic_lagrangian(const M& model, const Vec<double, M::dof>& q, double t = 0.0) {
  check_model<M>();
  detail::require_static_size<M>();
  constexpr int n = M::dof;
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

namespace detail {

/// g(q, t), G = ∂g/∂q and the Hessians ∇²g_i of the holonomic constraints.
struct HolonomicDerivatives {
  Eigen::VectorXd value;
  Eigen::MatrixXd jacobian;
  std::vector<Eigen::MatrixXd> hessians;
};

template <class M>
HolonomicDerivatives holonomic_derivatives(const M& model, const Vec<double, M::dof>& q, double t) {
  constexpr int n = M::dof;
  constexpr int m = holonomic_count_v<M>;
  HolonomicDerivatives d;
  d.value.resize(m);
  d.jacobian.resize(m, n);
  if constexpr (m > 0) {
    using J = ad::Jet<double, n, 2>;
    Vec<J, n> qj;
    for (int k = 0; k < n; ++k) qj[k] = J::variable(q[k], k);
    const auto g = model.holonomic(qj, J(t));
    for (int i = 0; i < m; ++i) {
      d.value[i] = g[i].v;
      Eigen::MatrixXd h(n, n);
      for (int k = 0; k < n; ++k) {
        d.jacobian(i, k) = g[i].g[k];
        for (int j = 0; j < n; ++j) h(k, j) = g[i].hess(k, j);
      }
      d.hessians.push_back(h);
    }
  } else {
    (void)model;
    (void)q;
    (void)t;
  }
  return d;
}

template <class M>
void refuse_for_equilibria(const M&) {
  if constexpr (pfaffian_count_v<M> > 0)
    throw AnalysisError("equilibria: the model declares " + std::to_string(pfaffian_count_v<M>) +
                        " Pfaffian (nonholonomic) constraints; only holonomic constraints are supported");
  if constexpr (unilateral_count_v<M> > 0)
    throw AnalysisError("equilibria: the model declares " + std::to_string(unilateral_count_v<M>) +
                        " unilateral constraints (contacts); resting contacts are not supported");
  if constexpr (has_generalized_forces_v<M>)
    throw AnalysisError("equilibria: the model declares generalized forces Q, which are not derived from a "
                        "potential; equilibria of U = -L(q, 0) would ignore them");
}

/// λ minimising ‖∇U − Gᵀλ‖ (complete orthogonal decomposition).
inline Eigen::VectorXd least_squares_multipliers(const Eigen::MatrixXd& G, const Eigen::VectorXd& grad) {
  if (G.rows() == 0) return Eigen::VectorXd();
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(G.transpose());
  return cod.solve(grad);
}

/// Newton's method on F(q, λ) = [∇U − Gᵀλ; g] = 0 from q (projected onto g = 0 first).
/// Returns true and writes q, λ when it converges.
template <class M>
bool newton_equilibrium(const M& model, Vec<double, M::dof>& q, Eigen::VectorXd& lambda, double t,
                        int max_iterations) {
  constexpr int n = M::dof;
  constexpr int m = holonomic_count_v<M>;
  try {
    if constexpr (m > 0) project_positions(model, q, t, 1e-12, 50, ActiveSet{0});
  } catch (const ConstraintError&) {
    return false;
  }
  auto evaluate = [&](const Vec<double, n>& x, const Eigen::VectorXd& lam, Eigen::VectorXd& F, Eigen::MatrixXd* Jac) {
    const PotentialDerivatives u = potential_derivatives(model, x, t);
    const HolonomicDerivatives c = holonomic_derivatives(model, x, t);
    F.resize(n + m);
    F.head(n) = u.gradient;
    if (m > 0) {
      F.head(n) -= c.jacobian.transpose() * lam;
      F.tail(m) = c.value;
    }
    if (Jac) {
      Jac->setZero(n + m, n + m);
      Eigen::MatrixXd H = u.hessian;
      for (int i = 0; i < m; ++i) H -= lam[i] * c.hessians[static_cast<std::size_t>(i)];
      Jac->topLeftCorner(n, n) = H;
      if (m > 0) {
        Jac->topRightCorner(n, m) = -c.jacobian.transpose();
        Jac->bottomLeftCorner(m, n) = c.jacobian;
      }
    }
    return u;
  };
  {
    const PotentialDerivatives u = potential_derivatives(model, q, t);
    lambda = least_squares_multipliers(holonomic_derivatives(model, q, t).jacobian, u.gradient);
  }
  Eigen::VectorXd F;
  Eigen::MatrixXd Jac;
  evaluate(q, lambda, F, &Jac);
  double force_scale = Jac.topLeftCorner(n, n).cwiseAbs().maxCoeff() * (1.0 + q.template lpNorm<Eigen::Infinity>()) +
                       F.head(n).template lpNorm<Eigen::Infinity>();
  if (!(force_scale > 0)) force_scale = 1.0;
  for (int it = 0; it < max_iterations; ++it) {
    if (!F.allFinite() || !Jac.allFinite()) return false;
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(Jac);
    const Eigen::VectorXd step = cod.solve(-F);
    if (!step.allFinite()) return false;
    // Backtracking on ‖F‖ (at most 20 halvings).
    const double f0 = F.norm();
    double alpha = 1.0;
    Vec<double, n> qn;
    Eigen::VectorXd ln, Fn;
    for (int b = 0; b < 20; ++b) {
      qn = q + alpha * step.head(n);
      ln = m > 0 ? Eigen::VectorXd(lambda + alpha * step.tail(m)) : lambda;
      evaluate(qn, ln, Fn, nullptr);
      if (Fn.allFinite() && Fn.norm() <= (1 - 1e-4 * alpha) * f0) break;
      alpha *= 0.5;
    }
    if (!Fn.allFinite()) return false;
    const double dq = (alpha * step.head(n)).template lpNorm<Eigen::Infinity>();
    q = qn;
    lambda = ln;
    evaluate(q, lambda, F, &Jac);
    if (dq <= 1e-13 * (1.0 + q.template lpNorm<Eigen::Infinity>())) break;
  }
  const double res = F.head(n).template lpNorm<Eigen::Infinity>();
  const double cres = m > 0 ? F.tail(m).template lpNorm<Eigen::Infinity>() : 0.0;
  return res <= 1e-9 * force_scale && cres <= 1e-10 * (1.0 + q.template lpNorm<Eigen::Infinity>());
}

template <class M>
struct MinimisationProblem {
  const M* model;
  double t;
};

template <class M>
double minimisation_objective(unsigned n, const double* x, double* grad, void* data) {
  const auto& p = *static_cast<const MinimisationProblem<M>*>(data);
  Vec<double, M::dof> q;
  for (unsigned i = 0; i < n; ++i) q[static_cast<int>(i)] = x[i];
  const PotentialDerivatives u = potential_derivatives(*p.model, q, p.t);
  if (grad)
    for (unsigned i = 0; i < n; ++i) grad[i] = u.gradient[static_cast<int>(i)];
  return u.value;
}

template <class M>
void minimisation_constraints(unsigned m, double* result, unsigned n, const double* x, double* grad, void* data) {
  const auto& p = *static_cast<const MinimisationProblem<M>*>(data);
  Vec<double, M::dof> q;
  for (unsigned i = 0; i < n; ++i) q[static_cast<int>(i)] = x[i];
  const HolonomicDerivatives c = holonomic_derivatives(*p.model, q, p.t);
  for (unsigned i = 0; i < m; ++i) {
    result[i] = c.value[static_cast<int>(i)];
    if (grad)
      for (unsigned k = 0; k < n; ++k) grad[i * n + k] = c.jacobian(static_cast<int>(i), static_cast<int>(k));
  }
}

/// Minimises U from q with NLopt (LD_LBFGS, or LD_SLSQP under constraints); false on failure.
template <class M>
bool minimise_potential(const M& model, Vec<double, M::dof>& q, double t) {
  constexpr int n = M::dof;
  constexpr int m = holonomic_count_v<M>;
  MinimisationProblem<M> problem{&model, t};
  std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(
      nlopt_create(m > 0 ? NLOPT_LD_SLSQP : NLOPT_LD_LBFGS, n), &nlopt_destroy);
  if (!opt) return false;
  nlopt_set_min_objective(opt.get(), &minimisation_objective<M>, &problem);
  if constexpr (m > 0) {
    std::vector<double> tol(static_cast<std::size_t>(m), 1e-12);
    nlopt_add_equality_mconstraint(opt.get(), m, &minimisation_constraints<M>, &problem, tol.data());
  }
  nlopt_set_xtol_rel(opt.get(), 1e-12);
  nlopt_set_ftol_abs(opt.get(), 0.0);
  nlopt_set_maxeval(opt.get(), 3000);
  std::vector<double> x(q.data(), q.data() + n);
  double f = 0;
  const nlopt_result r = nlopt_optimize(opt.get(), x.data(), &f);
  if (!(r > 0 || r == NLOPT_ROUNDOFF_LIMITED || r == NLOPT_MAXEVAL_REACHED)) return false;
  for (int i = 0; i < n; ++i) q[i] = x[static_cast<std::size_t>(i)];
  return q.allFinite() && std::isfinite(f);
}

/// Classifies a converged equilibrium: U, K_t and its eigenvalues.
template <class M>
Equilibrium classify_equilibrium(const M& model, const Vec<double, M::dof>& q, const Eigen::VectorXd& lambda,
                                 double t, double zero_tolerance) {
  constexpr int n = M::dof;
  const PotentialDerivatives u = potential_derivatives(model, q, t);
  const HolonomicDerivatives c = holonomic_derivatives(model, q, t);
  Eigen::MatrixXd K = u.hessian;
  for (int i = 0; i < c.value.size(); ++i) K -= lambda[i] * c.hessians[static_cast<std::size_t>(i)];
  const Eigen::MatrixXd Z = tangent_basis(c.jacobian, n);
  const Eigen::MatrixXd Kt = Z.transpose() * K * Z;
  Equilibrium e;
  e.q = q;
  e.potential = u.value;
  e.multipliers = lambda;
  e.residual = (u.gradient - (c.value.size() ? Eigen::VectorXd(c.jacobian.transpose() * lambda)
                                             : Eigen::VectorXd::Zero(n)))
                   .template lpNorm<Eigen::Infinity>();
  e.constraint_residual = c.value.size() ? c.value.template lpNorm<Eigen::Infinity>() : 0.0;
  if (Kt.rows() > 0) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (Kt + Kt.transpose()), Eigen::EigenvaluesOnly);
    e.hessian_eigenvalues = es.eigenvalues();
  }
  const double scale = e.hessian_eigenvalues.size() ? e.hessian_eigenvalues.cwiseAbs().maxCoeff() : 0.0;
  int neg = 0, pos = 0, zero = 0;
  for (int i = 0; i < e.hessian_eigenvalues.size(); ++i) {
    const double v = e.hessian_eigenvalues[i];
    if (std::abs(v) <= zero_tolerance * scale) ++zero;
    else if (v < 0) ++neg;
    else ++pos;
  }
  e.zero_eigenvalues = zero;
  e.kind = neg > 0 ? (pos > 0 || zero > 0 ? EquilibriumKind::saddle : EquilibriumKind::maximum)
                   : (zero > 0 ? EquilibriumKind::degenerate : EquilibriumKind::minimum);
  e.stable = e.kind == EquilibriumKind::minimum;
  return e;
}

}  // namespace detail

/// Equilibria of `model` (stationary points of U = −L(q, 0, t) on g(q) = 0)
/// from every start in `options`: NLopt minimisation (polished by Newton)
/// finds minima; Newton's method on ∇U = Gᵀλ, g = 0 also finds saddles and
/// maxima near a start. Duplicates (within dedupe_tolerance, periodic
/// coordinates wrapped) are merged; the result is sorted by U. Each is
/// classified by the eigenvalues of K_t. Throws AnalysisError for models with
/// Pfaffian or unilateral constraints or generalized forces, and OptionError
/// for no start or a start of the wrong size or not finite.
template <class M>
std::vector<Equilibrium> find_equilibria(const M& model, const EquilibriumOptions& options) {
  check_model<M>();
  detail::require_static_size<M>();
  detail::refuse_for_equilibria(model);
  constexpr int n = M::dof;
  if (options.starts.empty()) throw OptionError("equilibria: starts: at least one start is needed");
  for (std::size_t s = 0; s < options.starts.size(); ++s) {
    if (options.starts[s].size() != n)
      throw OptionError("equilibria: starts[" + std::to_string(s) + "]: has " +
                        std::to_string(options.starts[s].size()) + " values, the model has " + std::to_string(n) +
                        " coordinates");
    if (!options.starts[s].allFinite())
      throw OptionError("equilibria: starts[" + std::to_string(s) + "]: not finite");
  }
  std::vector<Equilibrium> found;
  auto add = [&](const Vec<double, n>& q, const Eigen::VectorXd& lambda, const char* how) {
    Equilibrium e = detail::classify_equilibrium(model, q, lambda, options.t, options.zero_tolerance);
    e.found_by = how;
    detail::wrap_periodic(e.q, options.periods);
    for (const Equilibrium& f : found) {
      Eigen::VectorXd d = e.q - f.q;
      detail::wrap_periodic(d, options.periods);
      if (d.template lpNorm<Eigen::Infinity>() <= options.dedupe_tolerance * (1.0 + e.q.template lpNorm<Eigen::Infinity>()))
        return;
    }
    found.push_back(std::move(e));
  };
  for (const Eigen::VectorXd& start : options.starts) {
    if (options.minimise) {
      Vec<double, n> q = start;
      Eigen::VectorXd lambda;
      if (detail::minimise_potential(model, q, options.t) &&
          detail::newton_equilibrium(model, q, lambda, options.t, options.max_iterations))
        add(q, lambda, "minimisation");
    }
    if (options.newton) {
      Vec<double, n> q = start;
      Eigen::VectorXd lambda;
      if (detail::newton_equilibrium(model, q, lambda, options.t, options.max_iterations)) add(q, lambda, "Newton");
    }
  }
  std::stable_sort(found.begin(), found.end(),
                   [](const Equilibrium& a, const Equilibrium& b) { return a.potential < b.potential; });
  return found;
}

/// The linearisation about q (normally an equilibrium; Modes::residual says
/// how far from one it is): M, K with the constraint curvature, the tangent
/// basis, normal modes and the state matrix A. Zero modes (|ω²| ≤
/// zero_tolerance · max|ω²|) are reported as ω = 0. Throws AnalysisError when
/// M_t is not positive definite.
template <class M>
Modes small_oscillations(const M& model, const Vec<double, M::dof>& q, double t = 0.0,
                         double zero_tolerance = 1e-9) {
  check_model<M>();
  detail::require_static_size<M>();
  detail::refuse_for_equilibria(model);
  constexpr int n = M::dof;
  const QuadraticLagrangian ql = quadratic_lagrangian(model, q, t);
  const detail::HolonomicDerivatives c = detail::holonomic_derivatives(model, q, t);
  Modes md;
  md.q = q;
  const Eigen::VectorXd grad = -ql.force;
  md.multipliers = detail::least_squares_multipliers(c.jacobian, grad);
  md.residual = (c.value.size() ? Eigen::VectorXd(grad - c.jacobian.transpose() * md.multipliers) : grad)
                    .template lpNorm<Eigen::Infinity>();
  md.mass = ql.mass;
  md.stiffness = ql.stiffness;
  for (int i = 0; i < c.value.size(); ++i) md.stiffness -= md.multipliers[i] * c.hessians[static_cast<std::size_t>(i)];
  md.gyroscopic = ql.mixed - ql.mixed.transpose();
  md.basis = detail::tangent_basis(c.jacobian, n);
  const Eigen::MatrixXd& Z = md.basis;
  const int d = static_cast<int>(Z.cols());
  md.tangent_mass = Z.transpose() * md.mass * Z;
  md.tangent_stiffness = Z.transpose() * md.stiffness * Z;
  md.tangent_mass = 0.5 * (md.tangent_mass + md.tangent_mass.transpose()).eval();
  md.tangent_stiffness = 0.5 * (md.tangent_stiffness + md.tangent_stiffness.transpose()).eval();
  const Eigen::MatrixXd Gt = Z.transpose() * md.gyroscopic * Z;
  const double mscale = md.mass.cwiseAbs().maxCoeff();
  md.gyroscopic_terms = Gt.cwiseAbs().maxCoeff() > 1e-12 * std::max(1.0, mscale);
  if (d == 0) return md;
  Eigen::LLT<Eigen::MatrixXd> llt(md.tangent_mass);
  if (llt.info() != Eigen::Success)
    throw AnalysisError("small oscillations: the mass matrix on the tangent space is not positive definite");
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(md.tangent_stiffness, md.tangent_mass);
  if (ges.info() != Eigen::Success) throw AnalysisError("small oscillations: the eigenproblem K v = w^2 M v failed");
  md.omega_squared = ges.eigenvalues();
  const double wscale = md.omega_squared.cwiseAbs().maxCoeff();
  md.omega.resize(d);
  for (int j = 0; j < d; ++j) {
    double& w2 = md.omega_squared[j];
    if (std::abs(w2) <= zero_tolerance * wscale) {
      w2 = 0.0;
      ++md.zero_modes;
    }
    md.omega[j] = w2 >= 0 ? std::sqrt(w2) : std::numeric_limits<double>::quiet_NaN();
  }
  // Eigen normalises generalized eigenvectors to vᵀ M v = 1.
  md.shapes = Z * ges.eigenvectors();
  for (int j = 0; j < d; ++j) {  // sign: largest component positive
    Eigen::Index imax = 0;
    md.shapes.col(j).cwiseAbs().maxCoeff(&imax);
    if (md.shapes(imax, j) < 0) md.shapes.col(j) *= -1.0;
  }
  md.state_matrix.setZero(2 * d, 2 * d);
  md.state_matrix.topRightCorner(d, d).setIdentity();
  md.state_matrix.bottomLeftCorner(d, d) = -llt.solve(md.tangent_stiffness);
  md.state_matrix.bottomRightCorner(d, d) = -llt.solve(Gt);
  Eigen::EigenSolver<Eigen::MatrixXd> es(md.state_matrix, false);
  md.state_eigenvalues = es.eigenvalues();
  return md;
}

// -- boundary-value problems -------------------------------------------------------

namespace detail {

template <class M>
void refuse_for_bvp(const M&) {
  if constexpr (has_constraints_v<M>)
    throw AnalysisError("stationary action: the model declares " + std::to_string(constraint_count_v<M>) +
                        " constraints; boundary-value problems are solved for unconstrained models only");
  if constexpr (has_generalized_forces_v<M> || has_dissipation_v<M>)
    throw AnalysisError("stationary action: the model declares " +
                        std::string(has_generalized_forces_v<M> ? "generalized forces Q" : "a dissipation function D") +
                        ", which no action accounts for; boundary-value problems need a conservative model");
}

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
BvpResult solve_bvp(const M& model, const Vec<double, M::dof>& a, const Vec<double, M::dof>& b, double t0, double t1,
                    const BvpOptions& options = {}) {
  check_model<M>();
  detail::require_static_size<M>();
  detail::refuse_for_bvp(model);
  constexpr int n = M::dof;
  const int K = options.steps;
  if (!a.allFinite()) throw OptionError("stationary action: from: not finite");
  if (!b.allFinite()) throw OptionError("stationary action: to: not finite");
  if (!std::isfinite(t0) || !std::isfinite(t1) || !(t1 > t0))
    throw OptionError("stationary action: time: need finite t0 < t1, got t0 = " + std::to_string(t0) +
                      " s, t1 = " + std::to_string(t1) + " s");
  if (K < 2) throw OptionError("stationary action: steps: need at least 2, got " + std::to_string(K));
  if (options.guess.size() != 0 && (options.guess.rows() != K + 1 || options.guess.cols() != n))
    throw OptionError("stationary action: guess: must be (steps + 1) x n");
  const double h = (t1 - t0) / K;
  const int N = (K - 1) * n;
  Eigen::MatrixXd Q(K + 1, n);
  for (int k = 0; k <= K; ++k) {
    if (options.guess.size() != 0 && k > 0 && k < K) {
      Q.row(k) = options.guess.row(k);
    } else {
      const double s = static_cast<double>(k) / K;
      Q.row(k) = ((1 - s) * a + s * b).transpose();
    }
  }
  auto node = [&](int k) -> Vec<double, n> { return Q.row(k).transpose(); };
  std::vector<DiscreteLagrangian<n>> seg(static_cast<std::size_t>(K));
  Eigen::VectorXd R(N);
  Eigen::SparseMatrix<double> H(N, N);
  auto assemble = [&](bool jacobian) {
    for (int k = 0; k < K; ++k)
      seg[static_cast<std::size_t>(k)] = discrete_lagrangian_derivatives(model, node(k), node(k + 1), t0 + k * h, h,
                                                                         options.rule);
    std::vector<Eigen::Triplet<double>> trip;
    if (jacobian) trip.reserve(static_cast<std::size_t>(3 * n * n * (K - 1)));
    for (int k = 1; k < K; ++k) {
      const auto& prev = seg[static_cast<std::size_t>(k - 1)];
      const auto& next = seg[static_cast<std::size_t>(k)];
      const int r = (k - 1) * n;
      R.segment(r, n) = prev.d2 + next.d1;
      if (!jacobian) continue;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          trip.emplace_back(r + i, r + j, prev.d22(i, j) + next.d11(i, j));
          if (k > 1) trip.emplace_back(r + i, r - n + j, prev.d12(j, i));
          if (k < K - 1) trip.emplace_back(r + i, r + n + j, next.d12(i, j));
        }
    }
    if (jacobian) H.setFromTriplets(trip.begin(), trip.end());
  };
  BvpResult out;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  bool converged = false;
  assemble(true);
  for (int it = 0; it < options.max_iterations; ++it) {
    if (!R.allFinite()) break;
    ldlt.compute(H);
    if (ldlt.info() != Eigen::Success) break;
    const Eigen::VectorXd dx = ldlt.solve(-R);
    if (!dx.allFinite()) break;
    // Backtracking on ‖R‖ when a full step makes it grow by more than 10×
    // (Newton is otherwise left free: near a saddle ‖R‖ need not fall monotonically).
    const Eigen::MatrixXd Q0 = Q;
    const double r0 = R.norm();
    double alpha = 1.0;
    for (int bt = 0; bt < 30; ++bt) {
      for (int k = 1; k < K; ++k) Q.row(k) = Q0.row(k) + alpha * dx.segment((k - 1) * n, n).transpose();
      assemble(false);
      if (R.allFinite() && (R.norm() <= 10 * r0 || r0 == 0)) break;
      alpha *= 0.5;
    }
    assemble(true);
    ++out.iterations;
    if ((alpha * dx).template lpNorm<Eigen::Infinity>() <= options.tolerance * (1.0 + Q.template lpNorm<Eigen::Infinity>())) {
      converged = true;
      break;
    }
  }
  out.residual = R.template lpNorm<Eigen::Infinity>();
  // Morse index from the LDLᵀ factorisation of the Hessian at the solution
  // (Sylvester's law of inertia: the permutation is symmetric).
  ldlt.compute(H);
  if (ldlt.info() == Eigen::Success) {
    const Eigen::VectorXd D = ldlt.vectorD();
    out.negative_eigenvalues = static_cast<int>((D.array() < 0).count());
  }
  const Mat<double, n> Ma = mass_matrix(model, a, Vec<double, n>::Zero(), t0);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> mes(Eigen::MatrixXd(Ma), Eigen::EigenvaluesOnly);
  const double pi = 3.141592653589793;
  out.free_reference = mes.eigenvalues()[0] * (4.0 / h) * std::pow(std::sin(pi / (2.0 * K)), 2);
  if (N <= options.max_dense_eigen && Eigen::Map<const Eigen::VectorXd>(H.valuePtr(), H.nonZeros()).allFinite()) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Eigen::MatrixXd(H), Eigen::EigenvaluesOnly);
    if (es.info() == Eigen::Success) {
      out.eigenvalues_computed = true;
      out.lowest_eigenvalue = es.eigenvalues()[0];
      out.smallest_magnitude = es.eigenvalues().cwiseAbs().minCoeff();
      out.negative_eigenvalues = static_cast<int>((es.eigenvalues().array() < 0).count());
    }
  }
  std::ostringstream why;
  why.precision(6);
  const bool singular = out.eigenvalues_computed
                            ? out.smallest_magnitude < options.singular_fraction * out.free_reference
                            : ldlt.info() != Eigen::Success;
  if (singular) {
    why << "stationary action: the boundary-value problem is singular over t1 - t0 = " << (t1 - t0)
        << " s (a conjugate point: the Hessian of the discrete action has an eigenvalue " << out.smallest_magnitude
        << " in magnitude, below " << options.singular_fraction << " x " << out.free_reference
        << ", the lowest eigenvalue of a free particle on the same grid); the path between the two end points is "
           "not unique or does not exist — change the time span or the end points";
    throw AnalysisError(why.str());
  }
  if (!converged || !Q.allFinite()) {
    why << "stationary action: Newton's method did not converge in " << out.iterations
        << " iterations (residual of the discrete Euler-Lagrange equations " << out.residual
        << "); try more steps or a different time span";
    throw AnalysisError(why.str());
  }
  // Path, momenta, velocities, energy.
  out.t.resize(static_cast<std::size_t>(K + 1));
  out.q = Q;
  out.p.resize(K + 1, n);
  out.qd.resize(K + 1, n);
  out.energy.resize(static_cast<std::size_t>(K + 1));
  out.action = 0;
  for (int k = 0; k < K; ++k) out.action += seg[static_cast<std::size_t>(k)].value;
  for (int k = 0; k <= K; ++k) {
    out.t[static_cast<std::size_t>(k)] = k == K ? t1 : t0 + k * h;
    const Vec<double, n> pk = k == 0 ? Vec<double, n>(-seg[0].d1) : Vec<double, n>(seg[static_cast<std::size_t>(k - 1)].d2);
    out.p.row(k) = pk.transpose();
    const Vec<double, n> qk = node(k);
    const double tk = out.t[static_cast<std::size_t>(k)];
    const Vec<double, n> zero = Vec<double, n>::Zero();
    const Mat<double, n> Mk = mass_matrix(model, qk, zero, tk);
    const Vec<double, n> p0 = momenta(model, qk, zero, tk);
    const Eigen::LLT<Mat<double, n>> llt(Mk);
    const Vec<double, n> v = llt.solve(pk - p0);
    if (llt.info() != Eigen::Success || !v.allFinite()) {
      std::ostringstream os;
      os.precision(17);
      os << "stationary action: the path was found, but the mass matrix is singular at node " << k << " ("
         << detail::describe_state(qk, zero, tk) << "), so the velocities there cannot be recovered from the momenta";
      throw AnalysisError(os.str());
    }
    out.qd.row(k) = v.transpose();
    out.energy[static_cast<std::size_t>(k)] = energy_function(model, qk, v, tk);
  }
  return out;
}

namespace detail {

template <class M>
struct ActionProblem {
  const M* model;
  Vec<double, M::dof> a, b;
  double t0, h;
  int K;
  DiscreteRule rule;
  int evaluations = 0;
};

/// S_d(q_1 … q_{K−1}) and its gradient, the DEL residuals D2 L_d + D1 L_d.
template <class M>
double action_objective(unsigned, const double* x, double* grad, void* data) {
  auto& p = *static_cast<ActionProblem<M>*>(data);
  constexpr int n = M::dof;
  ++p.evaluations;
  auto node = [&](int k) -> Vec<double, n> {
    if (k == 0) return p.a;
    if (k == p.K) return p.b;
    return Eigen::Map<const Vec<double, n>>(x + (k - 1) * n);
  };
  double s = 0;
  if (grad) std::fill(grad, grad + (p.K - 1) * n, 0.0);
  for (int k = 0; k < p.K; ++k) {
    const auto d = discrete_lagrangian_derivatives(*p.model, node(k), node(k + 1), p.t0 + k * p.h, p.h, p.rule);
    s += d.value;
    if (!grad) continue;
    for (int i = 0; i < n; ++i) {
      if (k > 0) grad[(k - 1) * n + i] += d.d1[i];
      if (k + 1 < p.K) grad[k * n + i] += d.d2[i];
    }
  }
  return s;
}

}  // namespace detail

/// The discrete action minimised over the interior points by NLopt's
/// LD_LBFGS from the straight line (gradient: the discrete Euler–Lagrange
/// residuals). Where the action has a minimum this is the path solve_bvp()
/// finds; beyond a conjugate point S_d has no minimum (it is unbounded below
/// along the negative directions of its Hessian for an oscillator) and the
/// minimiser runs away: ActionMinimum::converged is false and the action is
/// below that of the stationary path. Meant for comparison; solve_bvp() is
/// the solver. Same input checks and refusals as solve_bvp().
template <class M>
ActionMinimum minimise_action(const M& model, const Vec<double, M::dof>& a, const Vec<double, M::dof>& b, double t0,
                              double t1, const BvpOptions& options = {}) {
  check_model<M>();
  detail::require_static_size<M>();
  detail::refuse_for_bvp(model);
  constexpr int n = M::dof;
  const int K = options.steps;
  if (!a.allFinite() || !b.allFinite()) throw OptionError("minimise action: end points are not finite");
  if (!std::isfinite(t0) || !std::isfinite(t1) || !(t1 > t0))
    throw OptionError("minimise action: time: need finite t0 < t1");
  if (K < 2) throw OptionError("minimise action: steps: need at least 2, got " + std::to_string(K));
  detail::ActionProblem<M> problem{&model, a, b, t0, (t1 - t0) / K, K, options.rule};
  const int N = (K - 1) * n;
  std::vector<double> x(static_cast<std::size_t>(N));
  for (int k = 1; k < K; ++k)
    for (int i = 0; i < n; ++i) {
      const double s = static_cast<double>(k) / K;
      x[static_cast<std::size_t>((k - 1) * n + i)] = (1 - s) * a[i] + s * b[i];
    }
  std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(nlopt_create(NLOPT_LD_LBFGS, static_cast<unsigned>(N)),
                                                             &nlopt_destroy);
  nlopt_set_min_objective(opt.get(), &detail::action_objective<M>, &problem);
  nlopt_set_xtol_rel(opt.get(), 1e-14);
  nlopt_set_ftol_rel(opt.get(), 0.0);
  nlopt_set_maxeval(opt.get(), 20000);
  double f = 0;
  ActionMinimum out;
  out.nlopt_result = static_cast<int>(nlopt_optimize(opt.get(), x.data(), &f));
  out.evaluations = problem.evaluations;
  out.q.resize(K + 1, n);
  out.q.row(0) = a.transpose();
  out.q.row(K) = b.transpose();
  for (int k = 1; k < K; ++k)
    for (int i = 0; i < n; ++i) out.q(k, i) = x[static_cast<std::size_t>((k - 1) * n + i)];
  std::vector<double> g(static_cast<std::size_t>(N));
  out.action = detail::action_objective<M>(static_cast<unsigned>(N), x.data(), g.data(), &problem);
  double gmax = 0, pmax = 0;
  for (double v : g) gmax = std::max(gmax, std::abs(v));
  const auto d0 = discrete_lagrangian_derivatives(model, a, Vec<double, n>(out.q.row(1).transpose()), t0,
                                                  (t1 - t0) / K, options.rule);
  pmax = d0.d1.template lpNorm<Eigen::Infinity>();
  out.residual = gmax;
  out.converged = out.nlopt_result > 0 && std::isfinite(out.action) && std::isfinite(gmax) &&
                  gmax <= 1e-8 * (1.0 + pmax);
  return out;
}

}  // namespace lagrangian
