#pragma once
/// \file simulate.hpp
/// Integration of the AD-derived equations of motion of a model.
///
/// The state is x = [q; q̇] (length 2n) and the first-order system is
///   ẋ = [q̇; q̈(q, q̇, t)],
/// with q̈ from accelerations(). `simulate` hands the model, as a System
/// (integrate/detail/model_system.hpp), to the driver compiled once in the library
/// (integrate.hpp), which runs the Boost.Odeint stepper chosen by name,
/// sends samples to an observer, watches the energy function and the
/// momenta of cyclic coordinates, and returns a RunReport. Per model only
/// the model's own derivatives are compiled, and the variational integrator
/// for models that opt in to it (structure_preserving_v in model.hpp).

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/integrate/detail/model_system.hpp"
#include "lagrangian/integrate/detail/observer_ref.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/fpe.hpp"
#include "lagrangian/integrate/integrate.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/params.hpp"
#include "lagrangian/mechanics/properties.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/integrate/variational.hpp"

namespace lagrangian {

namespace detail {

/// Throws OptionError when the chosen method cannot run this model: the
/// variational integrator without a compile-time number of coordinates or with Pfaffian or
/// unilateral constraints; the symplectic steppers on a model that is not
/// separable (separability_problem()).
template <class M>
void refuse_unsuited_method(const M& model, const State<coordinate_count_v<M>>& initial,
                            const SimulationOptions& options) {
  const Method m = options.method;
  const MethodInfo& info = method_info(m);
  if (info.needs_lagrangian && !structure_preserving_v<M>) {
    throw OptionError("method '" + std::string(info.name) + "' is compiled only for models that opt in to the structure-preserving methods, "
                      "and model " + model_name(model) +
                      " does not: declare 'static constexpr bool structure_preserving = true;' in the model, or pass "
                      "lagrangian::with_structure_preserving(model) (see structure_preserving_v in model.hpp)");
  }
  if (info.needs_lagrangian && !variational_supported_v<M>) {
    throw OptionError(
        "method '" + std::string(info.name) + "' cannot run model " + model_name(model) +
        ": it needs a compile-time number of coordinates and supports holonomic constraints only (no Pfaffian or "
        "unilateral constraints, no contacts); use dopri5 or fehlberg78");
  }
  if (info.needs_separable) {
    const std::string why = separability_problem(model, initial, options.t0);
    if (!why.empty())
      throw OptionError("method '" + std::string(to_string(m)) + "' needs a separable model (L = 1/2 qd^T M qd - V(q), constant M); model " +
                        model_name(model) + " is not: " + why + "; use variational, dopri5 or fehlberg78");
  }
}

/// A watched event that stops the run marks an edge of the model's domain
/// (a mass reaching its pulley, a projectile reaching its plane). A start
/// already beyond one — its function past 0 in the direction it is watched
/// for — would run where the model does not hold, so it is refused with a
/// DomainError naming the edge and the function's value.
template <class M>
void refuse_start_beyond_edges(const M& model, const State<coordinate_count_v<M>>& x0, double t0) {
  if constexpr (event_count_v<M> > 0) {
    const auto values = model.events(x0.q, x0.qd, t0);
    const std::vector<EventSpec> specs = event_specs(model);
    for (std::size_t i = 0; i < specs.size(); ++i) {
      const EventSpec& e = specs[i];
      const double v = values[static_cast<Eigen::Index>(i)];
      if (e.action != EventAction::stop) continue;
      const bool falling = e.direction == Direction::falling, rising = e.direction == Direction::rising;
      if (!((falling && v < 0) || (rising && v > 0))) continue;
      throw DomainError(model_name(model) + ": the initial state is beyond the edge '" + e.name +
                        "' of the model's domain: its event function is " + detail::format_number(v) +
                        " at t0, and the run stops where it " + (falling ? "falls" : "rises") +
                        " through 0; start on the " + (falling ? "positive" : "negative") + " side");
    }
  }
}

/// A start where the model's energy is not finite is at a singularity of
/// the model (r = 0 of a central force, two bodies at one place): refused
/// with a DomainError naming T or V, its value and the coordinates.
template <class M>
void refuse_singular_start(const M& model, const State<coordinate_count_v<M>>& x0, double t0) {
  if constexpr (has_kinetic_potential_v<M>) {
    const double T = model.kinetic(x0.q, x0.qd, t0), V = model.potential(x0.q, t0);
    if (std::isfinite(T) && std::isfinite(V)) return;
    const auto names = coordinate_names(model);
    std::ostringstream os;
    os.precision(17);
    os << model_name(model) << ": the initial state is a singularity of the model: "
       << (std::isfinite(V) ? "the kinetic energy T = " : "the potential energy V = ") << (std::isfinite(V) ? T : V)
       << " J at t0, where";
    for (std::size_t i = 0; i < names.size(); ++i)
      os << (i ? ", " : " ") << names[i] << " = " << x0.q[static_cast<Eigen::Index>(i)];
    os << " (a collision, or the centre of a central force at r = 0); start away from it";
    throw DomainError(os.str());
  } else if constexpr (detail::has_lagrangian_for<M, double>) {
    const double L = model.lagrangian(x0.q, x0.qd, t0);
    if (std::isfinite(L)) return;
    std::ostringstream os;
    os.precision(17);
    os << model_name(model) << ": the initial state is a singularity of the model: L = " << L
       << " J at t0 (a collision, or the centre of a central force at r = 0); start away from it";
    throw DomainError(os.str());
  }
}

/// The body of simulate(), compiled once per model (the observer is erased):
/// checks the input, fills the report's header, and runs the model's
/// ModelSystem through the driver (integrate.hpp).
template <class M>
RunReport simulate_impl(const M& model, const State<coordinate_count_v<M>>& initial, const SimulationOptions& options,
                        ObserverRef<coordinate_count_v<M>> observer) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
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
  refuse_start_beyond_edges(model, initial, options.t0);
  refuse_singular_start(model, initial, options.t0);

  RunReport report;
  report.model = model_name(model);
  report.coordinates = names;
  report.method = to_string(options.method);
  report.adaptive = !fixed_step_method(options.method);
  report.rtol = options.rtol;
  report.atol = options.atol;
  report.dt = options.dt;
  report.t0 = options.t0;
  report.t_end = options.t_end;
  report.conservative = !uses_generalized_forces(model) && !uses_dissipation(model) &&
                        is_autonomous(model, initial, options.t0) &&
                        constraints_workless(model, initial, options.t0);

  if constexpr (!has_constraints_v<M> || runtime_constraint_counts_v<M>) {
    if (!has_constraints(model)) {
      Workspace<n> ws(size);
      // a singular M at t0 is an input error
      free_accelerations(model, ws, initial.q, initial.qd, options.t0, ws.accelerations);
    }
  }

  ModelSystem<M> system(model, options, observer, report);
  system.prepare(initial, options.t0);
  std::vector<double> x(static_cast<std::size_t>(2 * size));
  for (int i = 0; i < size; ++i) {
    x[static_cast<std::size_t>(i)] = initial.q[i];
    x[static_cast<std::size_t>(size + i)] = initial.qd[i];
  }
  integrate(system, x, options, report);
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
RunReport simulate(const M& model, const State<coordinate_count_v<M>>& initial, const SimulationOptions& options,
                   Observer&& observer = {}) {
  check_model<M>();
  using Obs = std::remove_reference_t<Observer>;
  RunReport report = detail::simulate_impl(model, initial, options,
                                           detail::ObserverRef<coordinate_count_v<M>>::of(observer));
  if constexpr (detail::observer_with_finish<Obs>) {
    const auto start = std::chrono::steady_clock::now();
    observer.finish();
    report.wall_time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return report;
}


}  // namespace lagrangian
