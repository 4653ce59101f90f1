#pragma once
/// \file integrate.hpp
/// The integration driver, compiled once in the library: one run of a
/// System (system.hpp) with the stepper options.method names.
///
/// A run: system.start at t0, a sample there, then steps of the chosen
/// Boost.Odeint stepper to t_end (or until an event stops the run). After
/// every accepted step the driver checks that x is finite and max_steps is
/// not exceeded, lets the system stabilise its constraints and handle the
/// step's events, and samples every step (output_interval = 0), on the
/// grid t0 + k·output_interval (interpolated by dense output, or steps
/// shortened to land on it), or only at the ends (< 0). After the loop the
/// end state is sampled and, for the adaptive explicit steppers, the
/// stiffness of f at the end is estimated (report.stiffness_rho).

#include <vector>

#include "lagrangian/integrate/report.hpp"
#include "lagrangian/integrate/system.hpp"

namespace lagrangian {

/// Integrates `system` from x (2n values at options.t0) and fills the run's
/// cost and end in `report` (steps, rejected_steps, rhs_evaluations,
/// samples, t_final, stiffness_rho, warnings); x ends as the state at
/// report.t_final. Options are assumed validated (SimulationOptions::validate).
///
/// Methods: dopri5, cash_karp54, fehlberg78, bulirsch_stoer (adaptive),
/// rosenbrock4 (adaptive, implicit; Jacobian by central differences of f),
/// rk4, symplectic_rkn_sb3a_mclachlan and velocity_verlet (fixed step dt;
/// the symplectic steppers use q̈ = f(q, q̇ = 0) and so assume a separable
/// system, which the caller checks), and variational (the system's own
/// variational_step).
///
/// Throws SimulationError (with the time) when the run fails part-way: a
/// non-finite state, step-size underflow, max_steps, or a DynamicsError
/// from the system; OptionError for an unknown method.
void integrate(System& system, std::vector<double>& x, const SimulationOptions& options, RunReport& report);

}  // namespace lagrangian
