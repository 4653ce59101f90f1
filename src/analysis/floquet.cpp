// The monodromy matrix by the variational equations, run by the one driver
// (lagrangian/analysis/floquet.hpp).

#include "lagrangian/analysis/floquet.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <vector>

#include <Eigen/Eigenvalues>

#include "lagrangian/integrate/integrate.hpp"
#include "tangent_system.hpp"

namespace lagrangian::detail {

FloquetResult floquet_multipliers(const TangentModel& model, const double* q0, const double* qd0,
                                  const FloquetOptions& options) {
  if (!std::isfinite(options.period) || !(options.period > 0)) {
    std::ostringstream os;
    os << "floquet: period = " << options.period << " s must be finite and > 0";
    throw OptionError(os.str());
  }
  if (!std::isfinite(options.tolerance) || !(options.tolerance >= 0)) {
    std::ostringstream os;
    os << "floquet: tolerance = " << options.tolerance << " must be finite and >= 0";
    throw OptionError(os.str());
  }
  SimulationOptions run = options.run;
  run.t_end = run.t0 + options.period;
  run.output_interval = -1;
  check_tangent_run(run, "floquet");
  const int n = model.n;
  const auto clock_start = std::chrono::steady_clock::now();

  TangentSystem system(model, 2 * n, 0.0, false);
  const int c = system.coordinate_count();
  std::vector<double> x;
  RunReport report;
  integrate_tangents(system, n, q0, qd0, run, "floquet: the run stopped before t0 + period", x, report);

  FloquetResult result;
  result.monodromy = system.tangents(x.data());
  for (int i = 0; i < n; ++i) {
    result.closure = std::max(result.closure, std::abs(x[static_cast<std::size_t>(i)] - q0[i]));
    result.closure = std::max(result.closure, std::abs(x[static_cast<std::size_t>(c + i)] - qd0[i]));
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> eigen(result.monodromy, false);
  if (eigen.info() != Eigen::Success)
    throw AnalysisError("floquet: the eigenvalues of the monodromy matrix did not converge");
  for (int i = 0; i < 2 * n; ++i) result.multipliers.push_back(eigen.eigenvalues()[i]);
  std::sort(result.multipliers.begin(), result.multipliers.end(),
            [](const std::complex<double>& a, const std::complex<double>& b) { return std::abs(a) > std::abs(b); });
  result.largest_modulus = std::abs(result.multipliers.front());
  result.stable = result.largest_modulus <= 1 + options.tolerance;
  result.steps = report.steps;
  result.rhs_evaluations = system.evaluations();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  return result;
}

}  // namespace lagrangian::detail
