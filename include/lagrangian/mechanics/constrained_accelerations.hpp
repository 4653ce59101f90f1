#pragma once
/// \file constrained_accelerations.hpp
/// q̈ and the multipliers λ of a constrained model: the saddle-point
/// system M q̈ = f + Cᵀλ, C q̈ = −γ − b solved through the Schur complement
/// (constraints.hpp has the derivation).

#include <Eigen/Core>

#include "lagrangian/mechanics/active_set.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/constraint_state.hpp"
#include "lagrangian/mechanics/detail/min_norm_solver.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// Scratch space of a constrained evaluation, for n coordinates and c
/// constraint rows (the template sizes, or given at run time for Dynamic).
template <int N, int C>
struct ConstraintWorkspace {
  ConstraintWorkspace() : ConstraintWorkspace(N == Dynamic ? 0 : N, C == Dynamic ? 0 : C) {}
  ConstraintWorkspace(int n, int c)
      : minv_ct(n, c), schur(c, c), schur_solver(c, c), multipliers(c), constraint_forces(n), free(n), target(c) {}
  Eigen::Matrix<double, N, C> minv_ct;  ///< M⁻¹ Cᵀ
  Mat<double, C> schur;                 ///< S = C M⁻¹ Cᵀ
  /// S⁺ by a decomposition compiled once in the library (min_norm_solver.hpp),
  /// its storage allocated once here.
  detail::MinNormSolver schur_solver;
  Vec<double, C> multipliers;        ///< λ
  Vec<double, N> constraint_forces;  ///< Cᵀ λ
  Vec<double, N> free;               ///< M⁻¹ f
  Vec<double, C> target;             ///< −γ − b − C M⁻¹ f
  ConstraintState<N, C> state;       ///< C, g, ġ, γ at the last evaluation
};

/// The ConstraintWorkspace of model M (its n coordinates and all its constraint rows).
template <class M>
using ConstraintWorkspaceFor = ConstraintWorkspace<coordinate_count_v<M>, constraint_count_v<M>>;

/// A ConstraintWorkspaceFor<M> sized for `model` (needed when its sizes are run-time ones).
template <class M>
ConstraintWorkspaceFor<M> constraint_workspace(const M& model) {
  return ConstraintWorkspaceFor<M>(model_size(model), constraint_count(model));
}

/// q̈ and λ of a constrained model (see the file comment for the system).
/// `omega` > 0 adds the Baumgarte term with that rate (1/s); unilateral
/// constraints not in `active` are left out. A model whose only constraints
/// are unilateral, none of them active, takes the unconstrained path (λ = 0).
/// Nothing is allocated when `cw` is sized for the model.
template <class M>
void constrained_accelerations(const M& model, Workspace<coordinate_count_v<M>>& ws, ConstraintWorkspaceFor<M>& cw,
                               const Vec<double, coordinate_count_v<M>>& q, const Vec<double, coordinate_count_v<M>>& qd,
                               double t, Vec<double, coordinate_count_v<M>>& out, double omega = 0.0,
                               const ActiveSet& active = all_active) {
  if (!has_bilateral_constraints(model) && !active.any(unilateral_count(model))) {
    // contacts only, none touching (or no constraints at all): free motion
    detail::free_accelerations(model, ws, q, qd, t, out);
    cw.multipliers.setZero();
    cw.constraint_forces.setZero();
    return;
  }
  evaluate(model, ws, q, qd, t);
  detail::factor_mass_matrix(ws, q, qd, t);
  auto& cs = cw.state;
  constraint_state_into(model, q, qd, t, cs);
  drop_inactive(model, cs, active);
  const int rows = static_cast<int>(cs.position.size());
  const int mh = position_rows(model);
  cw.target = -cs.gamma;
  if (omega > 0) {
    for (int i = 0; i < rows; ++i) {
      if (i < mh) {
        cw.target[i] -= 2.0 * omega * cs.velocity[i] + omega * omega * cs.position[i];
      } else {
        cw.target[i] -= omega * cs.velocity[i];
      }
    }
  }
  cw.minv_ct = cs.jacobian.transpose();
  ws.cholesky.solve(cw.minv_ct.data(), cw.minv_ct.data(), static_cast<int>(cw.minv_ct.cols()));
  cw.schur.noalias() = cs.jacobian * cw.minv_ct;
  cw.schur_solver.factorize(cw.schur.data());
  cw.free = ws.rhs;
  ws.cholesky.solve(cw.free.data(), cw.free.data());
  cw.target.noalias() -= cs.jacobian * cw.free;
  cw.schur_solver.solve(cw.target.data(), cw.multipliers.data());
  cw.constraint_forces.noalias() = cs.jacobian.transpose() * cw.multipliers;
  out = cw.free;
  out.noalias() += cw.minv_ct * cw.multipliers;
}

/// Convenience form of constrained_accelerations() that allocates its own
/// workspaces and returns q̈, every constraint row active, no stabilisation;
/// the multipliers λ go to `*multipliers` when it is given. For repeated
/// calls keep a Workspace and a ConstraintWorkspaceFor<M> and use the form above.
template <class M>
  requires has_constraints_v<M>
Vec<double, coordinate_count_v<M>> constrained_accelerations(const M& model,
                                                             const Vec<double, coordinate_count_v<M>>& q,
                                              const Vec<double, coordinate_count_v<M>>& qd, double t = 0.0,
                                              Vec<double, constraint_count_v<M>>* multipliers = nullptr) {
  Workspace<coordinate_count_v<M>> ws(static_cast<int>(q.size()));
  ConstraintWorkspaceFor<M> cw = constraint_workspace(model);
  Vec<double, coordinate_count_v<M>> qdd(q.size());
  constrained_accelerations(model, ws, cw, q, qd, t, qdd);
  if (multipliers) *multipliers = cw.multipliers;
  return qdd;
}

}  // namespace lagrangian
