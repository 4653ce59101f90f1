#pragma once
/// \file projection.hpp
/// Projection of a state onto its constraints: positions onto g = 0 by
/// Gauss–Newton with the minimum-norm step, velocities onto C q̇ + c = 0
/// in the metric of M.

#include <Eigen/Core>

#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/active_set.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/constraint_names.hpp"
#include "lagrangian/mechanics/constraint_state.hpp"
#include "lagrangian/mechanics/detail/min_norm_solver.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

namespace detail {

/// project_positions with the pseudo-inverse's workspace `solver` (sized
/// position rows × n): nothing allocated per call.
template <class M>
int project_positions_with(const M& model, Vec<double, coordinate_count_v<M>>& q, double t, double tolerance,
                           int max_iterations, const ActiveSet& active, MinNormSolver& solver) {
  constexpr int mh_v = position_rows_v<M>;
  if constexpr (mh_v == 0) {
    return 0;
  } else {
    const int mh = position_rows(model);
    if (mh == 0) return 0;
    const Vec<double, coordinate_count_v<M>> zero = Vec<double, coordinate_count_v<M>>::Zero(q.size());
    for (int it = 0; it < max_iterations; ++it) {
      auto cs = constraint_state(model, q, zero, t);
      drop_inactive(model, cs, active);
      const Vec<double, mh_v> g = cs.position.head(mh);
      const double scale = 1.0 + q.template lpNorm<Eigen::Infinity>();
      if (g.template lpNorm<Eigen::Infinity>() <= tolerance * scale) return it;
      const Eigen::Matrix<double, mh_v, coordinate_count_v<M>> G = cs.jacobian.topRows(mh);
      solver.factorize(G.data());
      Vec<double, coordinate_count_v<M>> dq(q.size());
      solver.solve(g.data(), dq.data());
      q -= dq;
      if (!q.allFinite()) break;
    }
    const auto cs = constraint_state(model, q, zero, t);
    std::ostringstream os;
    os.precision(17);
    os << "cannot satisfy the holonomic constraints: after " << max_iterations
       << " Gauss-Newton steps the residuals are";
    const auto names = constraint_names(model);
    for (int i = 0; i < mh; ++i) os << " " << names[static_cast<std::size_t>(i)] << " = " << cs.position[i];
    os << " at t = " << t;
    throw ConstraintError(os.str());
  }
}

/// project_velocities with the workspace `solver` (sized c × c, c the
/// constraint count): nothing allocated per call.
template <class M>
void project_velocities_with(const M& model, Workspace<coordinate_count_v<M>>& ws,
                             const Vec<double, coordinate_count_v<M>>& q, Vec<double, coordinate_count_v<M>>& qd,
                             double t, const ActiveSet& active, MinNormSolver& solver) {
  if constexpr (has_constraints_v<M>) {
    if (!has_constraints(model)) return;
    evaluate(model, ws, q, qd, t);
    auto cs = constraint_state(model, q, qd, t);
    drop_inactive(model, cs, active);
    detail::factor_mass_matrix(ws, q, qd, t);
    const Eigen::Matrix<double, coordinate_count_v<M>, constraint_count_v<M>> minv_ct =
        ws.cholesky.solve(cs.jacobian.transpose());
    constexpr int c = constraint_count_v<M>;
    const Mat<double, c> schur = cs.jacobian * minv_ct;
    solver.factorize(schur.data());
    const Vec<double, c> residual = cs.velocity;
    Vec<double, c> correction(residual.size());
    solver.solve(residual.data(), correction.data());
    qd -= minv_ct * correction;
  }
}

}  // namespace detail

/// Moves q onto g(q, t) = 0 by Gauss–Newton steps q ← q − G⁺ g (G⁺ the
/// minimum-norm pseudo-inverse, by complete orthogonal decomposition) until
/// ‖g‖∞ ≤ tolerance. Returns the number of iterations; throws
/// ConstraintError when `max_iterations` do not reach the tolerance.
template <class M>
int project_positions(const M& model, Vec<double, coordinate_count_v<M>>& q, double t, double tolerance = 1e-12,
                      int max_iterations = 20, const ActiveSet& active = all_active) {
  if constexpr (position_rows_v<M> == 0) {
    return 0;
  } else {
    detail::MinNormSolver solver(position_rows(model), model_size(model));
    return detail::project_positions_with(model, q, t, tolerance, max_iterations, active, solver);
  }
}

/// Projects q̇ onto C q̇ + c = 0 in the M-norm (the nearest consistent
/// velocities in kinetic energy): q̇ ← q̇ − M⁻¹Cᵀ S⁺ (C q̇ + c).
template <class M>
void project_velocities(const M& model, Workspace<coordinate_count_v<M>>& ws,
                        const Vec<double, coordinate_count_v<M>>& q, Vec<double, coordinate_count_v<M>>& qd,
                        double t, const ActiveSet& active = all_active) {
  if constexpr (has_constraints_v<M>) {
    detail::MinNormSolver solver(constraint_count(model), constraint_count(model));
    detail::project_velocities_with(model, ws, q, qd, t, active, solver);
  }
}

}  // namespace lagrangian
