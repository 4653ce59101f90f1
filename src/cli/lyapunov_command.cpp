// `lagrangian lyapunov SCENE`: the Lyapunov exponents and MEGNO of the
// scene's model or bodies from its initial state (analysis/lyapunov.hpp).

#include "commands.hpp"

namespace lagrangian::cli {

const Subcommand LyapunovCommand::kInfo{
    "lyapunov",
    "Lyapunov exponents (1/s, largest first), their sum and MEGNO of the scene model (or its bodies) from its initial state: the "
    "variational equations integrated beside the motion, renormalised by Benettin's method."};

void LyapunovCommand::declare(OptionList& o) {
  scene_.add(o, "scene file (TOML) with a built-in model, one stated as text, or bodies (with links and surfaces, or "
                "contacts)");
  scene_.add_settings(o);
  overrides_.add(o,
                 "stepper: rk4, dopri5, cash_karp54, fehlberg78, bulirsch_stoer, gauss_radau15 or rosenbrock4 "
                 "(the tangent vectors are integrated beside the state)");
  o.value("--exponents", request_.exponents, "how many exponents, 1 .. d (d = 2n, or the dimension of a constraint manifold; default 0: all d; "
                                               "1 is cheapest)");
  o.value("--interval", request_.interval,
          "longest time between renormalisations (s; default (t_end - t0)/100; shorter when the vectors grow)");
  o.flag("--json", json_, "print one JSON object (spectrum, sum, megno, ...) instead of text");
  o.flag("-q,--quiet", quiet_, "print only errors");
}

int LyapunovCommand::run() {
  return run_analysis(
      "lyapunov", scene_, overrides_, json_, quiet_, [] {},
      [&](const scene::Scene& scene) { return scene::lyapunov(scene, request_); });
}

}  // namespace lagrangian::cli
