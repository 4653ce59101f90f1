#pragma once
/// \file simulate.hpp
/// Integration of the AD-derived equations of motion with Boost.Odeint.
///
/// The state is x = [q; q̇] (length 2n) and the first-order system is
///   ẋ = [q̇; q̈(q, q̇, t)],
/// with q̈ from accelerations(). `simulate` drives an Odeint stepper chosen by
/// name, sends samples to an observer, watches the energy function and the
/// momenta of cyclic coordinates, and returns a RunReport.

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>

#include "lagrangian/constraints.hpp"
#include "lagrangian/detail/first_order_system.hpp"
#include "lagrangian/detail/fixed_grid_loops.hpp"
#include "lagrangian/detail/observer_ref.hpp"
#include "lagrangian/detail/rk_loops.hpp"
#include "lagrangian/detail/rosenbrock_loop.hpp"
#include "lagrangian/detail/run_state.hpp"
#include "lagrangian/detail/stiffness_check.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/fpe.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/observers.hpp"
#include "lagrangian/properties.hpp"
#include "lagrangian/report.hpp"
#include "lagrangian/variational.hpp"

namespace lagrangian {

namespace detail {

/// Throws OptionError when the chosen method cannot run this model: the
/// variational integrator without a compile-time dof or with Pfaffian or
/// unilateral constraints; the symplectic steppers on a model that is not
/// separable (separability_problem()).
template <class M>
void refuse_unsuited_method(const M& model, const State<M::dof>& initial, const SimulationOptions& options) {
  const std::string& m = options.method;
  if (m == "variational" && !variational_supported_v<M>) {
    throw OptionError(
        "method 'variational' cannot run model " + model_name(model) +
        ": it needs a compile-time number of coordinates and supports holonomic constraints only (no Pfaffian or "
        "unilateral constraints, no contacts); use dopri5 or fehlberg78");
  }
  if (m == "symplectic_rkn_sb3a_mclachlan" || m == "velocity_verlet") {
    const std::string why = separability_problem(model, initial, options.t0);
    if (!why.empty())
      throw OptionError("method '" + m + "' needs a separable model (L = 1/2 qd^T M qd - V(q), constant M); model " +
                        model_name(model) + " is not: " + why + "; use variational, dopri5 or fehlberg78");
  }
}

/// The body of simulate(), compiled once per model (the observer is erased).
template <class M>
RunReport simulate_impl(const M& model, const State<M::dof>& initial, const SimulationOptions& options,
                        ObserverRef<M::dof> observer) {
  check_model<M>();
  constexpr int n = M::dof;
  namespace odeint = boost::numeric::odeint;
#if defined(LAGRANGIAN_TRAP_FE_INVALID) && LAGRANGIAN_TRAP_FE_INVALID
  const FloatingPointTrap trap;  // debug builds: the first NaN raises SIGFPE where it is made
#endif
  const auto wall_start = std::chrono::steady_clock::now();
  options.validate();
  const int size = model_size(model);
  const auto names = coordinate_names(model);
  if (initial.q.size() != size || initial.qd.size() != size)
    throw OptionError("initial state has " + std::to_string(initial.q.size()) + " coordinates and " +
                      std::to_string(initial.qd.size()) + " velocities; the model has " + std::to_string(size));
  for (int i = 0; i < size; ++i) {
    if (!std::isfinite(initial.q[i]) || !std::isfinite(initial.qd[i])) {
      std::ostringstream os;
      os << "initial state: " << (std::isfinite(initial.q[i]) ? "qd" : "q") << "[" << i << "] ('"
         << names[static_cast<std::size_t>(i)] << "') is "
         << (std::isfinite(initial.q[i]) ? initial.qd[i] : initial.q[i]) << "; it must be finite";
      throw OptionError(os.str());
    }
  }

  refuse_unsuited_method(model, initial, options);

  RunReport report;
  report.model = model_name(model);
  report.coordinates = names;
  report.method = options.method;
  report.adaptive = !fixed_step_method(options.method);
  report.rtol = options.rtol;
  report.atol = options.atol;
  report.dt = options.dt;
  report.t0 = options.t0;
  report.t_end = options.t_end;
  report.conservative = !has_generalized_forces_v<M> && !has_dissipation_v<M> &&
                        is_autonomous(model, initial, options.t0) &&
                        constraints_workless(model, initial, options.t0);

  Workspace<n> ws(size);
  if constexpr (!has_constraints_v<M>)
    accelerations(model, ws, initial.q, initial.qd, options.t0);  // a singular M at t0 is an input error

  RunState<M> rs(model, options, observer, report);
  FirstOrderSystem<M> sys{&model, &ws, &report.rhs_evaluations};
  [[maybe_unused]] std::conditional_t<has_constraints_v<M>, ConstraintContext<M>, None> constraint_context{};
  if constexpr (has_constraints_v<M>) {
    constraint_context.omega = options.stabilization == Stabilization::baumgarte ? options.baumgarte_omega : 0.0;
    sys.constraints = &constraint_context;
    rs.attach(&constraint_context);
  }
  using X = StateBuffer<n>;
  X x = make_buffer<n>(size);
  for (int i = 0; i < size; ++i) {
    x[i] = initial.q[i];
    x[size + i] = initial.qd[i];
  }
  {
    const State<n> start = rs.start(initial);  // impacts at t0 may change the velocities
    for (int i = 0; i < size; ++i) {
      x[static_cast<std::size_t>(i)] = start.q[i];
      x[static_cast<std::size_t>(size + i)] = start.qd[i];
    }
  }
  try {
    const std::string& m = options.method;
    if (m == "dopri5") {
      run_out_of_line<M>([&] { run_dopri5(sys, x, options, rs); });
    } else if (m == "rk4") {
      run_out_of_line<M>([&] { run_rk4(sys, x, options, rs); });
    } else if (m == "cash_karp54") {
      using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_cash_karp54<X>>;
      run_out_of_line<M>([&] { run_controlled<Controlled>(sys, x, options, rs); });
    } else if (m == "fehlberg78") {
      using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<X>>;
      run_out_of_line<M>([&] { run_controlled<Controlled>(sys, x, options, rs); });
    } else if (m == "bulirsch_stoer") {
      run_out_of_line<M>([&] { run_controlled<odeint::bulirsch_stoer<X>>(sys, x, options, rs); });
    } else if (m == "rosenbrock4") {
      run_rosenbrock4(sys, x, options, rs);
    } else if (m == "variational") {
      run_variational(model, x, options, rs, report);
    } else if (m == "symplectic_rkn_sb3a_mclachlan" || m == "velocity_verlet") {
      run_symplectic(model, ws, x, options, rs, report);
    } else {
      throw OptionError("unreachable: unknown method '" + m + "'");
    }
  } catch (const DynamicsError& e) {
    throw SimulationError(std::string("run stopped: ") + e.what(), std::numeric_limits<double>::quiet_NaN());
  }
  rs.finish(x.data());
  if (report.adaptive && options.method != "rosenbrock4") check_stiffness(sys, x, report.t_final, rs.recent_step(), report);
  report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return report;
}

}  // namespace detail

/// Integrates a model from `initial` over [options.t0, options.t_end] and
/// returns what the run cost and how accurate it was. Samples go to
/// `observer` (see observers.hpp); its finish() is called only on success.
///
/// Throws OptionError for invalid options or a non-finite initial state,
/// DynamicsError when M is singular at t0, ConstraintError for an unusable
/// constraint set or an inconsistent initial state, and SimulationError (with
/// the time) when the run fails part-way: a non-finite state, step-size
/// underflow, max_steps, or a singular mass matrix met during the run.
template <class M, class Observer = NullObserver>
RunReport simulate(const M& model, const State<M::dof>& initial, const SimulationOptions& options,
                   Observer&& observer = {}) {
  check_model<M>();
  using Obs = std::remove_reference_t<Observer>;
  RunReport report = detail::simulate_impl(model, initial, options, detail::ObserverRef<M::dof>::of(observer));
  if constexpr (detail::observer_with_finish<Obs>) {
    const auto start = std::chrono::steady_clock::now();
    observer.finish();
    report.wall_time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return report;
}


}  // namespace lagrangian
