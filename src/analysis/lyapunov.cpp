// Benettin's method over the augmented system of state and tangent vectors
// (lagrangian/analysis/lyapunov.hpp), run by the one driver.

#include "lagrangian/analysis/lyapunov.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Cholesky>
#include <Eigen/QR>

#include "lagrangian/integrate/integrate.hpp"
#include "lagrangian/integrate/method.hpp"
#include "lagrangian/integrate/system.hpp"
#include "tangent_run.hpp"
#include "tangent_system.hpp"

namespace lagrangian::detail {
namespace {

/// d: 2n, or for a constrained model the dimension of its manifold's
/// tangent space (tangent_system.hpp).
void check_options(const LyapunovOptions& options, int n, int d) {
  check_tangent_run(options.run, "lyapunov");
  if (options.exponents < 0 || options.exponents > d) {
    std::ostringstream os;
    os << "lyapunov: exponents = " << options.exponents << " is outside [0, " << d << "] (0 asks for all ";
    if (d == 2 * n) {
      os << "2n = " << d << ")";
    } else {
      os << d << ", the dimension of the constraint manifold's tangent space)";
    }
    throw OptionError(os.str());
  }
  if (!(options.interval >= 0) || !std::isfinite(options.interval)) {
    std::ostringstream os;
    os << "lyapunov: interval = " << options.interval << " s must be finite and >= 0 (0 lets the code choose it)";
    throw OptionError(os.str());
  }
}

}  // namespace

LyapunovResult lyapunov_spectrum(const TangentModel& model, const double* q0, const double* qd0,
                                 const LyapunovOptions& options) {
  const int n = model.n;
  const int d =
      model.manifold > 0 ? static_cast<int>(manifold_basis(model, q0, qd0, options.run.t0).cols()) : 2 * n;
  if (d == 0)
    throw AnalysisError(
        "lyapunov: the constraints leave no motion (the constraint manifold's tangent space has dimension 0)");
  check_options(options, n, d);
  const int k = options.exponents == 0 ? d : options.exponents;
  const auto clock_start = std::chrono::steady_clock::now();
  const double span = options.run.t_end - options.run.t0;
  TangentSystem system(model, k, options.interval > 0 ? options.interval : span / 100, true);
  const int c = system.coordinate_count();
  SimulationOptions run = options.run;
  run.output_interval = -1;  // no samples between the ends
  std::vector<double> x;
  RunReport report;
  integrate_tangents(system, n, q0, qd0, run, "lyapunov: the run stopped before t_end", x, report);
  system.close(x.data(), report.t_final);

  LyapunovResult result;
  result.t_final = report.t_final;
  for (double s : system.sums()) result.spectrum.push_back(s / span);
  std::sort(result.spectrum.begin(), result.spectrum.end(), std::greater<>());
  for (double l : result.spectrum) result.sum += l;
  result.renormalisations = system.renormalisations();
  result.impacts = system.impacts();
  result.rests = system.rests();
  result.releases = system.releases();
  result.interval_min = system.shortest();
  result.interval_max = system.longest();
  result.steps = report.steps;
  result.megno = system.megno();
  result.megno_mean = system.megno_mean(report.t_final);
  result.q_final.assign(x.begin(), x.begin() + n);
  result.qd_final.assign(x.begin() + c, x.begin() + c + n);
  result.rhs_evaluations = system.evaluations();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  return result;
}

}  // namespace lagrangian::detail
