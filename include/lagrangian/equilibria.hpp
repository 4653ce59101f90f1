#pragma once
/// \file equilibria.hpp
/// Equilibria q* of a model: stationary points of U = −L(q, 0, t) on the
/// constraint manifold, ∇U(q*) = Gᵀλ, g(q*) = 0, found by minimisation
/// (NLopt) and Newton's method, and classified by the Hessian of U on the
/// manifold (see analysis.hpp for the equations).

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


/// A table of equilibria for a terminal: U, q, kind, the eigenvalues of K_t
/// and λ; `names` and `units` label the coordinates (units may be empty).
std::string format_equilibria(const std::vector<Equilibrium>& equilibria, const std::vector<std::string>& names,
                              const std::vector<std::string>& units);

namespace detail {


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

}  // namespace lagrangian
