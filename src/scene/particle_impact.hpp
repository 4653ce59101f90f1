#pragma once
// Internal to the particle scenes' engine: Newton's law at an impact of one
// contact of a particle scene, with the rows of its links and surfaces kept:
// as a plain run applies it (particle_system.cpp), and its derivatives that
// the tangent flow (particle_tangent.cpp) takes across the impact: along
// the state, for the saltation matrix, and along one of the scene's
// parameters.

#include "particle_model.hpp"

namespace lagrangian::scene::detail {

/// The impact map of contact `c` with coefficient e at (q, q̇⁻) (3N
/// positions in m, 3N velocities in m/s):
///   q̇⁺ = q̇⁻ + M⁻¹Wᵀμ,   (W M⁻¹ Wᵀ) μ = −(C q̇⁻, (1 + e) v),
/// M = diag(m) ⊗ I₃ (kg), W = [C; ∇φᵀ] the gradients of the first
/// model.fixed_rows() rows (links, surfaces; not resting contacts) and of
/// the contact's gap φ, v = ∇φ·q̇⁻ the approach speed (m/s), μ the rows'
/// impulses by the minimum-norm pseudo-inverse (redundant rows allowed).
/// Without rows this is q̇⁺_a = q̇⁻_a + J n̂/m_a, q̇⁺_b = q̇⁻_b − J n̂/m_b,
/// J = −(1 + e) v/(1/m_a + 1/m_b). Writes q̇⁺ (3N values) and ∂q̇⁺/∂(q, q̇)
/// (3N × 6N, column-major) by ad::Jets along the coordinates of the
/// contact's and the rows' bodies (every other velocity passes unchanged);
/// returns v.
double impact_map(const particles::ParticleModel& model, const particles::Contact& c, const double* q,
                  const double* qd, double e, double* qd_plus, double* jacobian);

/// The law applied by a plain run to its state x = [r; v] (the velocities
/// replaced by q̇⁺); returns the contact's impulse μ_k along ∇φ (N·s).
/// Resting contacts are not rows of the law: they take part as contacts of
/// their own (released when the impulse makes them approach, see
/// ParticleModel::wake_approaching()).
double impulse(const particles::ParticleModel& model, const particles::Contact& c, double e, double* x);

/// The same law at (q, q̇⁻) along the seeded parameter `p` (the state held
/// constant): ∂q̇⁺/∂p (3N values into `dqd_plus`), with the contact's own e,
/// or e = 0 when `plastic` (the impact that begins a rest); returns ∂φ/∂p
/// of its gap φ = n̂·(r_a − p) − R (a plane or a box wall) or
/// |r_a − r_b| − R_a − R_b (a pair): −n̂·∂p/∂p for the plane's point or the
/// box's corner, −1 for a radius (m per unit of p).
double impact_along_parameter(const particles::ParticleModel& model, const particles::Contact& c,
                              const particles::Parameter& p, const double* q, const double* qd, bool plastic,
                              double* dqd_plus);

}  // namespace lagrangian::scene::detail
