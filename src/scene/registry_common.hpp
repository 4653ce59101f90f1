#pragma once
// Internal: what the registry translation units share — parameters resolved
// against the catalog, the initial state, a run with trajectory output and
// progress ticks, and the inspection text.
//
// A registry TU describes each model by a small definition struct
//
//   struct SimplePendulumDef {
//     using Model = models::SimplePendulum;
//     static constexpr std::string_view name = "simple_pendulum";        // as in the catalog
//     static constexpr std::string_view type = "models::SimplePendulum"; // for inspect
//     static Model build(const Parameters& p);                           // may throw ParameterError
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
// from one shared value); Def::alias("") names the key for messages that do
// not name a parameter.

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

#include "lagrangian/constraints.hpp"
#include "lagrangian/detail/eom_sample.hpp"  // (compiled with simulate(), src/models/)
#include "lagrangian/detail/model_run.hpp"
#include "lagrangian/detail/point_momenta.hpp"
#include "lagrangian/detail/scene_registry.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/impact.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/observers.hpp"
#include "lagrangian/params.hpp"
#include "lagrangian/scene.hpp"
#include "lagrangian/scene_models.hpp"
#include "lagrangian/simulate.hpp"
#include "json_object.hpp"
#include "key_units.hpp"
#include "registry_analysis.hpp"

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

/// The inspection text of a model at (initial, t0): coordinates,
/// parameters, state and momenta, constraints and degrees of freedom,
/// conserved quantities and the declared forces, contacts and events.
template <class M>
std::string inspect_model(const M& model, const ModelInfo& info, std::string_view type, const Parameters& params,
                          const State<coordinate_count_v<M>>& s, double t0, bool as_json = false,
                          const InspectExtras& extras = {}) {
  const std::vector<std::string>& momentum_formulas = extras.momentum_formulas;
  constexpr int n = coordinate_count_v<M>;   // (Dynamic for a run-time sized model)
  const int size = static_cast<int>(s.q.size());  // the number of coordinates
  std::ostringstream os;
  os << inspect_header(info, type, params);
  JsonObject js;  // the same facts as JSON (inspect --json)
  inspect_header_json(js, info, type, params);
  js.number("t0", t0);
  const auto names = coordinate_names(model);
  auto unit = [&](int i) {
    return static_cast<std::size_t>(i) < info.units.size() ? info.units[static_cast<std::size_t>(i)] : std::string();
  };

  // State and momenta.
  const Vec<double, n> p = momenta(model, s.q, s.qd, t0);
  os << "\nInitial state at t0 = " << number(t0) << " s\n";
  std::vector<std::vector<std::string>> rows{{"coordinate", "q", "", "qdot", "", "p = dL/dqdot", ""}};
  for (int i = 0; i < size; ++i)
    rows.push_back({names[static_cast<std::size_t>(i)], number(s.q[i]), unit(i), number(s.qd[i]),
                    velocity_unit(unit(i)), number(p[i]), momentum_unit(unit(i))});
  os << columns(rows);
  {
    std::vector<std::string> items;
    for (int i = 0; i < size; ++i) {
      JsonObject c;
      c.string("name", names[static_cast<std::size_t>(i)]);
      c.string("unit", unit(i));
      c.number("q", s.q[i]);
      c.number("qdot", s.qd[i]);
      c.number("p", p[i]);
      c.string("qdot_unit", velocity_unit(unit(i)));
      c.string("p_unit", momentum_unit(unit(i)));
      items.push_back(c.str());
    }
    js.raw("coordinates", json_array(items));
  }
  // The momenta as formulas (models stated by expressions: p_i = ∂T/∂q̇_i).
  if (!momentum_formulas.empty()) {
    os << "\nGeneralized momenta p = dL/dqdot\n";
    std::vector<std::vector<std::string>> lines;
    JsonObject f;
    for (int i = 0; i < size; ++i) {
      const std::string& c = names[static_cast<std::size_t>(i)];
      lines.push_back({"p_" + c, "=", momentum_formulas[static_cast<std::size_t>(i)]});
      f.string(c, momentum_formulas[static_cast<std::size_t>(i)]);
    }
    os << columns(lines);
    js.raw("momentum_formulas", f.str());
  }

  // Constraints and degrees of freedom.
  if (has_constraints(model)) {
    const DofReport dof = dof_report(model, s, t0);
    os << "\nConstraints and degrees of freedom\n";
    std::string redundant = dof.redundant.empty() ? "none" : "";
    for (std::size_t i = 0; i < dof.redundant.size(); ++i) redundant += (i ? ", " : "") + dof.redundant[i];
    const std::string nc = std::to_string(dof.coordinates);
    os << columns({{"coordinates", nc},
                   {"holonomic constraints", std::to_string(dof.holonomic)},
                   {"Pfaffian constraints", std::to_string(dof.pfaffian)},
                   {"unilateral constraints", std::to_string(dof.unilateral), "(contacts; not in the ranks)"},
                   {"rank of dg/dq", std::to_string(dof.holonomic_rank)},
                   {"rank of [dg/dq; A]", std::to_string(dof.velocity_rank)},
                   {"redundant constraints", redundant},
                   {"degrees of freedom", std::to_string(dof.degrees_of_freedom),
                    "= " + nc + " - " + std::to_string(dof.holonomic_rank) + " (n - rank dg/dq)"},
                   {"velocity degrees of freedom", std::to_string(dof.velocity_degrees_of_freedom),
                    "= " + nc + " - " + std::to_string(dof.velocity_rank) + " (n - rank [dg/dq; A])"}});
    JsonObject d;
    d.integer("coordinates", dof.coordinates);
    d.integer("holonomic", dof.holonomic);
    d.integer("pfaffian", dof.pfaffian);
    d.integer("unilateral", dof.unilateral);
    d.integer("rank_dg_dq", dof.holonomic_rank);
    d.integer("rank_dg_dq_and_A", dof.velocity_rank);
    d.raw("redundant", json_strings(dof.redundant));
    d.integer("degrees_of_freedom", dof.degrees_of_freedom);
    d.integer("velocity_degrees_of_freedom", dof.velocity_degrees_of_freedom);
    js.raw("constraints", d.str());
  }

  // Conserved quantities.
  os << "\nConserved quantities\n";
  std::vector<std::vector<std::string>> cons;
  const std::vector<int> cyclic = cyclic_coordinates(model, s, t0);
  if (cyclic.empty()) cons.push_back({"cyclic coordinates", "none"});
  std::vector<std::string> cyclic_json;
  for (std::size_t k = 0; k < cyclic.size(); ++k) {
    const int i = cyclic[k];
    const std::string& c = names[static_cast<std::size_t>(i)];
    cons.push_back({k == 0 ? "cyclic coordinates" : "", c,
                    "p_" + c + " = " + number(p[i]) + " " + momentum_unit(unit(i)) + " (conserved)"});
    JsonObject cj;
    cj.string("coordinate", c);
    cj.number("p", p[i]);
    cj.string("p_unit", momentum_unit(unit(i)));
    cyclic_json.push_back(cj.str());
  }
  js.raw("cyclic", json_array(cyclic_json));
  const double h = energy_function(model, s.q, s.qd, t0);
  const std::string why = energy_not_conserved_because(model, s, t0);
  std::string contact_note;
  if constexpr (unilateral_count_v<M> > 0 && has_restitution_v<M>) {
    const auto e = restitution_coefficients(model);
    bool lossy = false;
    for (double v : e) lossy = lossy || v < 1.0;
    if (lossy) contact_note = "; impacts with e < 1 dissipate";
  }
  cons.push_back({"energy function h = p.qdot - L", number(h) + " J",
                  why.empty() ? "conserved" + contact_note : "not conserved: " + why});
  {
    JsonObject hj;
    hj.number("value", h);
    hj.boolean("conserved", why.empty());
    hj.string("why_not", why);
    hj.boolean("impacts_dissipate", !contact_note.empty());
    js.raw("energy_function", hj.str());
  }
  if constexpr (has_kinetic_potential_v<M>) {
    const double T = model.kinetic(s.q, s.qd, t0), V = model.potential(s.q, t0);
    // Natural system: h = T + V at the state and at nearby states.
    bool natural = true;
    for (const State<n>& probe : lagrangian::detail::probe_states(s)) {
      const double tp = model.kinetic(probe.q, probe.qd, t0), vp = model.potential(probe.q, t0);
      const double hp = energy_function(model, probe.q, probe.qd, t0);
      natural = natural && std::abs(hp - (tp + vp)) <= 1e-12 * std::max(1.0, std::abs(tp) + std::abs(vp));
    }
    cons.push_back({"T + V", number(T + V) + " J",
                    natural ? "equals h (natural system: T quadratic in qdot)"
                            : "differs from h (T has terms of degree 0 or 1 in qdot; T = " + number(T) + " J)"});
    JsonObject e;
    e.number("T", T);
    e.number("V", V);
    e.number("T_plus_V", T + V);
    e.boolean("natural", natural);
    js.raw("energy", e.str());
  } else {
    cons.push_back({"T + V", "n/a", "the model gives L directly"});
    js.raw("energy", "null");
  }
  os << columns(cons);

  // Declared extras.
  os << "\nDeclared\n";
  std::vector<std::vector<std::string>> decl;
  JsonObject dj;
  // Q(t0) alone, and −∂D/∂q̇ alone (the forces less Q).
  Vec<double, n> q_force = Vec<double, n>::Zero(size);
  if constexpr (has_generalized_forces_v<M>) {
    if (uses_generalized_forces(model)) q_force = model.generalized_forces(s.q, s.qd, t0);
  }
  if (uses_generalized_forces(model)) {
    decl.push_back({"generalized forces Q", "yes", "Q(t0) = " + numbers(q_force.data(), size)});
    dj.raw("generalized_forces", json_numbers(q_force.data(), size));
  } else {
    decl.push_back({"generalized forces Q", "none"});
    dj.raw("generalized_forces", "null");
  }
  if (uses_dissipation(model)) {
    const Vec<double, n> qd_force = nonconservative_forces(model, s.q, s.qd, t0) - q_force;
    decl.push_back({"dissipation D", "yes", "-dD/dqdot at t0 = " + numbers(qd_force.data(), size)});
    dj.raw("dissipation_forces", json_numbers(qd_force.data(), size));
  } else {
    decl.push_back({"dissipation D", "none"});
    dj.raw("dissipation_forces", "null");
  }
  const std::vector<std::string> cnames = constraint_names(model);
  auto list = [&](int from, int count) {
    if (count == 0) return std::string("none");
    std::string out;
    for (int i = 0; i < count; ++i) out += (i ? ", " : "") + cnames[static_cast<std::size_t>(from + i)];
    return out;
  };
  const int mh = holonomic_count(model), mu = unilateral_count(model), mp = pfaffian_count(model);
  decl.push_back({"holonomic constraints", std::to_string(mh), list(0, mh)});
  decl.push_back({"Pfaffian constraints", std::to_string(mp), list(mh + mu, mp)});
  decl.push_back({"unilateral constraints", std::to_string(mu), list(mh, mu)});
  auto names_of = [&](int from, int count) {
    return std::vector<std::string>(cnames.begin() + from, cnames.begin() + from + count);
  };
  dj.raw("holonomic", json_strings(names_of(0, mh)));
  dj.raw("pfaffian", json_strings(names_of(mh + mu, mp)));
  dj.raw("unilateral", json_strings(names_of(mh, mu)));
  dj.raw("restitution", "null");
  if (mu > 0) {
    if constexpr (has_restitution_v<M>) {
      const auto e = restitution_coefficients(model);
      std::string text;
      bool same = true;
      for (double v : e) same = same && v == e[0];
      if (same) {
        text = "e = " + number(e[0]) + " for every contact";
      } else {
        for (int j = 0; j < mu; ++j)
          text += (j ? ", " : "") + cnames[static_cast<std::size_t>(mh + j)] + " " +
                  number(e[static_cast<std::size_t>(j)]);
      }
      decl.push_back({"restitution", "yes", text});
      dj.raw("restitution", json_numbers(e.data(), mu));
    } else {
      decl.push_back({"restitution", "none", "(contacts may rest and release, not be struck)"});
    }
  }
  if constexpr (event_count_v<M> > 0) {
    const std::vector<EventSpec> specs = event_specs(model);
    std::string text;
    std::vector<std::string> items;
    for (std::size_t k = 0; k < specs.size(); ++k) {
      const EventSpec& e = specs[k];
      const char* direction = e.direction == Direction::falling  ? "falling"
                              : e.direction == Direction::rising ? "rising"
                                                                 : "either";
      text += (k ? ", " : "") + e.name + " (" + direction + ", " +
              (e.action == EventAction::stop ? "stops the run" : "recorded") + ")";
      JsonObject ej;
      ej.string("name", e.name);
      ej.string("direction", direction);
      ej.string("action", e.action == EventAction::stop ? "stop" : "record");
      items.push_back(ej.str());
    }
    decl.push_back({"watched events", std::to_string(event_count_v<M>), text});
    dj.raw("watched_events", json_array(items));
  } else {
    decl.push_back({"watched events", "none"});
    dj.raw("watched_events", "[]");
  }
  // The point masses: the model's particles (placed by their coordinates)
  // or its mass points (a text model's points with a mass).
  std::vector<PointMotion> masses;
  if constexpr (lagrangian::detail::has_point_masses_v<M>)
    lagrangian::detail::point_motions(model, s.q.data(), s.qd.data(), nullptr, t0, 1.0, masses);
  if (!masses.empty()) {
    // P = Σ m v, L = Σ m r × v about the origin (as the runs report them) and
    // the centre of mass Σ m r / Σ m.
    std::array<double, 3> P{}, L{}, centre{};
    lagrangian::detail::total_momenta(masses, {0.0, 0.0, 0.0}, P, L);
    double total = 0;
    for (const PointMotion& pm : masses) {
      for (std::size_t a = 0; a < 3; ++a) centre[a] += pm.mass * pm.r[a];
      total += pm.mass;
    }
    for (double& c : centre) c /= total;
    decl.push_back({"particles", std::to_string(masses.size()),
                    "P = " + numbers(P.data(), 3) + " kg*m/s, L = " + numbers(L.data(), 3) +
                        " kg*m^2/s about the origin; centre of mass " + numbers(centre.data(), 3) + " m"});
    JsonObject pj;
    pj.integer("count", static_cast<int>(masses.size()));
    pj.raw("P", json_numbers(P.data(), 3));
    pj.raw("L", json_numbers(L.data(), 3));
    pj.raw("centre_of_mass", json_numbers(centre.data(), 3));
    js.raw("particles", pj.str());
  } else {
    js.raw("particles", "null");
  }
  decl.push_back({"closed-form reference", has_reference_v<M> ? "yes" : "no",
                  has_reference_v<M> ? "(runs report their true error)" : ""});
  js.raw("declared", dj.str());
  js.boolean("closed_form_reference", has_reference_v<M>);
  os << columns(decl);
  return as_json ? js.str() + "\n" : os.str();
}

// -- entries ----------------------------------------------------------------------

template <class Def>
typename Def::Model build_model(const ModelInfo& info, const Parameters& p) {
  return with_parameter_keys<Def>(info, [&] { return Def::build(p); });
}

template <class Def>
State<coordinate_count_v<typename Def::Model>> default_state(const ModelInfo& info, const typename Def::Model& model,
                                                             double t0) {
  return with_parameter_keys<Def>(info, [&] { return Def::initial(model, t0); });
}

template <class Def>
RunReport run_entry(const ModelSpec& spec, const SimulationOptions& options, const std::string& csv_path,
                    const SampleTick& tick, FinalState* final_state) {
  const ModelInfo& info = catalog_entry(Def::name);
  const Parameters p(info, spec);
  const typename Def::Model model = build_model<Def>(info, p);
  const auto initial = initial_state(info, spec, default_state<Def>(info, model, options.t0));
  return run_model(model, initial, options, csv_path, tick, final_state);
}

/// q̈, p, M and h of the model of `spec` at (q, q̇, t) (ModelEntry::eom).
template <class Def>
lagrangian::detail::EomSample eom_entry(const ModelSpec& spec, const double* q, const double* qd, double t) {
  const ModelInfo& info = catalog_entry(Def::name);
  return lagrangian::detail::eom_sample(build_model<Def>(info, Parameters(info, spec)), q, qd, t);
}

template <class Def>
std::string inspect_entry(const ModelSpec& spec, double t0, bool as_json) {
  const ModelInfo& info = catalog_entry(Def::name);
  const Parameters p(info, spec);
  const typename Def::Model model = build_model<Def>(info, p);
  const auto initial = initial_state(info, spec, default_state<Def>(info, model, t0));
  return inspect_model(model, info, Def::type, p, initial, t0, as_json);
}

template <class Def>
std::string analyse_entry(const ModelSpec& spec, double t0, const AnalysisRequest& request) {
  const ModelInfo& info = catalog_entry(Def::name);
  const Parameters p(info, spec);
  const typename Def::Model model = build_model<Def>(info, p);
  const auto initial = initial_state(info, spec, default_state<Def>(info, model, t0));
  return analyse_model(model, info, initial, t0, request);
}

template <class Def>
BvpResult bvp_entry(const ModelSpec& spec, const BvpRequest& request, DiscreteRule rule) {
  const ModelInfo& info = catalog_entry(Def::name);
  const Parameters p(info, spec);
  const typename Def::Model model = build_model<Def>(info, p);
  return solve_model_bvp(model, info, request, rule);
}

}  // namespace lagrangian::scene::detail
