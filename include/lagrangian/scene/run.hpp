#pragma once
/// \file scene/run.hpp
/// Running and inspecting a scene.

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "lagrangian/integrate/report.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/view/view.hpp"

namespace lagrangian::scene {

/// One sample of a run, the values of a row of trajectory.csv: time (s),
/// coordinates q and their rates q̇ (the model's units, m for bodies' x, y,
/// z), the energy function h and T + V (J; NaN where the run does not
/// sample it). The spans point into the run's own storage: valid during the
/// call only.
struct SampleRow {
  double t = 0;
  std::span<const double> q, qd;
  double energy = std::numeric_limits<double>::quiet_NaN();
  double total_energy = std::numeric_limits<double>::quiet_NaN();
};

/// How run() behaves beyond what the scene says.
struct RunControls {
  bool write_outputs = true;  ///< write trajectory.csv, events.csv, report.json and plots
  bool progress = false;      ///< progress bar on stderr (shown only on a terminal, after ~1 s)
  /// Non-empty: also write the run as a video there (view::write_video:
  /// .mp4, .webm or .gif, through ffmpeg); RunResult::video_written says
  /// whether it was, animation_note why not.
  std::string video_path;
  view::VideoOptions video;
  /// Called with every sample, in time order (with or without outputs
  /// written): samples read in memory, not from trajectory.csv.
  std::function<void(const SampleRow&)> on_sample;
};

/// Kinetic theory against a run of a gas: equal spheres in a box with
/// elastic walls and collisions and nothing else (a [gas] scene, or spheres
/// in a box), run on the event-driven engine.
///  - temperature from the final speeds: kT = m ⟨v²⟩ / 3;
///  - pressure on the walls from the impulses they received,
///    P = mean over the faces of J_face / (A_face (t_end − t0)), with one
///    standard error from its spread over ten equal stretches of the run;
///  - against kinetic theory, P_ideal = N m ⟨v²⟩ / (3 V), and with the
///    spheres' size: the centres keep R from the walls, so they fill
///    V_free = Π (L_i − 2R) at n = N / V_free and reach only
///    (L_j − 2R)(L_k − 2R) of a face L_j L_k; the bulk pressure is
///    n kT Z with the hard-sphere virial series Z = 1 + B₂ n + B₃ n²,
///    B₂ = 2πσ³/3, B₃ = 5 B₂²/8, σ = 2R: P_expected = n kT Z times the
///    reached fraction of a face (averaged over the three axes);
///  - the final speeds against the Maxwell–Boltzmann distribution at kT:
///    the Kolmogorov–Smirnov distance D, and 1.36 / √N, the 5 % point for a
///    distribution given in advance (kT is estimated from the same speeds,
///    which makes the test conservative).
struct GasCheck {
  std::size_t molecules = 0;
  double mass = 0;                  ///< m (kg)
  double radius = 0;                ///< R (m)
  double volume = 0;                ///< V of the box (m³)
  double duration = 0;              ///< t_end − t0 (s)
  double mean_square_speed = 0;     ///< ⟨v²⟩ at the end (m²/s²)
  double kT = 0;                    ///< m ⟨v²⟩ / 3 (J)
  double temperature = 0;           ///< kT / k_B (K)
  double pressure = 0;              ///< measured on the walls (Pa)
  double pressure_error = 0;        ///< its standard error (Pa)
  double pressure_ideal = 0;        ///< N m ⟨v²⟩ / (3 V) (Pa)
  double pressure_expected = 0;     ///< n kT Z × the reached fraction of a face (Pa)
  double ks_distance = 0;           ///< D against Maxwell–Boltzmann at kT
  double ks_critical = 0;           ///< 1.36 / √N
  std::vector<double> speeds;       ///< the final speeds (m/s)
  /// Lines for the run's summary: temperature, pressure against both
  /// predictions (ratios and standard errors), D against its 5 % point.
  std::string summary() const;
};

/// What a scene run did.
struct RunResult {
  RunReport report;                 ///< cost and accuracy (see report.hpp)
  std::string engine;               ///< "model" (built-in model), "ode" or "event_driven"
  std::vector<std::string> files;   ///< files written
  std::string plot_note;            ///< why plots were skipped, if they were
  std::string animation_note;       ///< why animation.html (or the video) was not written, if it was not
  bool video_written = false;       ///< RunControls::video_path was written
  /// A gas (see GasCheck): kinetic theory against the run; also in
  /// report.json ("gas") and plotted as speeds.png against Maxwell–Boltzmann.
  std::optional<GasCheck> gas;
  /// Particle scenes on the ODE engine: evaluations of each declared effect
  /// kernel (one per right-hand side). Undeclared kinds do not appear.
  std::map<std::string, std::uint64_t> effect_evaluations;
  /// Particle scenes on the ODE engine: contacts located by a root search on
  /// a step's interpolant (each ~10–40 evaluations of the whole state). Only
  /// the earliest closing of a step is needed, so contacts that are still
  /// open at the earliest closing found so far are not located: about one
  /// per event, however many contacts cross zero in the trial step.
  std::uint64_t contact_locations = 0;
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
/// coordinates and conserved quantities, and the active effects. With
/// `as_json`, the same facts as one JSON object (numbers as numbers, SI
/// units; docs/scenes.md, "inspect --json").
std::string inspect(const Scene& scene, bool as_json = false);

}  // namespace lagrangian::scene
