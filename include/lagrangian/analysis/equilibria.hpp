#pragma once
/// \file equilibria.hpp
/// Equilibria q* of a model: stationary points of U = −L(q, 0, t) on the
/// constraint manifold, ∇U(q*) = Gᵀλ, g(q*) = 0, found by minimisation
/// (NLopt) and Newton's method, and classified by the Hessian of U on the
/// manifold (see analysis.hpp for the equations).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/analysis/detail/rest_model.hpp"
#include "lagrangian/analysis/linearisation.hpp"
#include "lagrangian/model.hpp"

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
  std::string found_by;         ///< "minimisation" (NLopt, then Newton), "Newton" (on ∇U = Gᵀλ) or "Newton with deflation"
};

/// Options of find_equilibria().
struct EquilibriumOptions {
  std::vector<Eigen::VectorXd> starts;  ///< initial guesses (at least one)
  /// Period of each coordinate (2π for an angle), 0 for none; empty: none.
  std::vector<double> periods;
  double t = 0;                     ///< time at which L and g are frozen (s)
  bool minimise = true;             ///< run NLopt (LD_LBFGS, or LD_SLSQP with constraints) from each start
  bool newton = true;               ///< run Newton's method on ∇U = Gᵀλ, g = 0 from each start (finds saddles and maxima)
  /// After the searches above, Newton's method again from every start on the
  /// deflated system μ(q) F(q, λ), μ = Πᵢ (‖q − q*ᵢ‖⁻² + 1) over the equilibria
  /// q*ᵢ found so far (their basins no longer attract), repeated from a start
  /// while it finds a new one; found_by "Newton with deflation".
  bool deflation = true;
  int max_deflations_per_start = 8;  ///< deflated searches from one start at most
  double dedupe_tolerance = 1e-6;   ///< equilibria closer than this (∞-norm, relative to 1 + ‖q‖) are one
  double zero_tolerance = 1e-8;     ///< |eigenvalue| ≤ this × max |eigenvalue| counts as zero
  int max_iterations = 100;         ///< Newton iterations per start
};


/// A table of equilibria for a terminal: U, q, kind, the eigenvalues of K_t
/// and λ; `names` and `units` label the coordinates (units may be empty).
std::string format_equilibria(const std::vector<Equilibrium>& equilibria, const std::vector<std::string>& names,
                              const std::vector<std::string>& units);

namespace detail {

/// find_equilibria() on the model frozen at options.t (src/analysis/equilibria.cpp).
std::vector<Equilibrium> equilibria_of(const RestModel& model, const EquilibriumOptions& options);

}  // namespace detail

/// Equilibria of `model` (stationary points of U = −L(q, 0, t) on g(q) = 0)
/// from every start in `options`: NLopt minimisation (polished by Newton)
/// finds minima; Newton's method on ∇U = Gᵀλ, g = 0 also finds saddles and
/// maxima near a start; deflated Newton from the same starts finds further
/// ones whose basins no start lay in (EquilibriumOptions::deflation). Duplicates (within dedupe_tolerance, periodic
/// coordinates wrapped) are merged; the result is sorted by U. Each is
/// classified by the eigenvalues of K_t. Throws AnalysisError for models with
/// Pfaffian or unilateral constraints or generalized forces, and OptionError
/// for no start or a start of the wrong size or not finite.
template <class M>
std::vector<Equilibrium> find_equilibria(const M& model, const EquilibriumOptions& options) {
  check_model<M>();
  detail::refuse_for_equilibria(model);
  return detail::equilibria_of(detail::RestModelOf<M>(model, options.t), options);
}

}  // namespace lagrangian
