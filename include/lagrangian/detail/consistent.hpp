#pragma once
// Implementation of consistent_initial_state() (declared in constraints.hpp).

#include <memory>
#include <vector>

#include <nlopt.h>

#include "lagrangian/properties.hpp"

namespace lagrangian {
namespace detail {

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
  Vec<double, coordinate_count_v<M>> q;
  for (unsigned i = 0; i < n; ++i) q[static_cast<int>(i)] = x[i];
  auto cs = constraint_state(*p.model, q, Vec<double, coordinate_count_v<M>>::Zero().eval(), p.t);
  drop_inactive<M>(cs, ActiveSet{0});
  for (unsigned i = 0; i < m; ++i) {
    result[i] = cs.position[static_cast<int>(i)];
    if (grad)
      for (unsigned k = 0; k < n; ++k) grad[i * n + k] = cs.jacobian(static_cast<int>(i), static_cast<int>(k));
  }
}

}  // namespace detail

template <class M>
State<coordinate_count_v<M>> consistent_initial_state(const M& model, const State<coordinate_count_v<M>>& guess,
                                                      double t, double tolerance) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
  constexpr int mh = holonomic_count_v<M>;
  State<n> s = guess;
  const auto names = constraint_names(model);
  if (!guess.q.allFinite() || !guess.qd.allFinite())
    throw ConstraintError("initial guess for the consistent state is not finite");
  if constexpr (mh > 0) {
    // Counting constraints would refuse an over-constrained mechanism whose
    // rows are dependent (three parallel cranks: 3 rows, rank 2, 1 DOF); the
    // rank is judged on the solution below, where it is meaningful.
    detail::ConsistencyProblem<M> problem{&model, guess.q, t};
    std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(nlopt_create(NLOPT_LD_SLSQP, n), &nlopt_destroy);
    nlopt_set_min_objective(opt.get(), &detail::consistency_objective<M>, &problem);
    std::vector<double> tol(static_cast<std::size_t>(mh), 1e-14);
    nlopt_add_equality_mconstraint(opt.get(), mh, &detail::consistency_constraints<M>, &problem, tol.data());
    nlopt_set_xtol_rel(opt.get(), 1e-14);
    nlopt_set_maxeval(opt.get(), 500);
    std::vector<double> x(guess.q.data(), guess.q.data() + n);
    double f = 0;
    const nlopt_result r = nlopt_optimize(opt.get(), x.data(), &f);
    if (r > 0 || r == NLOPT_ROUNDOFF_LIMITED) {
      for (int i = 0; i < n; ++i) s.q[i] = x[static_cast<std::size_t>(i)];
    }
    // Polish (or, if SLSQP failed, try from the guess) with Gauss–Newton; it
    // throws ConstraintError naming the residuals when no solution is reached.
    project_positions(model, s.q, t, tolerance, 50, ActiveSet{0});
    // With dependent rows SLSQP can stop short of the nearest point: move
    // along the manifold toward the guess until q_guess − q is normal to it
    // (no component in the null space of G), projecting back each time.
    detail::MinNormSolver normal_solver(mh, mh);
    for (int it = 0; it < 30; ++it) {
      const auto cg = constraint_state(model, s.q, Vec<double, n>::Zero().eval(), t);
      const Eigen::Matrix<double, mh, n> G = cg.jacobian.template topRows<mh>();
      const Eigen::Matrix<double, mh, mh> GGt = G * G.transpose();
      const Vec<double, n> d = guess.q - s.q;
      const Vec<double, mh> Gd = G * d;
      Vec<double, mh> y;
      normal_solver.factorize(GGt.data(), rank_tolerance);
      normal_solver.solve(Gd.data(), y.data());
      const Vec<double, n> along = d - G.transpose() * y;
      if (!(along.norm() > 1e-14 * (1.0 + s.q.norm()))) break;
      s.q += along;
      project_positions(model, s.q, t, tolerance, 50, ActiveSet{0});
    }
    auto cq = constraint_state(model, s.q, s.qd, t);
    const int rank = detail::numeric_rank(cq.jacobian.topRows(mh));
    if (rank >= n && detail::constraints_workless(model, s, t))
      throw ConstraintError("the holonomic constraints fix all " + std::to_string(n) + " coordinates (rank " +
                            std::to_string(rank) + " at the consistent state): no motion is left");
  }
  if constexpr (has_constraints_v<M>) {
    Workspace<n> ws;
    project_velocities(model, ws, s.q, s.qd, t, ActiveSet{0});
    auto cs = constraint_state(model, s.q, s.qd, t);
    drop_inactive<M>(cs, ActiveSet{0});
    const double scale = 1.0 + s.qd.template lpNorm<Eigen::Infinity>();
    for (int i = 0; i < constraint_count_v<M>; ++i) {
      if (!(std::abs(cs.velocity[i]) <= 1e3 * tolerance * scale)) {
        std::ostringstream os;
        os.precision(17);
        os << "cannot make the velocities consistent: constraint " << names[static_cast<std::size_t>(i)]
           << " has velocity residual " << cs.velocity[i] << " after projection (rank-deficient constraints at t = "
           << t << "?)";
        throw ConstraintError(os.str());
      }
    }
  }
  return s;
}

}  // namespace lagrangian
