#include "lagrangian/integrate.hpp"

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
  const std::string& m = options.method;
  const bool explicit_adaptive = !fixed_step_method(m) && m != "rosenbrock4";
  const std::vector<double> x0 = explicit_adaptive ? x : std::vector<double>();  // for the stiffness test
  try {
    if (m == "dopri5" || m == "rk4" || m == "cash_karp54" || m == "fehlberg78" || m == "bulirsch_stoer") {
      if (!system.integrate_inlined(run, x)) run_explicit(run, x);
    } else if (m == "rosenbrock4") {
      run_rosenbrock4(run, x);
    } else if (m == "gauss_radau15") {
      run_gauss_radau15(run, x);
    } else if (m == "symplectic_rkn_sb3a_mclachlan" || m == "velocity_verlet") {
      run_symplectic(run, x);
    } else if (m == "variational") {
      run_variational(run, x);
    } else {
      throw OptionError("unknown method '" + m + "'");
    }
  } catch (const DynamicsError& e) {
    throw SimulationError(std::string("run stopped: ") + e.what(), run.last_time());
  }
  run.finish(x.data());
  check_drift(report, options.rtol);
  if (explicit_adaptive) check_stiffness(system, x, report.t_final, run.recent_step(), x0, options, report);
}

}  // namespace lagrangian
