#pragma once
/// \file scene/analysis.hpp
/// Equilibria, normal modes and stationary-action boundary-value problems of
/// a scene's built-in model (analysis.hpp), as `lagrangian inspect
/// --equilibria --modes` and `lagrangian solve-bvp` run them. Particle
/// scenes are refused (OptionError naming the option).

#include <string>
#include <vector>

#include "lagrangian/analysis/analysis.hpp"
#include "lagrangian/scene/scene.hpp"

namespace lagrangian::scene {

/// What to analyse beyond the inspection text.
struct AnalysisRequest {
  bool equilibria = false;        ///< find and classify equilibria
  bool modes = false;             ///< normal modes (about each stable or degenerate equilibrium found)
  bool modes_at_initial = false;  ///< normal modes about the scene's initial q instead
  /// Starts of the equilibrium search: the scene's initial q, then starts − 1
  /// points of a Halton sequence, angles (unit rad) over [−π, π), other
  /// coordinates over q0 ± max(1, 2|q0|) in their units.
  int starts = 16;
};

/// The text of the analyses (equilibria table, modes) for a built-in-model
/// scene. Throws OptionError (an option and why: particle scene, starts < 1)
/// and AnalysisError (the model does not suit: Pfaffian or unilateral
/// constraints, generalized forces).
std::string analyse(const Scene& scene, const AnalysisRequest& request);

/// A stationary-action boundary-value problem on a scene's model.
struct BvpRequest {
  std::vector<double> from;  ///< q(t0), one value per coordinate (units of each coordinate)
  std::vector<double> to;    ///< q(t1)
  double t0 = 0.0;           ///< s
  double t1 = 1.0;           ///< s, > t0
  int steps = 200;           ///< K intervals, 2 … 100000
  std::string rule = "midpoint";  ///< discrete Lagrangian: midpoint or trapezoidal
  std::string out_dir;       ///< where bvp_path.csv and the plots go; empty: write nothing
  bool plots = true;
  bool png = true;
  bool svg = true;
};

/// What solve_bvp() found and wrote.
struct BvpRun {
  BvpResult result;                       ///< path, momenta, action, Morse index (analysis.hpp)
  std::vector<std::string> coordinates;   ///< the model's coordinate names
  std::vector<std::string> units;
  std::vector<std::string> files;         ///< files written
  std::string plot_note;                  ///< why plots were skipped, if they were
  /// A few lines for a terminal: iterations, residual, action, Morse index, end velocities.
  std::string summary() const;
};

/// Solves the boundary-value problem on the scene's built-in model and, with
/// out_dir, writes `bvp_path.csv` (t, q…, q_dot…, energy; through a .partial
/// file renamed on success) and its plots. Throws OptionError for bad input
/// (naming --from, --to, --time, --steps; particle scenes; models with
/// constraints, forces or dissipation) and AnalysisError when the problem is
/// singular or Newton's method does not converge.
BvpRun solve_bvp(const Scene& scene, const BvpRequest& request);

/// Lyapunov exponents of a scene's model, built in or stated as text
/// (analysis/lyapunov.hpp, text/tangent_flow.hpp), or of a particle scene's
/// bodies (q their 3N positions; their links and surfaces kept, their
/// contacts crossed at their impacts), as `lagrangian
/// lyapunov` runs them: from the scene's initial state, over its run (t0,
/// t_end, method, rtol, atol).
struct LyapunovRequest {
  int exponents = 0;      ///< k in [1, 2n]; 0: all 2n
  double interval = 0.0;  ///< longest time between renormalisations (s); 0: (t_end − t0)/100
};

/// What lyapunov() found.
struct LyapunovRun {
  LyapunovResult result;
  std::string model;       ///< the model's registry name ("text" for a model stated as text, "particles" for bodies)
  SimulationOptions run;   ///< the run the exponents come from
  /// A few lines for a terminal: the exponents (1/s), their sum, MEGNO, the
  /// intervals and the cost.
  std::string summary() const;
  /// One JSON object: spectrum (1/s, largest first), sum (1/s), megno (the
  /// mean ⟨Y⟩), megno_final (Y at t_end), t0, t_end (s), method, rtol, atol,
  /// renormalisations, interval_min, interval_max (s), steps, evaluations,
  /// seconds.
  std::string json() const;
};

/// The Lyapunov exponents and MEGNO of the scene's model or bodies. Throws
/// OptionError for a bad request (naming it), a particle scene with rows and
/// contacts together, a gas or more than 100 bodies, or a model the tangent
/// flow is not derived for (constraints with contacts, more than 6
/// coordinates, a C++ model with a run-time number of them), and
/// SimulationError when the run fails.
LyapunovRun lyapunov(const Scene& scene, const LyapunovRequest& request);

/// Floquet multipliers of a scene's model (built in or stated as text) or of
/// a particle scene's bodies (as for lyapunov()) over one period
/// (analysis/floquet.hpp), as `lagrangian floquet` runs them: from the
/// scene's initial state at its t0, with its method and tolerances.
struct FloquetRequest {
  double period = 0.0;      ///< T (s), > 0; with find_orbit the guess
  double tolerance = 1e-6;  ///< stable when every |μ| ≤ 1 + tolerance
  /// Find the periodic orbit near the initial state first (FloquetOptions).
  bool find_orbit = false;
  bool fixed_period = false;  ///< with find_orbit: T is the drive's, only the start moves
  bool keep_energy = true;    ///< with find_orbit: hold the start's energy
};

/// What floquet() found.
struct FloquetRun {
  FloquetResult result;
  std::string model;      ///< the model's registry name ("text" for a model stated as text, "particles" for bodies)
  SimulationOptions run;  ///< method, tolerances, t0
  double period = 0;      ///< s
  double tolerance = 0;
  bool find_orbit = false;
  /// A few lines for a terminal: the orbit found (with find_orbit), the
  /// multipliers (re, im, modulus), the verdict, the closure and the cost.
  std::string summary() const;
  /// One JSON object: multipliers ([re, im] pairs, largest modulus first),
  /// stable, largest_modulus, tolerance, closure, period (s; the orbit's
  /// with find_orbit), t0 (s), method, rtol, atol, steps, evaluations,
  /// seconds; with find_orbit also q, qd (the orbit's start) and
  /// iterations.
  std::string json() const;
};

/// The Floquet multipliers of the scene's model or bodies. Throws
/// OptionError for a bad request (naming --period, --tolerance), a particle
/// scene or a model the tangent flow is not derived for (as for
/// lyapunov()), AnalysisError when the multipliers
/// cannot be computed, and SimulationError when the run fails.
FloquetRun floquet(const Scene& scene, const FloquetRequest& request);

/// How the motion of a scene's model (built in or stated as text) or of a
/// particle scene's bodies depends on where it starts and on the model's
/// parameters (analysis/sensitivity.hpp), as `lagrangian sensitivity` runs
/// it: ∂x(t_end)/∂x(t0) and ∂x(t_end)/∂p, x = (q, q̇), from the scene's
/// initial state over its run (t0, t_end, method, rtol, atol).
struct SensitivityRequest {
  /// The parameters p_j, by name as in the scene's [model.parameters].
  std::vector<std::string> parameters;
  bool initial_state = true;  ///< the 2n columns ∂x(t_end)/∂x(t0)
};

/// What sensitivity() found.
struct SensitivityRun {
  SensitivityResult result;
  std::string model;      ///< the model's registry name ("text", "particles")
  SimulationOptions run;  ///< the run the sensitivities come from
  /// A few lines for a terminal: x(t_end), the state transition matrix and
  /// the parameter columns, the impacts crossed and the cost.
  std::string summary() const;
  /// One JSON object: model, t0, t_end (s), state (x(t_end), 2n values),
  /// state_transition (2n rows of 2n: ∂x_i(t_end)/∂x_j(t0); Φ P0 on a
  /// constraint manifold; absent without the initial state's columns),
  /// parameters (name: the 2n values ∂x(t_end)/∂p), impacts, method, rtol,
  /// atol, steps, evaluations, seconds.
  std::string json() const;
};

/// The sensitivities of the scene's model or bodies. Throws OptionError for
/// an unknown parameter (naming it and the model's), parameters of a
/// particle scene, or a scene the tangent flow is not derived for;
/// AnalysisError for parameters a built-in model does not offer, parameters
/// of a model whose contacts do not follow its parameters or parameters
/// that move its constraint manifold past the start; SimulationError when
/// the run fails.
SensitivityRun sensitivity(const Scene& scene, const SensitivityRequest& request);

}  // namespace lagrangian::scene
