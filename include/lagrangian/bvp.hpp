#pragma once
/// \file bvp.hpp
/// Boundary-value problems by stationary discrete action: the path with
/// q(t0) = a, q(t1) = b on which the discrete Euler–Lagrange equations hold
/// (Newton on the block-tridiagonal Hessian of S_d), and the same action
/// minimised by NLopt for comparison (see analysis.hpp for the equations).

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
#include "lagrangian/linearisation.hpp"

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
