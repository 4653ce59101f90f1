// `lagrangian floquet SCENE --period T`: the Floquet multipliers of the
// scene's model or bodies over one period from its initial state
// (analysis/floquet.hpp).

#include "commands.hpp"

namespace lagrangian::cli {

const Subcommand FloquetCommand::kInfo{
    "floquet",
    "Floquet multipliers of the scene model (or its bodies) over one period T from its initial state (the monodromy matrix, by "
    "the variational equations) and the verdict stable or unstable."};

void FloquetCommand::declare(OptionList& o) {
  scene_.add(o, "scene file (TOML) with a built-in model, one stated as text, or bodies (with links and surfaces, or "
                "contacts)");
  scene_.add_settings(o);
  o.value("--period", period_, "T (s): the period of the drive or of the orbit (required; with --find-orbit the guess)");
  o.flag("--find-orbit", request_.find_orbit,
         "find the periodic orbit near the initial state first (Newton's method on the monodromy matrix; each step "
         "holds the start's energy to first order)");
  o.flag("--fixed-period", request_.fixed_period,
         "with --find-orbit: T is the drive's period; only the start moves (a periodic response)");
  o.flag("--any-energy", any_energy_,
         "with --find-orbit: do not hold the start's energy (an isolated orbit of a forced or damped system)");
  overrides_.add(o, "stepper: rk4, dopri5, cash_karp54, fehlberg78, bulirsch_stoer, gauss_radau15 or rosenbrock4",
                 false);
  o.value("--tolerance", request_.tolerance, "stable when every |mu| <= 1 + tolerance (default 1e-6)");
  o.flag("--json", json_, "print one JSON object (multipliers as [re, im], stable, ...) instead of text");
  o.flag("-q,--quiet", quiet_, "print only errors");
}

int FloquetCommand::run() {
  return run_analysis(
      "floquet", scene_, overrides_, json_, quiet_,
      [&] {
        if (!period_) throw BadInput{"command line: floquet: --period T (s) is required"};
        request_.period = *period_;
        request_.keep_energy = !any_energy_;
        if ((request_.fixed_period || any_energy_) && !request_.find_orbit)
          throw BadInput{"command line: floquet: --fixed-period and --any-energy go with --find-orbit"};
      },
      [&](const scene::Scene& scene) { return scene::floquet(scene, request_); });
}

}  // namespace lagrangian::cli
