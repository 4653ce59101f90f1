#pragma once
// Internal: how the scene runner reaches the built-in models.

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/integrate/detail/compiled_models.hpp"
#include "lagrangian/integrate/discrete.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/scene/run.hpp"
#include "lagrangian/view/view.hpp"

namespace lagrangian::scene::detail {

/// Called with every sample a run produces (progress display,
/// RunControls::on_sample).
using SampleTick = std::function<void(const SampleRow&)>;

/// The state a run ended in (the last sample): generalized coordinates and
/// their rates in the model's order, at time t (s).
struct FinalState {
  double t = 0;
  std::vector<double> q, qd;
};

/// A built-in model as the scene runner sees it.
struct ModelEntry {
  std::string name;  ///< as in builtin_models() (src/scene/model_catalog.cpp)
  /// Builds the model from spec.parameters (defaults for absent ones) and the
  /// initial state from spec.q / spec.qd (the model's default state when
  /// empty), runs simulate() with `options`, writes trajectory CSV to
  /// `csv_path` when non-empty (committed only on success), stores the last
  /// sample in `*final_state` when given, and returns the report. Bad
  /// parameters or state throw SceneError with keys
  /// "model.parameters.<name>", "model.q", "model.qd".
  RunReport (*run_fn)(const ModelSpec& spec, const SimulationOptions& options, const std::string& csv_path,
                      const SampleTick& tick, FinalState* final_state);
  /// Inspection at t0: coordinates, DOF report (rank, redundant
  /// constraints), momenta, cyclic coordinates and conserved quantities,
  /// declared forces/constraints/contacts; as text, or with `as_json` the
  /// same facts as one JSON object.
  std::string (*inspect)(const ModelSpec& spec, double t0, bool as_json);
  /// Equilibria and normal modes at t0 (scene/analysis.hpp), as text.
  std::string (*analyse)(const ModelSpec& spec, double t0, const AnalysisRequest& request);
  /// The stationary-action boundary-value problem (request.from/to/t0/t1/steps).
  BvpResult (*bvp)(const ModelSpec& spec, const BvpRequest& request, DiscreteRule rule);
  /// The model in space, for the animation (view.hpp): returns its figure
  /// and fills `xyz` with its bodies' centres (m), rows × bodies × 3, at the
  /// `rows` states q (rows × n values, row by row) at times t (s). A model
  /// without a picture returns a figure with no bodies.
  view::Figure (*picture)(const ModelSpec& spec, const double* t, const double* q, std::size_t rows,
                          std::vector<double>& xyz);
  /// A model of particles placed by their coordinates (particles(), no
  /// place() of its own): each particle's coordinate indices of x, y, z (−1
  /// absent), in the order of the picture's bodies; empty otherwise.
  std::vector<std::array<int, 3>> (*particle_axes)(const ModelSpec& spec);
  /// The model of `spec` (its parameters, not its state) at (q, q̇, t), n
  /// values each: q̈ (bilateral constraints kept, contacts open), p, M and
  /// h, what two statements of one system must agree in (compiled with
  /// the model's simulate(): lagrangian/integrate/detail/eom_sample.hpp).
  lagrangian::detail::EomSample (*eom)(const ModelSpec& spec, const double* q, const double* qd, double t);
  /// Lyapunov exponents and MEGNO of the motion from the spec's initial
  /// state (analysis/lyapunov.hpp); OptionError for a model the tangent
  /// flow is not derived for (constraints, contacts, more than 6 or a
  /// run-time number of coordinates).
  LyapunovResult (*lyapunov)(const ModelSpec& spec, const LyapunovOptions& options);
  /// Floquet multipliers of the motion from the spec's initial state over
  /// one period (analysis/floquet.hpp); refused as lyapunov is.
  FloquetResult (*floquet)(const ModelSpec& spec, const FloquetOptions& options);
  /// ∂x(t)/∂x(t0) and ∂x(t)/∂p of the motion from the spec's initial state
  /// (analysis/sensitivity.hpp); refused as lyapunov is, and OptionError
  /// naming --parameter for parameters a model does not offer.
  SensitivityResult (*sensitivity)(const ModelSpec& spec, const SensitivityOptions& options);

  /// Runs the model (see run_fn).
  RunReport run(const ModelSpec& spec, const SimulationOptions& options, const std::string& csv_path,
                const SampleTick& tick, FinalState* final_state = nullptr) const {
    return run_fn(spec, options, csv_path, tick, final_state);
  }
};

void add_pendulum_models(std::vector<ModelEntry>& out);
void add_constrained_models(std::vector<ModelEntry>& out);
void add_impact_models(std::vector<ModelEntry>& out);
void add_orbit_models(std::vector<ModelEntry>& out);  // two-body, Kepler, projectiles

/// Every entry, sorted by name (built once); one per builtin_models() entry.
const std::vector<ModelEntry>& model_entries();
const ModelEntry* find_entry(const std::string& name);
/// The entry of a model stated by expressions (ModelSpec::text).
const ModelEntry& text_entry();
/// The entry of a C++ model handed to scene::run_model() (ModelSpec::user).
const ModelEntry& user_entry();
/// The entry that runs `spec`: user_entry() or text_entry() for those
/// models, else the built-in model it names (nullptr when there is none).
const ModelEntry* entry_for(const ModelSpec& spec);

}  // namespace lagrangian::scene::detail
