#pragma once
/// \file constraints.hpp
/// Constrained systems: holonomic constraints g(q, t) = 0 and Pfaffian
/// (nonholonomic) constraints A(q, t) q̇ + a(q, t) = 0, declared in the model
/// like T and V:
///
///   template <class S> Vec<S, m> holonomic(const Vec<S, n>& q, const S& t) const;
///   template <class S> Vec<S, k> pfaffian(const Vec<S, n>& q, const Vec<S, n>& qd, const S& t) const;
///
/// (the Pfaffian expression is written as the whole of A q̇ + a and must be
/// affine in q̇), optionally with `holonomic_names()` / `pfaffian_names()`;
/// and unilateral constraints g(q, t) ≥ 0,
///
///   template <class S> Vec<S, u> unilateral(const Vec<S, n>& q, const S& t) const;
///
/// which act like holonomic ones while active (contact) and are released when
/// their multiplier would pull (see simulate.hpp).
///
/// All constraints are used at the velocity level, C(q, t) q̇ + c(q, t) = 0, with
/// the rows of C the holonomic Jacobian G = ∂g/∂q and the Pfaffian A = ∂φ/∂q̇.
/// Differentiating once more, C q̈ + γ = 0, where γ is the second derivative of
/// g along the path (δq, δt) = (q̇, 1), and for Pfaffian rows the derivative of
/// φ along (q̇, 1) at fixed q̇. With Lagrange multipliers λ the equations of
/// motion are the saddle-point system
///   M q̈ = f + Cᵀ λ,    C q̈ = −γ − b,
/// where f is the unconstrained right-hand side, Cᵀλ the generalized
/// constraint force (λ is the force along +∇g of each constraint, in N for a
/// length constraint) and b the Baumgarte term. It is solved by the Schur
/// complement S = C M⁻¹ Cᵀ, factorised with a complete orthogonal
/// decomposition so that redundant constraints (S singular) still give the
/// minimum-norm multipliers and the right q̈.
///
/// This header includes the parts, one job each: constraint_counts.hpp (how
/// many rows of each kind), active_set.hpp (which contacts are shut),
/// constraint_names.hpp (names, multiplier units), constraint_state.hpp
/// (C, g, ġ, γ by AD), constrained_accelerations.hpp (q̈ and λ), dof.hpp
/// (ranks, degrees of freedom, redundant rows), projection.hpp (onto the
/// constraints) and consistent_state.hpp (the nearest consistent state).

#include "lagrangian/mechanics/active_set.hpp"
#include "lagrangian/mechanics/constrained_accelerations.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/constraint_names.hpp"
#include "lagrangian/mechanics/constraint_state.hpp"
#include "lagrangian/mechanics/dof.hpp"
#include "lagrangian/mechanics/projection.hpp"
// Last: its definitions (detail/consistent.hpp) use all of the above.
#include "lagrangian/mechanics/consistent_state.hpp"
