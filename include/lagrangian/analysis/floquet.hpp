#pragma once
/// \file floquet.hpp
/// Floquet multipliers: the linear stability of a periodic motion.
///
/// For a motion x(t) of period T — a periodically driven system (period of
/// the drive) resting at an equilibrium or moving on a periodic orbit, or
/// a periodic orbit of an autonomous system — a small change δx(t0) comes
/// back after one period as δx(t0 + T) = Φ δx(t0), Φ = ∂x(t0 + T)/∂x(t0)
/// the monodromy matrix (2n × 2n, in the state coordinates (q, q̇)). It is
/// integrated as 2n tangent vectors beside the state by the variational
/// equations δẋ = J δx, J by automatic differentiation (tangent_flow.hpp),
/// in the one driver, from the unit vectors of the state. Its eigenvalues μ
/// are the Floquet multipliers: the motion is linearly stable when every
/// |μ| ≤ 1 (a Hamiltonian system's lie on the unit circle then, in pairs
/// μ, 1/μ̄), unstable when one |μ| > 1. An autonomous periodic orbit always
/// has a multiplier 1 (along the orbit).
///
/// The verdict `stable` allows |μ| ≤ 1 + tolerance (default 1e-6, above the
/// integration error of Φ at the default tolerances); `closure` =
/// max_i |x_i(t0 + T) − x_i(t0)| says how periodic the motion from the given
/// state was (the multipliers describe a periodic motion only when it is
/// small). Scope as tangent_flow.hpp: models with a fixed number n ≤ 6 of
/// coordinates.
///
/// A model with holonomic or Pfaffian constraints moves on its constraint
/// manifold (lyapunov.hpp), so its monodromy is a map of the manifold's
/// tangent space (dimension d = 2n − rank ∂h/∂(q, q̇)): the tangent
/// vectors start as an orthonormal basis B0 of the start's tangent space,
/// and the result's monodromy is C = B0ᵀ Φ B0 (d × d), with d multipliers.
/// On a closed motion Φ maps the tangent space onto itself and C is that
/// map in the basis B0; a time-periodic constraint whose manifold's tangent
/// space repeats (a spinning wire) gives the same. With find_orbit the
/// start moves in that tangent space (δx0 = B0 δ, the Newton equations
/// projected on it) and is projected back onto the manifold after each
/// step, for holonomic and Pfaffian constraints alike (the energy row is
/// ∇E from L itself; holonomic rows g(q) and Pfaffian rows A(q) q̇ = 0 do
/// no work on the motion, so E is conserved). A time-dependent constraint
/// repeats with its own period, and a Pfaffian row with a term free of q̇
/// does work: take fixed_period and keep_energy = false there, as for a
/// driven model.
///
/// With find_orbit, floquet_multipliers() first finds the periodic orbit near
/// the start and a guessed period by Newton's method on x(t0 + T; x0) − x0 = 0, with the
/// exact Jacobian [Φ − I, f(x(t0 + T))] from the same run (f = ẋ) and the
/// phase condition f(x0)·δx0 = 0 that fixes where on the orbit x0 lies. A
/// conservative system's orbits come in families, one per energy E, the
/// rest point among them: with `keep_energy` (the default) each step also
/// keeps ∇E(x0)·δx0 = 0, E = p·q̇ − L, so Newton finds the orbit at the
/// start's energy (to second order in the steps); turn it off for an
/// isolated orbit of a forced or dissipative autonomous system (a limit
/// cycle). The steps solve these rows by least squares, minimum norm. With
/// `fixed_period` (a system driven with period T) T stays and only x0
/// moves: a periodic response of the drive.
/// The result carries the multipliers of the orbit found; an autonomous
/// orbit has a multiplier 1 (along the orbit; two for a conservative one).

#include <complex>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// What floquet_multipliers() integrates, and how it finds the orbit first
/// when asked.
struct FloquetOptions {
  /// Method and tolerances, and t0 (s); the run ends at t0 + period.
  SimulationOptions run;
  double period = 0.0;        ///< T (s), > 0; with find_orbit the guess (the period itself with fixed_period)
  double tolerance = 1e-6;    ///< stable when every |μ| ≤ 1 + tolerance
  /// Find the periodic orbit near the initial state first (Newton's method,
  /// see the file comment), then its multipliers.
  bool find_orbit = false;
  bool fixed_period = false;  ///< find_orbit: keep T (a drive's period) and move only the start
  bool keep_energy = true;    ///< find_orbit: hold E = p·q̇ − L of the start (see the file comment)
  /// find_orbit: done when max_i |x_i(t0 + T) − x_i(t0)| ≤
  /// closure_tolerance (1 + max_i |x_i(t0)|).
  double closure_tolerance = 1e-8;
  int max_iterations = 20;  ///< find_orbit: Newton iterations, each one run with Φ
};

/// The monodromy matrix and its eigenvalues.
struct FloquetResult {
  Eigen::MatrixXd monodromy;                     ///< Φ (2n × 2n), in (q, q̇); B0ᵀ Φ B0 (d × d) on a constraint manifold
  std::vector<std::complex<double>> multipliers;  ///< eigenvalues of Φ (of C on a manifold), largest modulus first
  double largest_modulus = 0;                    ///< max |μ|
  bool stable = false;                           ///< every |μ| ≤ 1 + tolerance
  double closure = 0;                            ///< max_i |x_i(t0 + T) − x_i(t0)| (units of each)
  double period = 0;                             ///< T (s): the one given, or the orbit's found
  std::vector<double> q, qd;                     ///< the start at t0: the initial state, or the orbit's found
  int iterations = 0;                            ///< Newton iterations of find_orbit (0 without)
  std::uint64_t steps = 0;                       ///< accepted steps (of every iteration)
  std::uint64_t rhs_evaluations = 0;             ///< evaluations of q̈ with its Jacobian
  double seconds = 0;                            ///< wall time (s)
  int impacts = 0;                               ///< impacts crossed over the (last) period (saltation.hpp)
};

namespace detail {
/// The monodromy matrix over a TangentModel (src/analysis/floquet.cpp).
FloquetResult floquet_multipliers(const TangentModel& model, const double* q0, const double* qd0,
                                  const FloquetOptions& options);
/// ∇E = (∂E/∂q, ∂E/∂q̇) of E = p·q̇ − L at the state x = (q, q̇) (2n
/// values) and t, from L's derivatives alone (find_orbit's energy row;
/// src/analysis/floquet.cpp).
Eigen::VectorXd energy_gradient(const TangentModel& model, const Eigen::VectorXd& x, double t);
}  // namespace detail

/// The Floquet multipliers of the motion of `model` from `initial` at
/// options.run.t0 over one period (see the file comment). Throws
/// OptionError for a bad option (naming it and its value), AnalysisError
/// for constraints the tangent flow is not derived for (tangent_flow.hpp)
/// or, with find_orbit, when
/// Newton's method finds no orbit within max_iterations (with the closure
/// reached), its period leaves [T/2, 2T] of the guess T (every motion
/// closes as T → 0) or its start cannot be projected back onto a constraint
/// manifold, ConstraintError for a start off the manifold, SimulationError
/// when a run fails.
template <class M>
FloquetResult floquet_multipliers(const M& model, const State<coordinate_count_v<M>>& initial,
                                  const FloquetOptions& options) {
  constexpr int n = coordinate_count_v<M>;
  static_assert(n != Dynamic,
                "floquet_multipliers: the tangent flow is derived for models with a fixed coordinate_count");
  const detail::TangentModel tm = detail::tangent_model_of(model, "floquet: ");
  return detail::floquet_multipliers(tm, initial.q.data(), initial.qd.data(), options);
}

}  // namespace lagrangian
