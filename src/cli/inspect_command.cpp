// `lagrangian inspect SCENE`: the scene at t0 (coordinates, degrees of
// freedom, momenta, conserved quantities, effects), and on request its
// equilibria and normal modes.

#include <iostream>

#include "commands.hpp"

namespace lagrangian::cli {

const Subcommand InspectCommand::kInfo{"inspect",
                               "Describe a scene at t0: coordinates, degrees of freedom (rank, redundant constraints), momenta, "
                 "cyclic coordinates and conserved quantities, active effects."};

void InspectCommand::declare(OptionList& o) {
  scene_.add(o, "scene file (TOML); - reads it from standard input");
  scene_.add_settings(o);
  o.flag("--equilibria", analysis_.equilibria,
              "find equilibria (minima by NLopt, saddles and maxima by Newton's method) and say which are stable");
  o.flag("--modes", analysis_.modes, "normal modes (frequencies and shapes) about each stable equilibrium");
  o.flag("--at-initial-state", analysis_.modes_at_initial,
              "with --modes: linearise about the scene's initial configuration instead");
  o.value("--starts", analysis_.starts, "starts of the equilibrium search (default 16)");
  o.flag("--json", json_, "print the description at t0 as one JSON object (not with --equilibria or --modes)");
}

int InspectCommand::run() {
  const std::optional<scene::Scene> scene = scene_or_say([&] { return scene_.load(); });
  if (!scene) return kBadInput;
  try {
    if (analysis_.modes_at_initial && !analysis_.modes)
      throw OptionError("command line: --at-initial-state: only with --modes");
    if (json_ && (analysis_.equilibria || analysis_.modes))
      throw OptionError("command line: --json: describes the state at t0; --equilibria and --modes print text");
    if (json_) {
      std::cout << scene::inspect(*scene, true);
      return kOk;
    }
    const std::string analysed =
        analysis_.equilibria || analysis_.modes ? scene::analyse(*scene, analysis_) : std::string();
    std::cout << scene::inspect(*scene) << analysed;
    return kOk;
  } catch (const SimulationError& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
    return kRunFailed;
  } catch (const Error& e) {
    std::cerr << "lagrangian: " << e.what() << "\n";
    return kBadInput;
  }
}

}  // namespace lagrangian::cli
