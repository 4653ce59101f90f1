#pragma once
// Internal: what the registry translation units share — parameters resolved
// against the catalog, the initial state, a run with trajectory output and
// progress ticks, and the inspection text.
//
// A registry TU describes each model by a small definition struct
//
//   struct SimplePendulumDef {
//     using Model = models::SimplePendulum;                 // its name from Model::description
//     // or, for a preset of a template model (models::presets):
//     // static constexpr const auto& description = models::presets::newtons_cradle;
//     static constexpr std::string_view type = "models::SimplePendulum"; // for inspect
//     // optional: static Model build(const Parameters& p);  // may throw ParameterError; without it the
//     //   model is built as Model(p[name_0], p[name_1], …) in the description's parameter order
//     static State<coordinate_count_v<Model>> initial(const Model& m, double t0);       // the default state
//     // optional: static std::string_view alias(std::string_view model_parameter);
//     // optional, for the animation (view.hpp):
//     static view::Figure figure(const Model& m);          // bodies, rods, springs, fixed parts
//     static void place(const Model& m, const double* q, double t, view::Point* centres);  // one per body
//   };
//
// and registers it with entry<Def>() (registry_entry.hpp). A model that
// declares particles() is drawn without figure() and place(): one point mass
// per particle, placed by its axes; figure() alone adds rods, planes and radii
// to that. Parameter errors thrown by the model's own validation are re-thrown as SceneError("model.parameters.<name>", …):
// the model's parameter name is mapped to the registry's by equality, then
// Def::alias(), then by dropping trailing digits (m1 → m for models built
// from one shared value: parameter_stem(), shared_parameter_columns.hpp);
// Def::alias("") names the key for messages that do not name a parameter.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/integrate/detail/eom_sample.hpp"  // (compiled with simulate(), src/models/)
#include "lagrangian/scene/detail/model_run.hpp"
#include "lagrangian/mechanics/detail/point_momenta.hpp"
#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/impact.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/params.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/integrate/simulate.hpp"
#include "json_object.hpp"
#include "key_units.hpp"
#include "registry_analysis.hpp"
#include "shared_parameter_columns.hpp"

namespace lagrangian::scene::detail {

// -- non-template helpers (src/scene/registry.cpp) ------------------------------

/// The catalog entry of a built-in model; std::logic_error when the registry
/// and the catalog disagree (a bug, caught by the tests).
const ModelInfo& catalog_entry(std::string_view name);

/// A model's parameters: the scene's values where given, the catalog's
/// defaults otherwise. Unknown names and non-finite values are SceneErrors
/// keyed "model.parameters.<name>".
class Parameters {
 public:
  Parameters(const ModelInfo& info, const ModelSpec& spec);
  /// The value of a parameter of the catalog entry (std::logic_error for a
  /// name the catalog does not list: a registry bug).
  double operator[](std::string_view name) const;
  const ModelInfo& info() const { return *info_; }
  double value(std::size_t i) const { return values_[i]; }
  bool given(std::size_t i) const { return given_[i]; }

 private:
  const ModelInfo* info_;
  std::vector<double> values_;
  std::vector<bool> given_;
};

/// Re-throws a model's ParameterError (its message `what`) as a SceneError
/// keyed by the registry's parameter name; `alias` maps the model's names.
using ParameterAlias = std::string_view (*)(std::string_view model_parameter);
[[noreturn]] void throw_parameter_error(const ModelInfo& info, const std::string& what, ParameterAlias alias);

/// Checks spec.q and spec.qd: empty, or one finite value per coordinate.
/// Throws SceneError "model.q" / "model.qd".
void check_state_sizes(const ModelInfo& info, const ModelSpec& spec);

/// A number for the inspection text (12 significant digits).
std::string number(double v);
/// A list of numbers "[a, b, c]".
std::string numbers(const double* v, int n);
/// Rows of cells as aligned columns, each line starting with `indent`.
std::string columns(const std::vector<std::vector<std::string>>& rows, const std::string& indent = "  ");
// velocity_unit, momentum_unit: key_units.hpp
/// Header lines of the inspection: name, description, type, coordinates, parameters.
std::string inspect_header(const ModelInfo& info, std::string_view type, const Parameters& p);

/// The header's facts: model, description, type, coordinates with units, parameters.
void inspect_header_json(JsonObject& js, const ModelInfo& info, std::string_view type, const Parameters& p);

// -- building a model and its initial state -------------------------------------

/// The description of the model of `Def`: its preset's (Def::description)
/// or its model's own (Model::description).
template <class Def>
constexpr const auto& description_of() {
  if constexpr (requires { Def::description; }) {
    return Def::description;
  } else {
    return Def::Model::description;
  }
}

/// The name a scene gives the model of `Def`.
template <class Def>
constexpr std::string_view name_of() {
  return description_of<Def>().name;
}

/// The catalog entry of the model of `Def`.
template <class Def>
const ModelInfo& info_of() {
  return catalog_entry(name_of<Def>());
}

template <class Def>
ParameterAlias alias_of() {
  if constexpr (requires(std::string_view s) { Def::alias(s); }) {
    return &Def::alias;
  } else {
    return nullptr;
  }
}

/// Calls `make` (a model's constructor or default state); its ParameterError
/// becomes a SceneError naming the parameter.
template <class Def, class Make>
auto with_parameter_keys(const ModelInfo& info, Make&& make) -> decltype(make()) {
  try {
    return make();
  } catch (const ParameterError& e) {
    throw_parameter_error(info, e.what(), alias_of<Def>());
  }
}

/// The initial state: spec.q and spec.qd where given. With neither, the
/// model's default state; with q alone the system starts at rest (q̇ = 0);
/// with q̇ alone, from the default q.
template <int N>
State<N> initial_state(const ModelInfo& info, const ModelSpec& spec, const State<N>& defaults) {
  check_state_sizes(info, spec);
  State<N> s = defaults;
  if (!spec.q.empty()) {
    for (int i = 0; i < N; ++i) s.q[i] = spec.q[static_cast<std::size_t>(i)];
    if (spec.qd.empty()) s.qd.setZero();
  }
  if (!spec.qd.empty())
    for (int i = 0; i < N; ++i) s.qd[i] = spec.qd[static_cast<std::size_t>(i)];
  return s;
}

// -- inspection -----------------------------------------------------------------

/// Why the energy function h = p·q̇ − L is not conserved ("" when it is):
/// the test simulate() applies for RunReport::conservative.
template <class M>
std::string energy_not_conserved_because(const M& model, const State<coordinate_count_v<M>>& s, double t0) {
  std::vector<std::string> why;
  if (uses_generalized_forces(model)) why.emplace_back("generalized forces Q are declared");
  if (uses_dissipation(model)) why.emplace_back("a dissipation function D is declared");
  if (!is_autonomous(model, s, t0)) why.emplace_back("L depends explicitly on t");
  if (!lagrangian::detail::constraints_workless(model, s, t0)) why.emplace_back("moving constraints do work");
  std::string out;
  for (std::size_t i = 0; i < why.size(); ++i) out += (i ? "; " : "") + why[i];
  return out;
}

/// What an inspection shows beyond what the model's type tells: for a model
/// stated by expressions, its momenta as formulas.
struct InspectExtras {
  std::vector<std::string> momentum_formulas;  ///< p_i = ∂T/∂q̇_i, one per coordinate
};

/// What the inspection shows of a model at a state (q, q̇, t0), gathered by
/// the model's own code (inspect_facts) and written as text or JSON by
/// write_inspection() (registry.cpp), which is compiled once.
struct InspectFacts {
  std::vector<std::string> names;
  std::vector<double> q, qd, p;       ///< the state and p = ∂L/∂q̇
  std::optional<DofReport> dof;       ///< models with constraints
  std::vector<int> cyclic;            ///< cyclic coordinates
  double h = 0;                       ///< energy function (J)
  std::string energy_why_not;         ///< why h is not conserved ("" when it is)
  bool impacts_dissipate = false;     ///< a contact has e < 1
  bool kinetic_potential = false;     ///< T and V given apart (then T, V, natural)
  double T = 0, V = 0;
  bool natural = false;               ///< h = T + V at the state and nearby
  bool uses_forces = false;
  std::vector<double> q_force;        ///< Q(t0)
  bool uses_dissipation = false;
  std::vector<double> dissipation_force;  ///< −∂D/∂q̇ at t0
  std::vector<std::string> constraint_names;
  int holonomic = 0, unilateral = 0, pfaffian = 0;
  bool restitution_declared = false;
  std::vector<double> restitution;    ///< e per contact
  std::vector<EventSpec> events;      ///< watched events
  std::vector<PointMotion> masses;    ///< particles or mass points
  bool closed_form = false;           ///< the model has reference()
};

/// The inspection of a model from its facts: coordinates, parameters, state
/// and momenta, constraints and degrees of freedom, conserved quantities and
/// the declared forces, contacts and events; as text, or as one JSON object.
std::string write_inspection(const InspectFacts& f, const ModelInfo& info, std::string_view type,
                             const Parameters& params, double t0, bool as_json, const InspectExtras& extras);

/// The facts of `model` at (s, t0) for write_inspection().
template <class M>
InspectFacts inspect_facts(const M& model, const State<coordinate_count_v<M>>& s, double t0) {
  constexpr int n = coordinate_count_v<M>;  // (Dynamic for a run-time sized model)
  const int size = static_cast<int>(s.q.size());
  InspectFacts f;
  const auto names = coordinate_names(model);
  f.names.assign(names.begin(), names.end());
  const Vec<double, n> p = momenta(model, s.q, s.qd, t0);
  f.q.assign(s.q.data(), s.q.data() + size);
  f.qd.assign(s.qd.data(), s.qd.data() + size);
  f.p.assign(p.data(), p.data() + size);
  if (has_constraints(model)) f.dof = dof_report(model, s, t0);
  f.cyclic = cyclic_coordinates(model, s, t0);
  f.h = energy_function(model, s.q, s.qd, t0);
  f.energy_why_not = energy_not_conserved_because(model, s, t0);
  if constexpr (unilateral_count_v<M> > 0 && has_restitution_v<M>) {
    const auto e = restitution_coefficients(model);
    for (double v : e) f.impacts_dissipate = f.impacts_dissipate || v < 1.0;
  }
  if constexpr (has_kinetic_potential_v<M>) {
    f.kinetic_potential = true;
    f.T = model.kinetic(s.q, s.qd, t0);
    f.V = model.potential(s.q, t0);
    // Natural system: h = T + V at the state and at nearby states.
    f.natural = true;
    for (const State<n>& probe : lagrangian::detail::probe_states(s)) {
      const double tp = model.kinetic(probe.q, probe.qd, t0), vp = model.potential(probe.q, t0);
      const double hp = energy_function(model, probe.q, probe.qd, t0);
      f.natural = f.natural && std::abs(hp - (tp + vp)) <= 1e-12 * std::max(1.0, std::abs(tp) + std::abs(vp));
    }
  }
  // Q(t0) alone, and −∂D/∂q̇ alone (the forces less Q).
  Vec<double, n> q_force = Vec<double, n>::Zero(size);
  if constexpr (has_generalized_forces_v<M>) {
    if (uses_generalized_forces(model)) q_force = model.generalized_forces(s.q, s.qd, t0);
  }
  f.uses_forces = uses_generalized_forces(model);
  f.q_force.assign(q_force.data(), q_force.data() + size);
  f.uses_dissipation = uses_dissipation(model);
  if (f.uses_dissipation) {
    const Vec<double, n> qd_force = nonconservative_forces(model, s.q, s.qd, t0) - q_force;
    f.dissipation_force.assign(qd_force.data(), qd_force.data() + size);
  }
  f.constraint_names = constraint_names(model);
  f.holonomic = holonomic_count(model);
  f.unilateral = unilateral_count(model);
  f.pfaffian = pfaffian_count(model);
  if constexpr (has_restitution_v<M>) {
    if (f.unilateral > 0) {
      f.restitution_declared = true;
      const auto e = restitution_coefficients(model);
      f.restitution.assign(e.begin(), e.end());
    }
  }
  if constexpr (event_count_v<M> > 0) f.events = event_specs(model);
  // The point masses: the model's particles (placed by their coordinates)
  // or its mass points (a text model's points with a mass).
  if constexpr (lagrangian::detail::has_point_masses_v<M>)
    lagrangian::detail::point_motions(model, s.q.data(), s.qd.data(), nullptr, t0, 1.0, f.masses);
  f.closed_form = has_reference_v<M>;
  return f;
}

/// The inspection text (or JSON) of a model at (s, t0).
template <class M>
std::string inspect_model(const M& model, const ModelInfo& info, std::string_view type, const Parameters& params,
                          const State<coordinate_count_v<M>>& s, double t0, bool as_json = false,
                          const InspectExtras& extras = {}) {
  return write_inspection(inspect_facts(model, s, t0), info, type, params, t0, as_json, extras);
}

// -- entries ----------------------------------------------------------------------

/// Def::build(p) when the Def has one; otherwise the model's constructor
/// called with the description's parameters in their order,
/// Model(p[name_0], p[name_1], …).
template <class Def>
typename Def::Model build_model(const ModelInfo& info, const Parameters& p) {
  return with_parameter_keys<Def>(info, [&] {
    if constexpr (requires { Def::build(p); }) {
      return Def::build(p);
    } else {
      constexpr const auto& d = description_of<Def>();
      return [&]<std::size_t... I>(std::index_sequence<I...>) {
        return typename Def::Model(p[d.parameters[I].name]...);
      }(std::make_index_sequence<d.parameters.size()>{});
    }
  });
}

template <class Def>
State<coordinate_count_v<typename Def::Model>> default_state(const ModelInfo& info, const typename Def::Model& model,
                                                             double t0) {
  return with_parameter_keys<Def>(info, [&] { return Def::initial(model, t0); });
}

template <class Def>
RunReport run_entry(const ModelSpec& spec, const SimulationOptions& options, const std::string& csv_path,
                    const SampleTick& tick, FinalState* final_state) {
  const ModelInfo& info = info_of<Def>();
  const Parameters p(info, spec);
  const typename Def::Model model = build_model<Def>(info, p);
  const auto initial = initial_state(info, spec, default_state<Def>(info, model, options.t0));
  return run_model(model, initial, options, csv_path, tick, final_state);
}

/// q̈, p, M and h of the model of `spec` at (q, q̇, t) (ModelEntry::eom).
template <class Def>
lagrangian::detail::EomSample eom_entry(const ModelSpec& spec, const double* q, const double* qd, double t) {
  const ModelInfo& info = info_of<Def>();
  return lagrangian::detail::eom_sample(build_model<Def>(info, Parameters(info, spec)), q, qd, t);
}

template <class Def>
std::string inspect_entry(const ModelSpec& spec, double t0, bool as_json) {
  const ModelInfo& info = info_of<Def>();
  const Parameters p(info, spec);
  const typename Def::Model model = build_model<Def>(info, p);
  const auto initial = initial_state(info, spec, default_state<Def>(info, model, t0));
  return inspect_model(model, info, Def::type, p, initial, t0, as_json);
}

template <class Def>
std::string analyse_entry(const ModelSpec& spec, double t0, const AnalysisRequest& request) {
  const ModelInfo& info = info_of<Def>();
  const Parameters p(info, spec);
  const typename Def::Model model = build_model<Def>(info, p);
  const auto initial = initial_state(info, spec, default_state<Def>(info, model, t0));
  return analyse_model(model, info, initial, t0, request);
}

/// `compute(model, initial)` on the model and initial state of `spec` at
/// options.run.t0, for the models the tangent flow is derived for (see
/// with_tangent_flow; `what` names the analysis in a refusal).
template <class Def, class Result, class Options, class Compute>
Result tangent_flow_entry(const ModelSpec& spec, const Options& options, const char* what, Compute&& compute) {
  const ModelInfo& info = info_of<Def>();
  const Parameters p(info, spec);
  const typename Def::Model model = build_model<Def>(info, p);
  const auto initial = initial_state(info, spec, default_state<Def>(info, model, options.run.t0));
  return with_tangent_flow<Result>(model, info, what, [&](const auto& m) { return compute(m, initial); });
}

template <class Def>
LyapunovResult lyapunov_entry(const ModelSpec& spec, const LyapunovOptions& options) {
  return tangent_flow_entry<Def, LyapunovResult>(spec, options, "lyapunov", [&](const auto& m, const auto& initial) {
    return lyapunov_spectrum(m, initial, options);
  });
}

template <class Def>
FloquetResult floquet_entry(const ModelSpec& spec, const FloquetOptions& options) {
  return tangent_flow_entry<Def, FloquetResult>(spec, options, "floquet", [&](const auto& m, const auto& initial) {
    return floquet_multipliers(m, initial, options);
  });
}

/// sensitivities() of the model, its parameter columns asked for by the
/// scene's names: a scene parameter that sets every body's (one m for
/// m1 … mN) has the sum of their columns (shared_parameter_columns.hpp).
/// Every built-in model offers parameter types (has_parameter_type_v).
template <class Def>
SensitivityResult sensitivity_entry(const ModelSpec& spec, const SensitivityOptions& options) {
  return tangent_flow_entry<Def, SensitivityResult>(
      spec, options, "sensitivity", [&](const auto& m, const auto& initial) {
        using M = std::decay_t<decltype(m)>;
        static_assert(has_parameter_type_v<M>,
                      "a built-in model offers parameter sensitivities: declare with_parameter_type and "
                      "parameter_members() (analysis/sensitivity.hpp)");
        const SharedParameterColumns columns =
            shared_parameter_columns(options.parameters, info_of<Def>(), parameter_names_of<M>());
        if (columns.one_to_one()) return sensitivities(m, initial, options);
        SensitivityOptions expanded = options;
        expanded.parameters = columns.model;
        return fold_shared_columns(sensitivities(m, initial, expanded), columns);
      });
}

template <class Def>
BvpResult bvp_entry(const ModelSpec& spec, const BvpRequest& request, DiscreteRule rule) {
  const ModelInfo& info = info_of<Def>();
  const Parameters p(info, spec);
  const typename Def::Model model = build_model<Def>(info, p);
  return solve_model_bvp(model, info, request, rule);
}

}  // namespace lagrangian::scene::detail
