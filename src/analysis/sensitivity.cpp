// Forward sensitivities by the variational equations, run by the one driver
// (lagrangian/analysis/sensitivity.hpp).

#include "lagrangian/analysis/sensitivity.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "manifold.hpp"
#include "tangent_run.hpp"
#include "tangent_system.hpp"

namespace lagrangian::detail {

std::vector<int> parameter_indices(const std::vector<std::string>& wanted, const std::vector<std::string>& available) {
  std::vector<int> out;
  for (const std::string& name : wanted) {
    const auto it = std::find(available.begin(), available.end(), name);
    if (it == available.end()) {
      std::string list;
      for (const std::string& a : available) list += (list.empty() ? "" : ", ") + a;
      throw OptionError("sensitivity: parameters: '" + name + "' is not a parameter of the model (" + list + ")");
    }
    const int index = static_cast<int>(it - available.begin());
    if (std::find(out.begin(), out.end(), index) != out.end())
      throw OptionError("sensitivity: parameters: '" + name + "' is listed twice");
    out.push_back(index);
  }
  return out;
}

namespace {

/// AnalysisError naming the first parameter in `parameters` and the first
/// row of the constraint manifold that the parameter moves past the start
/// (q0, q̇0, t0): the row h_i changes by more than the 1e-9 (1 + ‖q‖∞) or
/// 1e-9 (1 + ‖q̇‖∞) the start is held to (tangent_system.hpp) when p
/// changes by max(|p|, 1). A start off the manifold is left to the run's
/// own check (a ConstraintError naming the row).
void require_manifold_kept(const TangentModel& model, const double* q0, const double* qd0, double t0,
                           const std::vector<int>& parameters, const std::vector<std::string>& names) {
  if (model.manifold == 0 || parameters.empty()) return;
  if (model.parameter_manifold == nullptr)
    throw AnalysisError("sensitivity: the model gives no derivative of its constraint rows along a parameter ('" +
                        names[static_cast<std::size_t>(parameters.front())] +
                        "'); ask for the initial state's columns only");
  const int n = model.n;
  const Eigen::Map<const Eigen::VectorXd> q(q0, n), qd(qd0, n);
  const double qs = 1.0 + q.lpNorm<Eigen::Infinity>(), vs = 1.0 + qd.lpNorm<Eigen::Infinity>();
  const auto tolerance = [&](int i) { return 1e-9 * (i < model.manifold_holonomic ? qs : vs); };
  std::vector<double> rate(static_cast<std::size_t>(model.manifold)),
      jacobian(static_cast<std::size_t>(2 * n * model.manifold));
  model.manifold_rows(model.model, q0, qd0, t0, rate.data(), jacobian.data());
  for (int i = 0; i < model.manifold; ++i)
    if (!(std::abs(rate[static_cast<std::size_t>(i)]) <= tolerance(i))) return;
  for (int p : parameters) {
    const double value = model.parameter_manifold(model.model, q0, qd0, t0, p, rate.data());
    const double step = std::max(std::abs(value), 1.0);
    for (int i = 0; i < model.manifold; ++i) {
      const double d = rate[static_cast<std::size_t>(i)];
      if (std::abs(d) * step <= tolerance(i)) continue;
      std::ostringstream os;
      os.precision(6);
      const std::string& name = names[static_cast<std::size_t>(p)];
      os << "sensitivity: parameter '" << name << "' moves the constraint manifold past the start: d("
         << model.manifold_names[static_cast<std::size_t>(i)] << ")/d" << name << " = " << d
         << " there, so the start would leave the constraints when " << name
         << " changes; ask for other parameters, or start where the constraints do not depend on it";
      throw AnalysisError(os.str());
    }
  }
}

}  // namespace

SensitivityResult sensitivities(const TangentModel& model, const double* q0, const double* qd0,
                                const std::vector<int>& parameters, const std::vector<std::string>& names,
                                const SensitivityOptions& options) {
  check_tangent_run(options.run, "sensitivity");
  SimulationOptions run = options.run;
  if (!(run.output_interval > 0)) run.output_interval = -1;  // t0 and t_end only
  if (!options.initial_state && parameters.empty())
    throw OptionError("sensitivity: nothing to compute: initial_state = false and no parameters");
  const int n = model.n;
  const auto clock_start = std::chrono::steady_clock::now();

  // On a constraint manifold of dimension d the d columns Φ B0 of its
  // tangent space's basis, recorded as Φ P0 (tangent_system.hpp).
  const int k = !options.initial_state ? 0
                : model.manifold > 0   ? static_cast<int>(manifold_basis(model, q0, qd0, run.t0).cols())
                                       : 2 * n;
  if (options.initial_state && k == 0)
    throw AnalysisError(
        "sensitivity: the constraints leave no motion (the constraint manifold's tangent space has dimension 0)");
  require_manifold_kept(model, q0, qd0, run.t0, parameters, names);
  TangentSystem system(model, k, 0.0, false, parameters, true);
  std::vector<double> x;
  RunReport report;
  integrate_tangents(system, n, q0, qd0, run, "sensitivity: the run stopped before t_end", x, report);

  SensitivityResult result;
  for (int p : parameters) result.parameters.push_back(names[static_cast<std::size_t>(p)]);
  result.state_columns = options.initial_state ? 2 * n : 0;
  result.times = system.times();
  result.states = system.states();
  result.sensitivities = system.recorded_columns();
  result.steps = report.steps;
  result.impacts = system.impacts();
  result.rhs_evaluations = system.evaluations();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  return result;
}

}  // namespace lagrangian::detail
