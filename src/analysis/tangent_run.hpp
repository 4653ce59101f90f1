#pragma once
// Internal: how the tangent analyses (lyapunov.cpp, floquet.cpp,
// sensitivity.cpp) check their run's options and integrate a TangentSystem
// (tangent_system.hpp) by the one driver.

#include <algorithm>
#include <string>
#include <vector>

#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/integrate.hpp"
#include "lagrangian/integrate/method.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/integrate/detail/run.hpp"
#include "tangent_system.hpp"

namespace lagrangian::detail {

/// Integrates `system` over `run` from the state (q0, q̇0) (n values each),
/// its columns as start() sets them, into x (the whole augmented state);
/// SimulationError(`stopped`) when the run ends before run.t_end (as the
/// loops count it: within rounding of t_end is there, reached()).
inline void integrate_tangents(TangentSystem& system, int n, const double* q0, const double* qd0,
                               const SimulationOptions& run, const std::string& stopped, std::vector<double>& x,
                               RunReport& report) {
  const int c = system.coordinate_count();
  system.set_run(run);
  x.assign(static_cast<std::size_t>(2 * c), 0.0);
  std::copy(q0, q0 + n, x.begin());
  std::copy(qd0, qd0 + n, x.begin() + c);
  integrate(system, x, run, report);
  if (!reached(report.t_final, run.t_end)) throw SimulationError(stopped, report.t_final);
}

/// OptionError for an invalid run or a method that cannot carry tangent
/// vectors (the symplectic and variational ones integrate a model's own
/// structure); `command` names the caller in the message.
inline void check_tangent_run(const SimulationOptions& run, const std::string& command) {
  run.validate();
  const MethodInfo& method = method_info(run.method);
  if (method.family != MethodFamily::explicit_runge_kutta && method.family != MethodFamily::gauss_radau &&
      method.family != MethodFamily::rosenbrock)
    throw OptionError(command + ": method '" + std::string(method.name) +
                      "' integrates a model's own structure, not the tangent vectors beside it; take an explicit "
                      "Runge-Kutta method (dopri5, fehlberg78, ...), gauss_radau15 or rosenbrock4");
}

}  // namespace lagrangian::detail
