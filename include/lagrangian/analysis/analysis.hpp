#pragma once
/// \file analysis.hpp
/// Analysis beyond simulation: equilibria, small oscillations about them, and
/// boundary-value problems solved by making the discrete action stationary.
///
/// **Effective potential.** Everything here starts from the Lagrangian at
/// rest, U(q) = −L(q, q̇ = 0, t) (J). For a natural system (T quadratic in
/// q̇) U = V; when T has a part T₀ that does not depend on q̇ (a bead on a
/// spinning hoop) U = V − T₀, the potential of the centrifugal field included.
/// q* is an equilibrium (q(t) = q* is a motion) exactly when ∂L/∂q(q*, 0) = 0,
/// i.e. ∇U(q*) = 0; with holonomic constraints g(q) = 0 (m rows, Jacobian G)
///   ∇U(q*) = Gᵀ λ,   g(q*) = 0,
/// where Gᵀλ is the generalized constraint force holding the system at rest
/// (the sign convention of constraints.hpp: M q̈ = f + Cᵀλ).
///
/// **Stability.** With Z an orthonormal basis of the tangent space (the null
/// space of G), the Hessian of U on the constraint manifold is
///   K_t = Zᵀ (∇²U − Σ_i λ_i ∇²g_i) Z      (J per unit², e.g. J/rad², N/m),
/// the constraint curvature term included. K_t positive definite ⇒ q* is a
/// strict minimum of U on the manifold and, by Lagrange–Dirichlet, stable
/// (for natural systems; gyroscopic terms can stabilise more, never less);
/// a negative eigenvalue ⇒ unstable for natural systems.
///
/// **Small oscillations.** Expanding L to second order about (q*, 0) gives
///   M q̈ + G_y q̇ + K q = 0,  M = ∂²L/∂q̇²,  K = −∂²L/∂q² (+ constraint curvature),
///   G_y = C − Cᵀ,  C_ij = ∂²L/∂q̇_i∂q_j    (gyroscopic, zero for natural systems),
/// in tangent coordinates ξ (q = q* + Z ξ). Without G_y the motion is a sum
/// of normal modes: K_t v = ω² M_t v (generalized symmetric eigenproblem),
/// ω in rad/s, shapes v normalised vᵀ M_t v = 1 and reported in the
/// original coordinates Z v. The linear model x = [ξ; ξ̇], ẋ = A x,
///   A = [[0, I], [−M_t⁻¹ K_t, −M_t⁻¹ G_t]]   (1/s, 1/s²),
/// is given for users who want it, with its eigenvalues (growth rates and
/// frequencies with gyroscopic terms).
///
/// **Stationary action.** Given q(t₀) = a and q(t₁) = b, the path on a
/// uniform grid t_k = t₀ + k h, h = (t₁ − t₀)/K, whose discrete action
/// S_d = Σ_k L_d(q_k, q_{k+1}) (J·s, discrete.hpp) is stationary in the
/// interior points q_1 … q_{K−1}: the discrete Euler–Lagrange equations
///   D2 L_d(q_{k−1}, q_k) + D1 L_d(q_k, q_{k+1}) = 0,
/// a block-tridiagonal system solved by Newton's method (its Jacobian is the
/// Hessian of S_d, from D11, D12, D22). Newton finds any stationary point,
/// minimum or saddle; the number of negative eigenvalues of the Hessian (its
/// Morse index) says which. Second-order accurate in h.

#include "lagrangian/analysis/bvp.hpp"         // IWYU pragma: export
#include "lagrangian/analysis/equilibria.hpp"  // IWYU pragma: export
#include "lagrangian/analysis/floquet.hpp"     // IWYU pragma: export
#include "lagrangian/analysis/linearisation.hpp"  // IWYU pragma: export
#include "lagrangian/analysis/lyapunov.hpp"       // IWYU pragma: export
#include "lagrangian/analysis/modes.hpp"       // IWYU pragma: export
#include "lagrangian/analysis/sensitivity.hpp"  // IWYU pragma: export
