// `lagrangian sensitivity SCENE`: how the scene's motion at t_end depends on
// its initial state and on its model's parameters (analysis/sensitivity.hpp).

#include "commands.hpp"

namespace lagrangian::cli {

const Subcommand SensitivityCommand::kInfo{
    "sensitivity",
    "Sensitivities of the scene model (or its bodies) at t_end: d x(t_end) / d x(t0), the state transition matrix, and "
    "d x(t_end) / d p for the model parameters named, x = (q, qdot), by the variational equations integrated beside "
    "the motion (automatic differentiation, no finite differences)."};

void SensitivityCommand::declare(OptionList& o) {
  scene_.add(o, "scene file (TOML) with a built-in model, one stated as text, or bodies");
  scene_.add_settings(o);
  overrides_.add(o,
                 "stepper: rk4, dopri5, cash_karp54, fehlberg78, bulirsch_stoer, gauss_radau15 or rosenbrock4 "
                 "(the columns are integrated beside the state)");
  o.values("--parameter", request_.parameters,
           "NAME: a model parameter (as in [model.parameters]) or a particle scene's key (gravity.g[2], "
           "bodies[0].mass) whose column d x(t_end) / d NAME follows; repeatable");
  o.flag("--parameters-only", parameters_only_, "only the parameters' columns, not the state transition matrix");
  o.flag("--json", json_, "print one JSON object (state, state_transition, parameters, ...) instead of text");
  o.flag("-q,--quiet", quiet_, "print only errors");
}

int SensitivityCommand::run() {
  return run_analysis(
      "sensitivity", scene_, overrides_, json_, quiet_,
      [&] {
        if (parameters_only_ && request_.parameters.empty())
          throw BadInput{"command line: sensitivity: --parameters-only needs at least one --parameter NAME"};
        request_.initial_state = !parameters_only_;
      },
      [&](const scene::Scene& scene) { return scene::sensitivity(scene, request_); });
}

}  // namespace lagrangian::cli
