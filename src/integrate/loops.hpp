#pragma once
// The stepper loops of the driver, one per stepper family; each runs from
// options.t0 with x (2n values) and leaves the end state in x.

#include <algorithm>
#include <cstdint>

#include "lagrangian/integrate/detail/controlled_loop.hpp"
#include "lagrangian/integrate/detail/run.hpp"

namespace lagrangian::detail {

/// The explicit Runge–Kutta methods (dopri5, rk4, cash_karp54, fehlberg78,
/// bulirsch_stoer; explicit_loops.hpp) on the Odeint state std::array<double,
/// 2n> for n ≤ kMaxFixedStateSize and StateVector above: a fixed-size state
/// lets Odeint's stage arithmetic run on registers and unrolled loops, which
/// saved 15 % of the instructions of a whole run of the double pendulum
/// against a std::vector state (docs/performance.md).
void run_explicit(Run& run, StateVector& x);
inline constexpr int kMaxFixedStateSize = 12;
/// run_explicit on std::array<double, 2N> (x copied in and out): defined in
/// integrate/detail/explicit_loops.hpp, compiled in explicit_*.cpp.
template <int N>
void run_explicit_fixed(Run& run, StateVector& x);
/// run_explicit on StateVector (explicit_dynamic.cpp).
void run_explicit_dynamic(Run& run, StateVector& x);
/// Odeint's rosenbrock4 (rosenbrock_loop.cpp).
void run_rosenbrock4(Run& run, StateVector& x);
/// The 15th-order Gauss–Radau stepper (gauss_radau_loop.cpp).
void run_gauss_radau15(Run& run, StateVector& x);
/// The fixed-step structure-preserving methods (fixed_grid_loops.cpp).
void run_symplectic(Run& run, StateVector& x);
void run_variational(Run& run, StateVector& x);

/// The work of a probe integration (stiffness.cpp): accepted steps and
/// evaluations of f (a Jacobian's included), and whether it reached the end
/// of its stretch, was stopped at its cap, or failed (f throwing, a
/// non-finite state, a step underflow).
struct ProbeCost {
  enum class Outcome { failed, capped, reached };
  std::uint64_t steps = 0, evaluations = 0;
  Outcome outcome = Outcome::failed;
};

/// rosenbrock4 as run_rosenbrock4 runs it (the autonomous form, the
/// Jacobian by central differences), from (x, t) to t_end at (rtol, atol),
/// starting with the step dt, its steps landing on the sample times
/// grid_t0 + k grid (grid > 0), on f as the system has it; stopped
/// (capped) once it has used more than max_evaluations evaluations of f.
ProbeCost rosenbrock4_probe(const System& system, StateVector x, double t, double t_end, double dt, double rtol,
                            double atol, double grid_t0, double grid, std::uint64_t max_evaluations);

/// Estimates ρ, the largest |eigenvalue| of ∂f/∂x at the end state x
/// (stiffness.cpp): sets report.stiffness_rho and warns when the final step
/// size h satisfies h ρ > 1 and the run's first stretch, integrated again
/// from the initial state x0 at tighter tolerances, does not show the steps
/// set by accuracy.
void check_stiffness(const System& system, const StateVector& x, double t, double step, const StateVector& x0,
                     const SimulationOptions& options, RunReport& report);

}  // namespace lagrangian::detail
