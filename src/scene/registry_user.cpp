// The registry entry of a C++ model handed to scene::run_model()
// (ModelSpec::user, scene/detail/model_run.hpp): runs and pictures it; the
// inspection and the analyses are for models the scene states, and say so.

#include "lagrangian/scene/detail/model_run.hpp"
#include "registry_entry.hpp"

namespace lagrangian::scene::detail {
namespace {

RunReport run_user(const ModelSpec& spec, const SimulationOptions& options, const std::string& csv_path,
                   const SampleTick& tick, FinalState* final_state) {
  return spec.user->run(options, csv_path, tick, final_state);
}

[[noreturn]] void not_for_user(const char* what) {
  throw OptionError(std::string(what) +
                    ": not for a C++ model run by scene::run_model(); call the library's function on the model "
                    "(inspect: dof_report, cyclic_coordinates; find_equilibria, small_oscillations, solve_bvp)");
}

std::string inspect_user(const ModelSpec&, double, bool) { not_for_user("inspect"); }
std::string analyse_user(const ModelSpec&, double, const AnalysisRequest&) { not_for_user("equilibria and modes"); }
BvpResult bvp_user(const ModelSpec&, const BvpRequest&, DiscreteRule) { not_for_user("solve-bvp"); }
lagrangian::detail::EomSample eom_user(const ModelSpec&, const double*, const double*, double) {
  not_for_user("the equations of motion at a state");
}

LyapunovResult lyapunov_user(const ModelSpec&, const LyapunovOptions&) { not_for_user("lyapunov"); }
FloquetResult floquet_user(const ModelSpec&, const FloquetOptions&) { not_for_user("floquet"); }
SensitivityResult sensitivity_user(const ModelSpec&, const SensitivityOptions&) { not_for_user("sensitivity"); }

view::Figure picture_user(const ModelSpec& spec, const double* t, const double* q, std::size_t rows,
                          std::vector<double>& xyz) {
  return spec.user->picture(t, q, rows, xyz);
}

std::vector<std::array<int, 3>> axes_user(const ModelSpec& spec) { return spec.user->particle_axes(); }

}  // namespace

const ModelEntry& user_entry() {
  static const ModelEntry e{"user",        &run_user,  &inspect_user, &analyse_user,  &bvp_user,
                            &picture_user, &axes_user, &eom_user,     &lyapunov_user, &floquet_user,
                            &sensitivity_user};
  return e;
}

}  // namespace lagrangian::scene::detail
