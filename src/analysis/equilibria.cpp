// Equilibria (equilibria.hpp) on the RestModel interface, compiled once:
// NLopt minimisation of U, Newton's method on ∇U = Gᵀλ, g = 0 (plain and
// deflated), and the classification by the Hessian of U on the constraint
// manifold.

#include "lagrangian/analysis/equilibria.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlopt.h>

#include "lagrangian/errors.hpp"

namespace lagrangian::detail {
namespace {

/// Wraps periodic coordinates into [−P/2, P/2).
void wrap_periodic(Eigen::VectorXd& q, const std::vector<double>& periods) {
  for (int i = 0; i < q.size() && static_cast<std::size_t>(i) < periods.size(); ++i) {
    const double p = periods[static_cast<std::size_t>(i)];
    if (p > 0) {
      q[i] -= p * std::floor(q[i] / p + 0.5);
      if (q[i] >= 0.5 * p) q[i] -= p;
    }
  }
}

/// Deflation of known roots r₁ … r_k (Farrell, Birkisson & Funke, SIAM J.
/// Sci. Comput. 37 (2015) A2026): Newton's method is run on
///
///     F̃(q, λ) = μ(q) F(q, λ),   μ(q) = Πᵢ (‖q − rᵢ‖^(−p) + σ),  p = 2, σ = 1,
///
/// (q − rᵢ with periodic coordinates wrapped), whose roots are those of F
/// except the rᵢ: near rᵢ, μ → ∞ and F̃ does not vanish there. With the
/// undeflated step δ = −J⁺F, the step of F̃ is, by Sherman–Morrison,
///
///     δ̃ = δ / (1 − ∇(ln μ)ᵀ δ_q),   ∇ ln μ = Σᵢ −p ‖dᵢ‖^(−p−2) dᵢ / (‖dᵢ‖^(−p) + σ),
///
/// so no other system is solved. A start that would converge to a known
/// root is pushed off it toward another.
struct Deflation {
  const std::vector<Eigen::VectorXd>* roots = nullptr;
  const std::vector<double>* periods = nullptr;
  static constexpr double power = 2.0;
  static constexpr double shift = 1.0;
  bool active() const { return roots && !roots->empty(); }
  Eigen::VectorXd offset(const Eigen::VectorXd& q, const Eigen::VectorXd& r) const {
    Eigen::VectorXd d = q - r;
    wrap_periodic(d, *periods);
    return d;
  }
  /// μ(q).
  double factor(const Eigen::VectorXd& q) const {
    double mu = 1.0;
    for (const Eigen::VectorXd& r : *roots) mu *= std::pow(offset(q, r).norm(), -power) + shift;
    return mu;
  }
  /// ∇ ln μ(q).
  Eigen::VectorXd log_gradient(const Eigen::VectorXd& q) const {
    Eigen::VectorXd grad = Eigen::VectorXd::Zero(q.size());
    for (const Eigen::VectorXd& r : *roots) {
      const Eigen::VectorXd d = offset(q, r);
      const double dn = d.norm();
      const double inv = std::pow(dn, -power);
      grad += (-power * std::pow(dn, -power - 2.0) / (inv + shift)) * d;
    }
    return grad;
  }
};

/// Newton's method on F(q, λ) = [∇U − Gᵀλ; g] = 0 from q (projected onto g = 0 first),
/// on the deflated F̃ = μ F when `deflation` is active (see Deflation).
/// Returns true and writes q, λ when it converges.
bool newton_equilibrium(const RestModel& model, Eigen::VectorXd& q, Eigen::VectorXd& lambda, int max_iterations,
                        const Deflation& deflation = {}) {
  const int n = model.coordinate_count();
  const int m = model.holonomic_count();
  if (m > 0 && !model.project(q)) return false;
  auto evaluate = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& lam, Eigen::VectorXd& F, Eigen::MatrixXd* Jac) {
    const PotentialDerivatives u = model.potential(x);
    const HolonomicDerivatives c = model.holonomic(x);
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
  };
  lambda = least_squares_multipliers(model.holonomic(q).jacobian, model.potential(q).gradient);
  Eigen::VectorXd F;
  Eigen::MatrixXd Jac;
  evaluate(q, lambda, F, &Jac);
  double force_scale = Jac.topLeftCorner(n, n).cwiseAbs().maxCoeff() * (1.0 + q.lpNorm<Eigen::Infinity>()) +
                       F.head(n).lpNorm<Eigen::Infinity>();
  if (!(force_scale > 0)) force_scale = 1.0;
  const bool deflated = deflation.active();
  for (int it = 0; it < max_iterations; ++it) {
    if (!F.allFinite() || !Jac.allFinite()) return false;
    Eigen::VectorXd step = min_norm_solve(Jac, -F);
    if (deflated) {
      const double denominator = 1.0 - deflation.log_gradient(q).dot(step.head(n));
      if (!(std::abs(denominator) > 1e-300)) return false;
      step /= denominator;
    }
    if (!step.allFinite()) return false;
    // Backtracking on ‖F‖, or ‖μ F‖ when deflated (at most 20 halvings).
    const double f0 = deflated ? deflation.factor(q) * F.norm() : F.norm();
    double alpha = 1.0;
    Eigen::VectorXd qn, ln, Fn;
    for (int b = 0; b < 20; ++b) {
      qn = q + alpha * step.head(n);
      ln = m > 0 ? Eigen::VectorXd(lambda + alpha * step.tail(m)) : lambda;
      evaluate(qn, ln, Fn, nullptr);
      const double fn = deflated ? deflation.factor(qn) * Fn.norm() : Fn.norm();
      if (Fn.allFinite() && fn <= (1 - 1e-4 * alpha) * f0) break;
      alpha *= 0.5;
    }
    if (!Fn.allFinite()) return false;
    const double dq = (alpha * step.head(n)).lpNorm<Eigen::Infinity>();
    q = qn;
    lambda = ln;
    evaluate(q, lambda, F, &Jac);
    if (dq <= 1e-13 * (1.0 + q.lpNorm<Eigen::Infinity>())) break;
  }
  const double res = F.head(n).lpNorm<Eigen::Infinity>();
  const double cres = m > 0 ? F.tail(m).lpNorm<Eigen::Infinity>() : 0.0;
  return res <= 1e-9 * force_scale && cres <= 1e-10 * (1.0 + q.lpNorm<Eigen::Infinity>());
}

double minimisation_objective(unsigned n, const double* x, double* grad, void* data) {
  const auto& model = *static_cast<const RestModel*>(data);
  const PotentialDerivatives u = model.potential(Eigen::Map<const Eigen::VectorXd>(x, n));
  if (grad)
    for (unsigned i = 0; i < n; ++i) grad[i] = u.gradient[static_cast<int>(i)];
  return u.value;
}

void minimisation_constraints(unsigned m, double* result, unsigned n, const double* x, double* grad, void* data) {
  const auto& model = *static_cast<const RestModel*>(data);
  const HolonomicDerivatives c = model.holonomic(Eigen::Map<const Eigen::VectorXd>(x, n));
  for (unsigned i = 0; i < m; ++i) {
    result[i] = c.value[static_cast<int>(i)];
    if (grad)
      for (unsigned k = 0; k < n; ++k) grad[i * n + k] = c.jacobian(static_cast<int>(i), static_cast<int>(k));
  }
}

/// Minimises U from q with NLopt (LD_LBFGS, or LD_SLSQP under constraints); false on failure.
bool minimise_potential(const RestModel& model, Eigen::VectorXd& q) {
  const int n = model.coordinate_count();
  const int m = model.holonomic_count();
  std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(
      nlopt_create(m > 0 ? NLOPT_LD_SLSQP : NLOPT_LD_LBFGS, static_cast<unsigned>(n)), &nlopt_destroy);
  if (!opt) return false;
  void* data = const_cast<RestModel*>(&model);
  nlopt_set_min_objective(opt.get(), &minimisation_objective, data);
  if (m > 0) {
    std::vector<double> tol(static_cast<std::size_t>(m), 1e-12);
    nlopt_add_equality_mconstraint(opt.get(), static_cast<unsigned>(m), &minimisation_constraints, data, tol.data());
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
Equilibrium classify_equilibrium(const RestModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& lambda,
                                 double zero_tolerance) {
  const int n = model.coordinate_count();
  const PotentialDerivatives u = model.potential(q);
  const HolonomicDerivatives c = model.holonomic(q);
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
                   .lpNorm<Eigen::Infinity>();
  e.constraint_residual = c.value.size() ? c.value.lpNorm<Eigen::Infinity>() : 0.0;
  if (Kt.rows() > 0) symmetric_eigenvalues(0.5 * (Kt + Kt.transpose()), e.hessian_eigenvalues);
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

}  // namespace

std::vector<Equilibrium> equilibria_of(const RestModel& model, const EquilibriumOptions& options) {
  const int n = model.coordinate_count();
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
  auto add = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& lambda, const char* how) {
    Equilibrium e = classify_equilibrium(model, q, lambda, options.zero_tolerance);
    e.found_by = how;
    wrap_periodic(e.q, options.periods);
    for (const Equilibrium& f : found) {
      Eigen::VectorXd d = e.q - f.q;
      wrap_periodic(d, options.periods);
      if (d.lpNorm<Eigen::Infinity>() <= options.dedupe_tolerance * (1.0 + e.q.lpNorm<Eigen::Infinity>())) return;
    }
    found.push_back(std::move(e));
  };
  for (const Eigen::VectorXd& start : options.starts) {
    if (options.minimise) {
      Eigen::VectorXd q = start;
      Eigen::VectorXd lambda;
      if (minimise_potential(model, q) && newton_equilibrium(model, q, lambda, options.max_iterations))
        add(q, lambda, "minimisation");
    }
    if (options.newton) {
      Eigen::VectorXd q = start;
      Eigen::VectorXd lambda;
      if (newton_equilibrium(model, q, lambda, options.max_iterations)) add(q, lambda, "Newton");
    }
  }
  // Deflation (see Deflation): from every start again, Newton's method on
  // μ F with every equilibrium found so far deflated, then polished on F
  // itself; repeated from the same start while it finds a new one.
  // A deflated iteration can also run off to where ∇U fades (a Kepler
  // potential at 1e34 m); such points, beyond 10 (1 + max ‖start‖∞), are
  // not taken.
  double reach = 0;
  for (const Eigen::VectorXd& start : options.starts) reach = std::max(reach, start.lpNorm<Eigen::Infinity>());
  reach = 10.0 * (1.0 + reach);
  if (options.newton && options.deflation) {
    for (const Eigen::VectorXd& start : options.starts) {
      for (int round = 0; round < options.max_deflations_per_start && !found.empty(); ++round) {
        std::vector<Eigen::VectorXd> roots;
        for (const Equilibrium& f : found) roots.push_back(f.q);
        Eigen::VectorXd q = start;
        Eigen::VectorXd lambda;
        if (!newton_equilibrium(model, q, lambda, options.max_iterations, Deflation{&roots, &options.periods})) break;
        if (!newton_equilibrium(model, q, lambda, options.max_iterations)) break;
        if (!(q.lpNorm<Eigen::Infinity>() <= reach)) break;
        const std::size_t before = found.size();
        add(q, lambda, "Newton with deflation");
        if (found.size() == before) break;
      }
    }
  }
  std::stable_sort(found.begin(), found.end(),
                   [](const Equilibrium& a, const Equilibrium& b) { return a.potential < b.potential; });
  return found;
}

}  // namespace lagrangian::detail
