#include "lagrangian/integrate/integrate.hpp"

#include <limits>
#include <string>

#include "lagrangian/errors.hpp"
#include "loops.hpp"

namespace lagrangian {

void System::variational_step(double, double, double*) {
  throw OptionError("method 'variational' needs the system's own variational stepper, and this system has none");
}

void integrate(System& system, std::vector<double>& x, const SimulationOptions& options, RunReport& report) {
  using namespace detail;
  const int n = system.coordinate_count();
  if (x.size() != static_cast<std::size_t>(2 * n))
    throw OptionError("integrate: the state has " + std::to_string(x.size()) + " values; the system has " +
                      std::to_string(n) + " coordinates, so 2n = " + std::to_string(2 * n));
  Run run(system, options, report);
  system.start(x.data(), options.t0);  // impacts at t0 may change x
  run.emit(options.t0, x.data());
  const MethodInfo& m = method_info(options.method);
  const bool explicit_adaptive = m.adaptive && m.family != MethodFamily::rosenbrock;
  const std::vector<double> x0 = explicit_adaptive ? x : std::vector<double>();  // for the stiffness test
  try {
    switch (m.family) {
      case MethodFamily::explicit_runge_kutta:
        if (!system.integrate_inlined(run, x)) run_explicit(run, x);
        break;
      case MethodFamily::rosenbrock: run_rosenbrock4(run, x); break;
      case MethodFamily::gauss_radau: run_gauss_radau15(run, x); break;
      case MethodFamily::symplectic: run_symplectic(run, x); break;
      case MethodFamily::variational: run_variational(run, x); break;
    }
  } catch (const DynamicsError& e) {
    throw SimulationError(std::string("run stopped: ") + e.what(), run.last_time());
  }
  run.finish(x.data());
  check_drift(report, options.rtol);
  if (explicit_adaptive) check_stiffness(system, x, report.t_final, run.recent_step(), x0, options, report);
}

}  // namespace lagrangian
