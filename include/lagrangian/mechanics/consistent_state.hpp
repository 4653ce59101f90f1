#pragma once
/// \file consistent_state.hpp
/// The nearest consistent initial state of a constrained model.

#include <string>

#include "lagrangian/mechanics/active_set.hpp"
#include "lagrangian/mechanics/constrained_accelerations.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/constraint_names.hpp"
#include "lagrangian/mechanics/constraint_state.hpp"
#include "lagrangian/mechanics/dof.hpp"
#include "lagrangian/mechanics/projection.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// What consistent_initial_state() found and how sure it is that the state
/// is the nearest one (docs/constraints.md, "Consistent initial states").
struct ConsistentStateReport {
  double distance = 0;           ///< ‖q − q_guess‖₂ (units of q)
  double position_residual = 0;  ///< ‖g(q, t)‖∞ of the holonomic rows
  double velocity_residual = 0;  ///< ‖C q̇ + c‖∞
  int starts = 0;                ///< starts projected onto g = 0 (the guess, SLSQP's point, q_guess ± d eᵢ)
  int candidates = 0;            ///< distinct consistent points they reached
  /// ‖(I − G⁺G)(q_guess − q)‖₂: the tangent part of q_guess − q, 0 at a
  /// stationary point of ‖q − q_guess‖ on g = 0.
  double stationarity = 0;
  /// Smallest eigenvalue of Zᵀ(I − Σμᵢ∇²gᵢ)Z, Gᵀμ = q − q_guess, Z a null-space
  /// basis of G: > 0 at a strict local minimum of the distance (0 when not computed).
  double tangent_curvature = 0;
  bool local_minimum = false;   ///< stationarity ≈ 0 and tangent_curvature > 0
  bool unique = true;           ///< no other candidate with motion left is as near (to 1e-9)
  /// Only when the guess is itself consistent (or there are no position
  /// constraints): otherwise a nearer point the starts missed cannot be ruled out.
  bool nearest_proven = false;
  bool rigid_nearer = false;  ///< a nearer candidate where the rank is n (no motion left) was passed over
  std::string note;           ///< one sentence saying the above
};

/// The nearest consistent initial state: q minimises ‖q − q_guess‖ subject
/// to g(q, t) = 0 — the nearest of the consistent points reached from several
/// starts (Gauss–Newton from the guess, SLSQP, q_guess ± d eᵢ), each slid
/// along the manifold to a stationary point of the distance, then polished
/// to `tolerance` — and q̇ is the M-weighted projection of q̇_guess onto
/// C q̇ + c = 0. Global nearness is not proven (`report` says what is).
/// Throws ConstraintError naming the residuals when no consistent state is
/// found, and when the constraints leave no motion at every point found.
template <class M>
State<coordinate_count_v<M>> consistent_initial_state(const M& model, const State<coordinate_count_v<M>>& guess,
                                                      double t = 0.0,
                                       double tolerance = 1e-12);
/// The same, and what was found into *report (when not null).
template <class M>
State<coordinate_count_v<M>> consistent_initial_state(const M& model, const State<coordinate_count_v<M>>& guess,
                                                      double t, double tolerance, ConsistentStateReport* report);

}  // namespace lagrangian

#include "lagrangian/mechanics/detail/holonomic_derivatives.hpp"
#include "lagrangian/mechanics/detail/consistent.hpp"
