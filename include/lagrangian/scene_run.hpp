#pragma once
/// \file scene_run.hpp
/// Running and inspecting a scene.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "lagrangian/report.hpp"
#include "lagrangian/scene.hpp"
#include "lagrangian/view.hpp"

namespace lagrangian::scene {

/// How run() behaves beyond what the scene says.
struct RunControls {
  bool write_outputs = true;  ///< write trajectory.csv, events.csv, report.json and plots
  bool progress = false;      ///< progress bar on stderr (shown only on a terminal, after ~1 s)
  /// Non-empty: also write the run as a video there (view::write_video:
  /// .mp4, .webm or .gif, through ffmpeg); RunResult::video_written says
  /// whether it was, animation_note why not.
  std::string video_path;
  view::VideoOptions video;
};

/// What a scene run did.
struct RunResult {
  RunReport report;                 ///< cost and accuracy (see report.hpp)
  std::string engine;               ///< "model" (built-in model), "ode" or "event_driven"
  std::vector<std::string> files;   ///< files written
  std::string plot_note;            ///< why plots were skipped, if they were
  std::string animation_note;       ///< why animation.html (or the video) was not written, if it was not
  bool video_written = false;       ///< RunControls::video_path was written
  /// Particle scenes on the ODE engine: evaluations of each declared effect
  /// kernel (one per right-hand side). Undeclared kinds do not appear.
  std::map<std::string, std::uint64_t> effect_evaluations;
  /// The state the run ended in: particle scenes, positions (m) and
  /// velocities (m/s) body by body (x, y, z); built-in models, the
  /// generalized coordinates q and rates q̇ in the model's order (units as in
  /// `lagrangian list` / inspect).
  std::vector<double> q_final, qd_final;
};

/// Validates and runs a scene. Throws SceneError for invalid input
/// (including an output directory that cannot be written) and
/// SimulationError when the run fails part-way; on failure no output file
/// is left looking complete.
RunResult run(const Scene& scene, const RunControls& controls = {});

/// A human-readable description of the scene at t0: coordinates, degrees of
/// freedom (rank of the constraints, redundant ones), momenta, cyclic
/// coordinates and conserved quantities, and the active effects.
std::string inspect(const Scene& scene);

}  // namespace lagrangian::scene
