// `lagrangian run SCENE`: integrates the scene, writes trajectory.csv,
// events.csv, report.json, plots and animation.html, prints the summary.

#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/scene/io.hpp"

namespace lagrangian::cli {

const Subcommand RunCommand::kInfo{"run",
                               "Run a scene: writes trajectory.csv, events.csv, report.json, plots and animation.html (open it in a "
             "browser) into the output directory and prints a summary."};

void RunCommand::declare(OptionList& o) {
  scene_.add(o, "scene file (TOML, see docs/scenes.md); - reads it from standard input");
  scene_.add_settings(o);
  overrides_.add(o,
                 "stepper: rk4, dopri5, cash_karp54, fehlberg78, bulirsch_stoer, gauss_radau15, rosenbrock4, variational, "
                 "symplectic_rkn_sb3a_mclachlan, velocity_verlet or event_driven");
  o.value("--out", out_dir_, "output directory, overrides output.directory");
  o.flag("--no-plots", no_plots_, "do not make plots");
  o.flag("--no-animation", no_animation_, "do not write animation.html");
  o.value("--animate-to", animate_to_,
                "also write the run as a video (.mp4, .webm or .gif, through ffmpeg) for slides and documents");
  o.value("--animate-seconds", animate_seconds_, "length of that video (s, default 10): the whole run");
  o.flag("--allow-drift", allow_drift_,
              "exit 0 even when a monitored invariant (the energy, a conserved momentum, the constraint residual or "
              "the error against a closed form) drifts beyond what the tolerance excuses (otherwise exit 3)");
  o.flag("-q,--quiet", quiet_, "print only errors");
}

/// The command line's overrides of the scene's run and output tables.
void RunCommand::apply(scene::Scene& scene) const {
  overrides_.apply(scene, true);
  if (out_dir_) {
    scene.output.directory = *out_dir_;
    scene.source.overrides["output.directory"] = "--out";
  }
  if (no_plots_) scene.output.plots = false;
  if (no_animation_) scene.output.animation = false;
  if (!animate_to_.empty()) {
    const std::string ext = std::filesystem::path(animate_to_).extension().string();
    if (ext != ".mp4" && ext != ".webm" && ext != ".gif")
      throw BadInput{"command line: --animate-to: '" + animate_to_ + "': unknown format '" + ext +
                     "' (use .mp4, .webm or .gif)"};
  }
  if (!(animate_seconds_ > 0 && animate_seconds_ <= 3600))
    throw BadInput{"command line: --animate-seconds: must be in (0, 3600] s, got " + std::to_string(animate_seconds_)};
}

int RunCommand::run() {
  const std::optional<scene::Scene> scene = scene_or_say([&] {
    scene::Scene s = scene_.load();
    apply(s);
    return s;
  });
  if (!scene) return kBadInput;
  return guarded("run", [&] {
    scene::RunControls controls;
    controls.progress = !quiet_;
    controls.video_path = animate_to_;
    controls.video.seconds = animate_seconds_;
    const scene::RunResult r = scene::run(*scene, controls);
    if (!quiet_) {
      std::cout << "scene " << scene->name << " — engine " << r.engine << "\n" << r.report.summary();
      if (r.gas) std::cout << r.gas->summary();
      if (!r.effect_evaluations.empty()) {
        std::cout << "effects evaluated:";
        for (const auto& [name, count] : r.effect_evaluations) std::cout << " " << name << " " << count << ";";
        std::cout << "\n";
      }
    }
    print_outputs(r.plot_note, r.files, quiet_);
    if (!r.animation_note.empty()) std::cerr << "lagrangian: " << r.animation_note << "\n";
    if (!animate_to_.empty() && !r.video_written) return kRunFailed;  // asked for, not made: said above
    if (r.report.drift_exceeded && !allow_drift_) {
      std::string which;
      for (const MonitorVerdict& m : r.report.monitors)
        if (m.exceeded) which += (which.empty() ? "" : ", ") + m.name;
      std::cerr << "lagrangian: the run finished, but it drifted beyond what its tolerance excuses (" << which
                << "; see the warning; report.json has drift_exceeded = true): exit 3; --allow-drift accepts it\n";
      return kDrift;
    }
    return kOk;
  });
}

}  // namespace lagrangian::cli
