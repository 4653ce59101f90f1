#pragma once
// The point masses a run's momentum monitor sums: a model's particles()
// (Cartesian coordinates, r = q) and its mass_points() (functions of q and
// t), and their total momenta P and L.

#include <array>
#include <cstddef>
#include <vector>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/mechanics/detail/min_norm_solver.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian::detail {

/// True when the model can have point masses for the monitor.
template <class M>
inline constexpr bool has_point_masses_v = has_particles_v<M> || has_mass_points_v<M>;

/// How many point masses `model` has.
template <class M>
int point_mass_count(const M& model) {
  int count = 0;
  if constexpr (has_particles_v<M>)
    for ([[maybe_unused]] const Particle& part : model.particles()) ++count;
  if constexpr (has_mass_points_v<M>) count += model.mass_point_count();
  return count;
}

/// Each point mass of `model` along the path (q + dq s + ½ ddq s², t + dt s)
/// at s = 0 (PointMotion; `ddq` null for zero), into `out` (its storage
/// reused from call to call).
template <class M>
void point_motions(const M& model, const double* q, const double* dq, const double* ddq, double t, double dt,
                   std::vector<PointMotion>& out) {
  out.clear();
  if constexpr (has_particles_v<M>) {
    for (const Particle& part : model.particles()) {
      PointMotion pm;
      pm.mass = part.mass;
      for (std::size_t a = 0; a < 3; ++a) {
        const int i = part.axes[a];
        if (i < 0) continue;
        pm.r[a] = q[i];
        pm.v[a] = dq[i];
        pm.a[a] = ddq != nullptr ? ddq[i] : 0.0;
      }
      out.push_back(pm);
    }
  }
  if constexpr (has_mass_points_v<M>) {
    const std::size_t first = out.size();
    out.resize(first + static_cast<std::size_t>(model.mass_point_count()));
    model.mass_points(q, dq, ddq, t, dt, out.data() + first);
  }
}

/// The change of q̇ that a unit impulse along the row `g` = ∂φ/∂q of a
/// contact gives at (q, q̇, t), the bilateral constraints held:
///   M Δq̇ = gᵀ + Cᵀ μ,  C Δq̇ = 0
/// (C the bilateral rows of the constraint Jacobian, μ their impulses;
/// without constraints Δq̇ = M⁻¹ gᵀ). What a contact's impulses can do to the
/// momenta of a model's mass points (ΔP = Σ m (∂r/∂q) Δq̇ per unit impulse).
template <class M, class Row>
Vec<double, coordinate_count_v<M>> unit_impulse_response(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                                         const Vec<double, coordinate_count_v<M>>& qd, double t,
                                                         const Row& g) {
  constexpr int n = coordinate_count_v<M>;
  Workspace<n> ws(static_cast<int>(q.size()));
  evaluate(model, ws, q, qd, t);
  factor_mass_matrix(ws, q, qd, t);
  Vec<double, n> dqd = ws.cholesky.solve(Vec<double, n>(g.transpose()));
  if constexpr (has_constraints_v<M>) {
    if (has_bilateral_constraints(model)) {
      auto cs = constraint_state(model, q, qd, t);
      drop_inactive(model, cs, ActiveSet{});  // (the contacts' rows are zero)
      const auto minv_ct = ws.cholesky.solve(cs.jacobian.transpose()).eval();
      const auto schur = (cs.jacobian * minv_ct).eval();
      const int rows = static_cast<int>(schur.rows());
      MinNormSolver solver(rows, rows);
      solver.factorize(schur.data(), rank_tolerance);
      const auto target = (-(cs.jacobian * dqd)).eval();
      auto mu = target;
      solver.solve(target.data(), mu.data());
      dqd += minv_ct * mu;
    }
  }
  return dqd;
}

}  // namespace lagrangian::detail
