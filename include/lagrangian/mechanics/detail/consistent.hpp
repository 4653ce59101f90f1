#pragma once
// Implementation of consistent_initial_state() (declared in constraints.hpp).
//
// The position part solves
//
//     min ½‖q − q_g‖²  subject to  g(q, t0) = 0                         (1)
//
// (q_g the guess) from several starts and keeps the nearest consistent point
// found. Each start is taken onto g = 0 by Gauss–Newton (minimum-norm steps
// q ← q − G⁺g, G = ∂g/∂q), which from a start near the manifold lands near
// its foot point, and then slid along the manifold to a stationary point of
// (1) (slide_to_nearest below). The starts: the guess itself, the point
// SLSQP (NLopt) reaches on (1), and q_g ± d eᵢ for every coordinate i, d the
// smallest distance found by the first two (the ball of radius d about q_g
// holds every nearer consistent point). Points where the holonomic rank is n
// (isolated, rigid) are kept out of the choice while a point with motion
// left exists. At the chosen point the first- and second-order conditions of
// (1) are checked: with μ solving Gᵀμ = q − q_g (Lagrangian
// ½‖q − q_g‖² − μᵀg), q_g − q must be normal to the manifold and
// Zᵀ(I − Σμᵢ∇²gᵢ)Z positive definite (Z an orthonormal basis of the null
// space of G; ∇²gᵢ by automatic differentiation): a strict local minimum of
// the distance. Nothing short of searching the whole manifold proves it the
// global one; ConsistentStateReport says which of these hold.

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Cholesky>
#include <nlopt.h>

#include "lagrangian/mechanics/properties.hpp"

namespace lagrangian {
namespace detail {

// Compiled once in src/analysis/linearisation.cpp (declared in linearisation.hpp).
Eigen::MatrixXd tangent_basis(const Eigen::MatrixXd& G, int n);
bool symmetric_eigenvalues(const Eigen::MatrixXd& S, Eigen::VectorXd& eigenvalues);

template <class M>
struct ConsistencyProblem {
  const M* model;
  Vec<double, coordinate_count_v<M>> guess;
  double t;
};

template <class M>
double consistency_objective(unsigned n, const double* x, double* grad, void* data) {
  const auto& p = *static_cast<const ConsistencyProblem<M>*>(data);
  double f = 0;
  for (unsigned i = 0; i < n; ++i) {
    const double d = x[i] - p.guess[static_cast<int>(i)];
    f += d * d;
    if (grad) grad[i] = 2 * d;
  }
  return f;
}

template <class M>
void consistency_constraints(unsigned m, double* result, unsigned n, const double* x, double* grad, void* data) {
  const auto& p = *static_cast<const ConsistencyProblem<M>*>(data);
  Vec<double, coordinate_count_v<M>> q(static_cast<int>(n));
  for (unsigned i = 0; i < n; ++i) q[static_cast<int>(i)] = x[i];
  auto cs = constraint_state(*p.model, q, Vec<double, coordinate_count_v<M>>::Zero(static_cast<int>(n)).eval(), p.t);
  drop_inactive(*p.model, cs, ActiveSet{});
  for (unsigned i = 0; i < m; ++i) {
    result[i] = cs.position[static_cast<int>(i)];
    if (grad)
      for (unsigned k = 0; k < n; ++k) grad[i * n + k] = cs.jacobian(static_cast<int>(i), static_cast<int>(k));
  }
}

/// G = ∂g/∂q of the holonomic rows at q (mh × n).
template <class M>
Eigen::Matrix<double, holonomic_count_v<M>, coordinate_count_v<M>> holonomic_jacobian(
    const M& model, const Vec<double, coordinate_count_v<M>>& q, double t) {
  const auto cs = constraint_state(model, q, Vec<double, coordinate_count_v<M>>::Zero(q.size()).eval(), t);
  return cs.jacobian.topRows(holonomic_count(model));
}

/// Levenberg–Marquardt steps on g(q) = 0 from q (before the Gauss–Newton
/// polish of project_positions):
///
///     δ = −(GᵀG + λI)⁻¹ Gᵀg,   λ = ν ‖G‖_F ‖g‖₂,
///
/// ν = 1, multiplied by 4 while a step does not reduce ‖g‖₂ and divided by 4
/// (down to 1) after one that does; until ‖g‖∞ ≤ 1e-10 (1 + ‖q‖∞). With
/// dependent rows the solution set is a manifold on which G loses rank, and
/// near it G has singular values σ ~ distance: a Gauss–Newton step (λ = 0)
/// takes them at face value and, with as many rows as coordinates, heads for
/// the point where the linearised rows meet, often a singular configuration
/// far away. With λ ∝ ‖g‖ ∝ distance those directions (σ² ≪ λ) are damped
/// and the step is close to the shortest one onto the manifold, while
/// λ → 0 keeps the fast local convergence (Levenberg–Marquardt with
/// λ ∝ ‖g‖ converges to a solution set under a local error bound, without
/// isolated roots; Fan & Yuan 2005). Returns false when no step reduces ‖g‖.
template <class M>
bool levenberg_marquardt_onto(const M& model, Vec<double, coordinate_count_v<M>>& q, double t) {
  constexpr int n = coordinate_count_v<M>;
  constexpr int MH = holonomic_count_v<M>;  // (Dynamic: counted at run time)
  const int size = static_cast<int>(q.size()), mh = holonomic_count(model);
  const Vec<double, n> zero = Vec<double, n>::Zero(size);
  auto residual = [&](const Vec<double, n>& x) {
    const auto cs = constraint_state(model, x, zero, t);
    return Vec<double, MH>(cs.position.head(mh));
  };
  double nu = 1.0;
  Vec<double, MH> g = residual(q);
  for (int it = 0; it < 200; ++it) {
    if (!g.allFinite()) return false;
    if (g.template lpNorm<Eigen::Infinity>() <= 1e-10 * (1.0 + q.template lpNorm<Eigen::Infinity>())) return true;
    const Eigen::Matrix<double, MH, n> G = holonomic_jacobian(model, q, t);
    const Mat<double, n> GtG = G.transpose() * G;
    const Vec<double, n> Gtg = G.transpose() * g;
    bool accepted = false;
    while (nu < 1e12) {
      const double lambda = nu * G.norm() * g.norm();
      const Mat<double, n> A = GtG + lambda * Mat<double, n>::Identity(size, size);
      const Vec<double, n> step = -A.ldlt().solve(Gtg);
      const Vec<double, n> trial = q + step;
      const Vec<double, MH> gt = residual(trial);
      if (step.allFinite() && gt.allFinite() && gt.norm() < g.norm()) {
        q = trial;
        g = gt;
        nu = std::max(1.0, nu / 4);
        accepted = true;
        break;
      }
      nu *= 4;
    }
    if (!accepted) return false;
  }
  return g.template lpNorm<Eigen::Infinity>() <= 1e-10 * (1.0 + q.template lpNorm<Eigen::Infinity>());
}

/// The local quadratic model of (1) at q on g = 0 (target = q_g): with
/// μ solving Gᵀμ = q − target (minimum-norm; the Lagrangian is
/// ½‖q − target‖² − μᵀg), Z an orthonormal basis of the null space of G
/// (SVD) and H_t = Zᵀ(I − Σμᵢ∇²gᵢ)Z the Hessian of the distance on the
/// manifold (∇²gᵢ from holonomic_derivatives()):
///   along  = Z Zᵀ(target − q), the tangent part (zero at a stationary point),
///   newton = Z H_t⁻¹ Zᵀ(target − q) when H_t is positive definite, else along,
///   curvature = the smallest eigenvalue of H_t (+∞ for an empty tangent space).
template <int n>
struct NearestPointModel {
  Vec<double, n> along;
  Vec<double, n> newton;
  double curvature = 0;
};

template <class M>
NearestPointModel<coordinate_count_v<M>> nearest_point_model(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                                             const Vec<double, coordinate_count_v<M>>& target,
                                                             double t) {
  constexpr int n = coordinate_count_v<M>;
  const int size = static_cast<int>(q.size()), mh = holonomic_count(model);
  const HolonomicDerivatives d = holonomic_derivatives(model, q, t);
  const Eigen::MatrixXd& G = d.jacobian;
  const Eigen::MatrixXd Gt = G.transpose();
  MinNormSolver solver(size, mh);
  solver.factorize(Gt.data(), rank_tolerance);
  const Vec<double, n> away = q - target;
  Eigen::VectorXd mu(mh);
  solver.solve(away.data(), mu.data());
  Eigen::MatrixXd H = Eigen::MatrixXd::Identity(size, size);
  for (int i = 0; i < mh; ++i) H -= mu[i] * d.hessians[static_cast<std::size_t>(i)];
  const Eigen::MatrixXd Z = tangent_basis(G, size);
  NearestPointModel<n> r;
  const Eigen::VectorXd zr = -(Z.transpose() * away);
  r.along = Z * zr;
  r.newton = r.along;
  r.curvature = std::numeric_limits<double>::infinity();
  if (Z.cols() == 0) return r;
  const Eigen::MatrixXd Ht = 0.5 * (Z.transpose() * H * Z + (Z.transpose() * H * Z).transpose());
  Eigen::VectorXd ev;
  r.curvature = symmetric_eigenvalues(Ht, ev) ? ev[0] : std::numeric_limits<double>::quiet_NaN();
  if (r.curvature > 0) {
    const Eigen::LLT<Eigen::MatrixXd> llt(Ht);
    if (llt.info() == Eigen::Success) r.newton = Z * llt.solve(zr);
  }
  return r;
}

/// From q on g = 0, a local nearest point of the manifold to `target`, by
/// Newton's method on the manifold:
///
///     q ← P(q + α s),   s = Z H_t⁻¹ Zᵀ(target − q)   (nearest_point_model),
///
/// P the Gauss–Newton projection onto g = 0 (a retraction), α = 1, ½, ¼, …
/// the first that makes ‖q − target‖ smaller — or, once the distance no
/// longer changes beyond round-off (its change is second order in the
/// tangent offset), that keeps it and makes the tangent part smaller. Where
/// H_t is not positive definite (near a farthest point) s is the tangent
/// part itself, a descent direction. Until the tangent part is below
/// 1e-12 (1 + ‖q‖): the first-order condition of (1), target − q normal to
/// the manifold. (A plain tangent step, α s with s the tangent part,
/// converges only linearly, at the rate 1 − D/l on a circle of radius l seen
/// from distance D of its centre, and overshoots once D > 2l.) Returns the
/// norm of the tangent part at the end (0 at a stationary point).
template <class M>
double slide_to_nearest(const M& model, const Vec<double, coordinate_count_v<M>>& target,
                        Vec<double, coordinate_count_v<M>>& q, double t, double tolerance) {
  constexpr int n = coordinate_count_v<M>;
  NearestPointModel<n> local = nearest_point_model(model, q, target, t);
  for (int it = 0; it < 100; ++it) {
    const double along_norm = local.along.norm();
    if (!(along_norm > 1e-12 * (1.0 + q.norm()))) break;
    const double dist = (q - target).norm();
    bool moved = false;
    for (const Vec<double, n>* step : {&local.newton, &local.along}) {
      for (double alpha = 1.0; alpha >= 1.0 / 1024 && !moved; alpha *= 0.5) {
        Vec<double, n> trial = q + alpha * *step;
        if (!trial.allFinite()) continue;
        try {
          project_positions(model, trial, t, tolerance, 50, ActiveSet{});
        } catch (const ConstraintError&) {
          continue;
        }
        const double trial_dist = (trial - target).norm();
        if (!(trial_dist <= dist * (1.0 + 1e-14))) continue;
        const NearestPointModel<n> next = nearest_point_model(model, trial, target, t);
        if (trial_dist < dist || next.along.norm() < along_norm) {
          q = trial;
          local = next;
          moved = true;
        }
      }
      if (moved) break;
    }
    if (!moved) break;  // no descent left at round-off: as near as the projection can resolve
  }
  return local.along.norm();
}

/// One consistent point reached from one start.
template <int n>
struct ConsistentCandidate {
  Vec<double, n> q;
  double distance = 0;      ///< ‖q − q_g‖₂
  double stationarity = 0;  ///< ‖Z Zᵀ(q_g − q)‖₂, the tangent part: 0 at a stationary point of (1)
  int rank = 0;             ///< holonomic rank at q
  bool rigid = false;       ///< rank n and workless constraints: no motion left at q
};

/// The consistent points reached from several starts (Gauss–Newton from
/// the guess, SLSQP on ‖q − q_g‖² subject to g = 0, q_g ± d eᵢ), each slid
/// to a stationary point of the distance, distinct, with their rank; the
/// starts counted in rep.starts and the first failure kept in first_error.
template <class M>
std::vector<ConsistentCandidate<coordinate_count_v<M>>> consistent_candidates(
    const M& model, const State<coordinate_count_v<M>>& guess, double t, double tolerance, ConsistentStateReport& rep,
    std::optional<ConstraintError>& first_error) {
  constexpr int n = coordinate_count_v<M>;
  const int size = static_cast<int>(guess.q.size()), mh = holonomic_count(model);
  // Counting constraints would refuse an over-constrained mechanism whose
  // rows are dependent (three parallel cranks: 3 rows, rank 2, 1 DOF); the
  // rank is judged on each candidate, where it is meaningful.
  std::vector<detail::ConsistentCandidate<n>> found;
  auto try_from = [&](const Vec<double, n>& start) {
    ++rep.starts;
    Vec<double, n> q = start;
    detail::levenberg_marquardt_onto(model, q, t);  // then Gauss–Newton to the tolerance
    try {
      project_positions(model, q, t, tolerance, 50, ActiveSet{});
    } catch (const ConstraintError& e) {
      if (!first_error) first_error = e;
      return;
    }
    detail::ConsistentCandidate<n> c;
    c.stationarity = detail::slide_to_nearest(model, guess.q, q, t, tolerance);
    c.q = q;
    c.distance = (q - guess.q).norm();
    for (const auto& f : found)
      if ((f.q - q).template lpNorm<Eigen::Infinity>() <= 1e-8 * (1.0 + q.template lpNorm<Eigen::Infinity>()))
        return;
    c.rank = detail::numeric_rank(detail::holonomic_jacobian(model, q, t));
    State<n> at = guess;
    at.q = q;
    c.rigid = c.rank >= size && detail::constraints_workless(model, at, t);
    found.push_back(c);
  };
  auto nearest_so_far = [&]() {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& f : found) d = std::min(d, f.distance);
    return d;
  };
  // 1. Gauss–Newton from the guess itself.
  try_from(guess.q);
  // 2. SLSQP on (1) with AD gradients (it can stop at a singular
  //    configuration, where its subproblems degenerate; it is one start
  //    among several, not the answer).
  if (!(nearest_so_far() == 0.0)) {
    detail::ConsistencyProblem<M> problem{&model, guess.q, t};
    std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(
        nlopt_create(NLOPT_LD_SLSQP, static_cast<unsigned>(size)), &nlopt_destroy);
    nlopt_set_min_objective(opt.get(), &detail::consistency_objective<M>, &problem);
    std::vector<double> tol(static_cast<std::size_t>(mh), 1e-14);
    nlopt_add_equality_mconstraint(opt.get(), mh, &detail::consistency_constraints<M>, &problem, tol.data());
    nlopt_set_xtol_rel(opt.get(), 1e-14);
    nlopt_set_maxeval(opt.get(), 500);
    std::vector<double> x(guess.q.data(), guess.q.data() + size);
    double f = 0;
    const nlopt_result r = nlopt_optimize(opt.get(), x.data(), &f);
    Vec<double, n> xq(size);
    for (int i = 0; i < size; ++i) xq[i] = x[static_cast<std::size_t>(i)];
    if ((r > 0 || r == NLOPT_ROUNDOFF_LIMITED) && xq.allFinite()) try_from(xq);
  }
  // 3. q_g ± d eᵢ, d the nearest distance so far.
  const double d0 = nearest_so_far();
  const double spread = std::isfinite(d0) ? d0 : 1.0 + guess.q.norm();
  if (spread > 0) {
    for (int i = 0; i < size; ++i)
      for (double sign : {1.0, -1.0}) {
        Vec<double, n> start = guess.q;
        start[i] += sign * spread;
        try_from(start);
      }
  }
  return found;
}

/// A few more Gauss–Newton steps on g(q, t) = 0, kept while they reduce
/// ‖g‖: the projection stops at tolerance · (1 + ‖q‖∞), these take g to
/// round-off.
template <class M>
void polish_positions(const M& model, Vec<double, coordinate_count_v<M>>& q, double t) {
  constexpr int n = coordinate_count_v<M>;
  constexpr int MH = holonomic_count_v<M>;
  const int size = static_cast<int>(q.size()), mh = holonomic_count(model);
  detail::MinNormSolver solver(mh, size);
  const Vec<double, n> zero = Vec<double, n>::Zero(size);
  Vec<double, MH> g = constraint_state(model, q, zero, t).position.head(mh);
  for (int it = 0; it < 3; ++it) {
    const Eigen::Matrix<double, MH, n> G = detail::holonomic_jacobian(model, q, t);
    solver.factorize(G.data());
    Vec<double, n> dq(size);
    solver.solve(g.data(), dq.data());
    const Vec<double, n> trial = q - dq;
    const Vec<double, MH> gt = constraint_state(model, trial, zero, t).position.head(mh);
    if (!(gt.norm() < g.norm())) break;
    q = trial;
    g = gt;
  }
}

/// q̇ projected onto C q̇ + c = 0 in the metric of M; a ConstraintError
/// naming the constraint (`names`: constraint_names()) when a velocity
/// residual stays; the residuals into rep.
template <class M>
void make_velocities_consistent(const M& model, State<coordinate_count_v<M>>& s, double t, double tolerance,
                                const std::vector<std::string>& names, ConsistentStateReport& rep) {
  constexpr int n = coordinate_count_v<M>;
  const int size = static_cast<int>(s.q.size()), mh = holonomic_count(model);
  Workspace<n> ws(size);
  project_velocities(model, ws, s.q, s.qd, t, ActiveSet{});
  auto cs = constraint_state(model, s.q, s.qd, t);
  drop_inactive(model, cs, ActiveSet{});
  const double scale = 1.0 + s.qd.template lpNorm<Eigen::Infinity>();
  for (int i = 0; i < constraint_count(model); ++i) {
    if (!(std::abs(cs.velocity[i]) <= 1e3 * tolerance * scale)) {
      std::ostringstream os;
      os.precision(17);
      os << "cannot make the velocities consistent: constraint " << names[static_cast<std::size_t>(i)]
         << " has velocity residual " << cs.velocity[i] << " after projection (rank-deficient constraints at t = "
         << t << "?)";
      throw ConstraintError(os.str());
    }
  }
  if (mh > 0) rep.position_residual = cs.position.head(mh).template lpNorm<Eigen::Infinity>();
  rep.velocity_residual = cs.velocity.template lpNorm<Eigen::Infinity>();
}

/// ConsistentStateReport::note: what was found and how sure it is.
inline std::string consistent_note(const ConsistentStateReport& rep) {
  std::ostringstream os;
  os.precision(6);
  if (rep.nearest_proven) {
    os << "the guess is consistent in position: it is its own nearest point";
  } else {
    os << "nearest of " << rep.candidates << " distinct consistent point(s) reached from " << rep.starts
       << " starts, at distance " << rep.distance << "; "
       << (rep.local_minimum ? "a strict local minimum of the distance (first- and second-order conditions hold)"
                             : "not verified to be a local minimum of the distance (tangent part " +
                                   std::to_string(rep.stationarity) + ", curvature " +
                                   std::to_string(rep.tangent_curvature) + ")")
       << "; not proven the globally nearest (only the starts were searched)";
    if (!rep.unique) os << "; another consistent point found is as near (the nearest is not unique)";
    if (rep.rigid_nearer) os << "; a nearer point where the constraints fix every coordinate was passed over";
  }
  return os.str();
}

}  // namespace detail

template <class M>
State<coordinate_count_v<M>> consistent_initial_state(const M& model, const State<coordinate_count_v<M>>& guess,
                                                      double t, double tolerance, ConsistentStateReport* report) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
  constexpr int MH = holonomic_count_v<M>;  // (Dynamic: counted at run time)
  const int size = static_cast<int>(guess.q.size()), mh = holonomic_count(model);
  State<n> s = guess;
  ConsistentStateReport rep;
  const auto names = constraint_names(model);
  if (!guess.q.allFinite() || !guess.qd.allFinite())
    throw ConstraintError("initial guess for the consistent state is not finite");
  bool searched = false;  // (no position constraints: q_g is consistent)
  if constexpr (MH != 0) {
    if (mh > 0) {
      searched = true;
      std::optional<ConstraintError> first_error;
      const std::vector<detail::ConsistentCandidate<n>> found =
          detail::consistent_candidates(model, guess, t, tolerance, rep, first_error);
      if (found.empty()) throw *first_error;  // names every residual (project_positions)
      rep.candidates = static_cast<int>(found.size());
      const detail::ConsistentCandidate<n>* best = nullptr;
      const detail::ConsistentCandidate<n>* best_rigid = nullptr;
      for (const auto& c : found) {
        auto& slot = c.rigid ? best_rigid : best;
        if (!slot || c.distance < slot->distance) slot = &c;
      }
      if (!best)
        throw ConstraintError("the holonomic constraints fix all " + std::to_string(size) + " coordinates (rank " +
                              std::to_string(best_rigid->rank) + " at the consistent state): no motion is left");
      s.q = best->q;
      detail::polish_positions(model, s.q, t);
      rep.distance = (s.q - guess.q).norm();
      rep.stationarity = best->stationarity;
      rep.rigid_nearer = best_rigid && best_rigid->distance < best->distance;
      for (const auto& c : found)
        if (&c != best && !c.rigid && std::abs(c.distance - best->distance) <= 1e-9 * (1.0 + best->distance) &&
            (c.q - best->q).template lpNorm<Eigen::Infinity>() > 1e-6 * (1.0 + best->q.template lpNorm<Eigen::Infinity>()))
          rep.unique = false;
      const double scale = 1.0 + s.q.norm();
      if (rep.distance <= 1e-15 * scale || best->distance == 0.0) {
        rep.distance = 0;
        rep.nearest_proven = true;  // the guess is itself consistent
        rep.local_minimum = true;
      } else {
        const auto local = detail::nearest_point_model(model, s.q, guess.q, t);
        rep.stationarity = local.along.norm();
        rep.tangent_curvature = local.curvature;
        rep.local_minimum = rep.stationarity <= 1e-9 * scale && rep.tangent_curvature > 1e-8;
      }
    }
  }
  if (!searched) {
    rep.nearest_proven = true;
    rep.local_minimum = true;
  }
  if constexpr (has_constraints_v<M>) detail::make_velocities_consistent(model, s, t, tolerance, names, rep);
  if (report) {
    rep.note = detail::consistent_note(rep);
    *report = rep;
  }
  return s;
}

template <class M>
State<coordinate_count_v<M>> consistent_initial_state(const M& model, const State<coordinate_count_v<M>>& guess,
                                                      double t, double tolerance) {
  return consistent_initial_state(model, guess, t, tolerance, nullptr);
}

}  // namespace lagrangian
