#pragma once
/// \file hard_spheres_tangent.hpp
/// The tangent flow of the event-driven hard-sphere engine (hard_spheres.hpp):
/// how the motion of a gas depends on its start, and its Lyapunov exponents.
///
/// State x = (r_1, …, r_N, v_1, …, v_N) (3N positions in m, 3N velocities
/// in m/s, in the order of HardSphereSystem::spheres, x, y, z each). A
/// tangent vector δx = (δr, δv) flies as the spheres do,
///   δr_i(t) = δr_i(t_e) + δv_i (t − t_e),   δv_i constant,
/// and crosses each impact by its saltation matrix
///   S = Dg + (f⁺ − Dg f⁻) ∇φᵀ / (∇φ · f⁻),
/// g the impact law (v⁺ = g(r, v)), f = (v, 0) the free flight before and
/// after, φ the gap. For spheres a, b (masses m_a, m_b, line of centres
/// n = (r_a − r_b)/d, relative velocity w = v_a − v_b, restitution e,
/// c_a = (1 + e) m_b/(m_a + m_b), c_b = (1 + e) m_a/(m_a + m_b)) this is, with
/// δρ = δr_a − δr_b, δw = δv_a − δv_b and s = (n·δρ)/(n·w) the shift of
/// the impact time (δt = −s):
///   δr_a ← δr_a + (v_a⁺ − v_a) s,   δr_b ← δr_b + (v_b⁺ − v_b) s,
///   δv_a ← δv_a − c_a A,            δv_b ← δv_b + c_b A,
///   A = δn (n·w) + n (δn·w) + n (n·δw),   δn = (I − n nᵀ)(δρ − s w)/d,
/// (δρ − s w is the relative displacement at the perturbed impact, tangent
/// to the contact). At a wall with inward normal n: s = (n·δr)/(n·v),
/// δr ← δr + (v⁺ − v) s, δv ← δv − (1 + e)(n·δv) n. Each saltation matrix
/// has determinant e² (1 for an elastic impact), so the whole spectrum of
/// an elastic gas sums to 0 and an inelastic one to (2/T) Σ ln e over its
/// impacts. The impacts are those of run_hard_spheres() (the same engine,
/// the TC model's elastic impacts included), seen through its
/// HardSphereImpactObserver: exact flights, no integration error.
///
/// Exponents are measured as lyapunov_spectrum() measures them: in the
/// canonical coordinates (r, p = m v), Benettin's method with Householder
/// QR, the tangent vectors starting as the first k canonical unit vectors.
/// A renormalisation follows the first impact after which a vector's length
/// in (r, v) has changed by more than a factor e since the last one, or
/// after `interval` (0: T/100); the tangent vectors are brought to that
/// time (their flights are exact), so no sample of the spheres is needed.
/// MEGNO (lyapunov.hpp) of the first vector: Y is exact, as |δx_1(t)|² is a
/// quadratic in t between impacts, whose log has a closed-form integral;
/// its mean ⟨Y⟩ is integrated by Simpson's rule over each flight.
///
/// Cost: per impact O(k) for k vectors (two spheres' rows), per
/// renormalisation O(N k²); the whole spectrum of N spheres has 6N
/// exponents, and at most kMaxHardSphereExponents are taken at once.

#include "lagrangian/analysis/fwd.hpp"
#include "lagrangian/scene/hard_spheres.hpp"

namespace lagrangian::scene {

/// Most tangent vectors lyapunov_hard_spheres() carries (the whole
/// spectrum of 100 spheres), and most spheres sensitivities_hard_spheres()
/// takes (its 6N × 6N matrix at each sample).
inline constexpr int kMaxHardSphereExponents = 600;
inline constexpr int kMaxHardSphereSensitivitySpheres = 100;

/// The k largest finite-time Lyapunov exponents (1/s) of the gas's motion
/// over [options.t0, options.t_end] (k = `exponents`, 0: all 6N), MEGNO,
/// the impacts crossed and the renormalisations (LyapunovResult; steps
/// counts the engine's events, rhs_evaluations is 0). Throws OptionError
/// (validate(); k outside [0, 6N] or above kMaxHardSphereExponents; a
/// restitution coefficient of 0, whose impacts have a singular saltation
/// matrix; interval < 0) and SimulationError as run_hard_spheres() does.
LyapunovResult lyapunov_hard_spheres(const HardSphereSystem& system, const HardSphereOptions& options,
                                     int exponents = 0, double interval = 0.0);

/// ∂x(t)/∂x(t0) (6N × 6N) and x(t) at the engine's sample times (t0, every
/// options.output_interval, t_end): SensitivityResult with state_columns
/// 6N and no parameters. OptionError for more than
/// kMaxHardSphereSensitivitySpheres spheres (and as validate()).
SensitivityResult sensitivities_hard_spheres(const HardSphereSystem& system, const HardSphereOptions& options);

}  // namespace lagrangian::scene
