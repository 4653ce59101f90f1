// The inspection of a generalized-coordinate model from its facts
// (write_inspection in registry_common.hpp): one copy of the text and JSON
// writing for every model, which inspect_facts<M> gathers per model.

#include <array>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

#include "json_object.hpp"
#include "key_units.hpp"
#include "lagrangian/integrate/detail/point_momenta_monitor.hpp"
#include "registry_common.hpp"

namespace lagrangian::scene::detail {
namespace {

/// The unit of coordinate i ("" when the catalog gives none).
std::string unit_of(const ModelInfo& info, int i) {
  const auto k = static_cast<std::size_t>(i);
  return k < info.units.size() ? info.units[k] : std::string();
}

/// The state and momenta, and the momenta as formulas when the model gives them.
void write_state(const InspectFacts& f, const ModelInfo& info, double t0, const InspectExtras& extras,
                 std::ostringstream& os, JsonObject& js) {
  const int size = static_cast<int>(f.q.size());
  auto unit = [&](int i) { return unit_of(info, i); };
  os << "\nInitial state at t0 = " << number(t0) << " s\n";
  std::vector<std::vector<std::string>> rows{{"coordinate", "q", "", "qdot", "", "p = dL/dqdot", ""}};
  for (int i = 0; i < size; ++i) {
    const auto k = static_cast<std::size_t>(i);
    rows.push_back({f.names[k], number(f.q[k]), unit(i), number(f.qd[k]), velocity_unit(unit(i)), number(f.p[k]),
                    momentum_unit(unit(i))});
  }
  os << columns(rows);
  std::vector<std::string> items;
  for (int i = 0; i < size; ++i) {
    const auto k = static_cast<std::size_t>(i);
    JsonObject c;
    c.string("name", f.names[k]);
    c.string("unit", unit(i));
    c.number("q", f.q[k]);
    c.number("qdot", f.qd[k]);
    c.number("p", f.p[k]);
    c.string("qdot_unit", velocity_unit(unit(i)));
    c.string("p_unit", momentum_unit(unit(i)));
    items.push_back(c.str());
  }
  js.raw("coordinates", json_array(items));
  // The momenta as formulas (models stated by expressions: p_i = ∂T/∂q̇_i).
  const std::vector<std::string>& formulas = extras.momentum_formulas;
  if (!formulas.empty()) {
    os << "\nGeneralized momenta p = dL/dqdot\n";
    std::vector<std::vector<std::string>> lines;
    JsonObject fj;
    for (std::size_t k = 0; k < f.names.size(); ++k) {
      lines.push_back({"p_" + f.names[k], "=", formulas[k]});
      fj.string(f.names[k], formulas[k]);
    }
    os << columns(lines);
    js.raw("momentum_formulas", fj.str());
  }
}

/// Constraints and degrees of freedom (models with constraints).
void write_dof(const DofReport& dof, std::ostringstream& os, JsonObject& js) {
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

/// Cyclic coordinates, the energy function and T + V.
void write_conserved(const InspectFacts& f, const ModelInfo& info, std::ostringstream& os, JsonObject& js) {
  auto unit = [&](int i) { return unit_of(info, i); };
  os << "\nConserved quantities\n";
  std::vector<std::vector<std::string>> cons;
  if (f.cyclic.empty()) cons.push_back({"cyclic coordinates", "none"});
  std::vector<std::string> cyclic_json;
  for (std::size_t k = 0; k < f.cyclic.size(); ++k) {
    const int i = f.cyclic[k];
    const std::string& c = f.names[static_cast<std::size_t>(i)];
    const double p = f.p[static_cast<std::size_t>(i)];
    cons.push_back({k == 0 ? "cyclic coordinates" : "", c,
                    "p_" + c + " = " + number(p) + " " + momentum_unit(unit(i)) + " (conserved)"});
    JsonObject cj;
    cj.string("coordinate", c);
    cj.number("p", p);
    cj.string("p_unit", momentum_unit(unit(i)));
    cyclic_json.push_back(cj.str());
  }
  js.raw("cyclic", json_array(cyclic_json));
  const std::string contact_note = f.impacts_dissipate ? "; impacts with e < 1 dissipate" : "";
  const std::string& why = f.energy_why_not;
  cons.push_back({"energy function h = p.qdot - L", number(f.h) + " J",
                  why.empty() ? "conserved" + contact_note : "not conserved: " + why});
  JsonObject hj;
  hj.number("value", f.h);
  hj.boolean("conserved", why.empty());
  hj.string("why_not", why);
  hj.boolean("impacts_dissipate", f.impacts_dissipate);
  js.raw("energy_function", hj.str());
  if (f.kinetic_potential) {
    cons.push_back({"T + V", number(f.T + f.V) + " J",
                    f.natural ? "equals h (natural system: T quadratic in qdot)"
                              : "differs from h (T has terms of degree 0 or 1 in qdot; T = " + number(f.T) + " J)"});
    JsonObject e;
    e.number("T", f.T);
    e.number("V", f.V);
    e.number("T_plus_V", f.T + f.V);
    e.boolean("natural", f.natural);
    js.raw("energy", e.str());
  } else {
    cons.push_back({"T + V", "n/a", "the model gives L directly"});
    js.raw("energy", "null");
  }
  os << columns(cons);
}

/// Forces, constraints, restitution and watched events as declared.
void write_declared_terms(const InspectFacts& f, std::vector<std::vector<std::string>>& decl, JsonObject& dj) {
  const int size = static_cast<int>(f.q.size());
  // A declared force term: its value at t0, or none.
  auto force_term = [&](const char* label, bool used, const char* value_label, const std::vector<double>& value,
                        const char* key) {
    if (used) {
      decl.push_back({label, "yes", std::string(value_label) + numbers(value.data(), size)});
      dj.raw(key, json_numbers(value.data(), size));
    } else {
      decl.push_back({label, "none"});
      dj.raw(key, "null");
    }
  };
  force_term("generalized forces Q", f.uses_forces, "Q(t0) = ", f.q_force, "generalized_forces");
  force_term("dissipation D", f.uses_dissipation, "-dD/dqdot at t0 = ", f.dissipation_force, "dissipation_forces");
  const std::vector<std::string>& cnames = f.constraint_names;
  auto list = [&](int from, int count) {
    if (count == 0) return std::string("none");
    std::string out;
    for (int i = 0; i < count; ++i) out += (i ? ", " : "") + cnames[static_cast<std::size_t>(from + i)];
    return out;
  };
  const int mh = f.holonomic, mu = f.unilateral, mp = f.pfaffian;
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
    if (f.restitution_declared) {
      const std::vector<double>& e = f.restitution;
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
  if (!f.events.empty()) {
    std::string text;
    std::vector<std::string> items;
    for (std::size_t k = 0; k < f.events.size(); ++k) {
      const EventSpec& e = f.events[k];
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
    decl.push_back({"watched events", std::to_string(f.events.size()), text});
    dj.raw("watched_events", json_array(items));
  } else {
    decl.push_back({"watched events", "none"});
    dj.raw("watched_events", "[]");
  }
}

/// The point masses: P, L about the origin and the centre of mass.
void write_masses(const std::vector<PointMotion>& masses, std::vector<std::vector<std::string>>& decl,
                  JsonObject& js) {
  if (masses.empty()) {
    js.raw("particles", "null");
    return;
  }
  // P = Σ m v, L = Σ m r × v about the origin (as the runs report them) and
  // the centre of mass Σ m r / Σ m.
  lagrangian::detail::PointMomenta momenta({0.0, 0.0, 0.0});
  std::array<double, 3> centre{};
  double total = 0;
  for (const PointMotion& pm : masses) {
    momenta.add(pm.mass, pm.r.data(), pm.v.data());
    for (std::size_t a = 0; a < 3; ++a) centre[a] += pm.mass * pm.r[a];
    total += pm.mass;
  }
  for (double& c : centre) c /= total;
  decl.push_back({"particles", std::to_string(masses.size()),
                  "P = " + numbers(momenta.linear().data(), 3) + " kg*m/s, L = " + numbers(momenta.angular().data(), 3) +
                      " kg*m^2/s about the origin; centre of mass " + numbers(centre.data(), 3) + " m"});
  JsonObject pj;
  pj.integer("count", static_cast<int>(masses.size()));
  pj.raw("P", json_numbers(momenta.linear().data(), 3));
  pj.raw("L", json_numbers(momenta.angular().data(), 3));
  pj.raw("centre_of_mass", json_numbers(centre.data(), 3));
  js.raw("particles", pj.str());
}

}  // namespace

std::string write_inspection(const InspectFacts& f, const ModelInfo& info, std::string_view type,
                             const Parameters& params, double t0, bool as_json, const InspectExtras& extras) {
  std::ostringstream os;
  os << inspect_header(info, type, params);
  JsonObject js;  // the same facts as JSON (inspect --json)
  inspect_header_json(js, info, type, params);
  js.number("t0", t0);
  write_state(f, info, t0, extras, os, js);
  if (f.dof) write_dof(*f.dof, os, js);
  write_conserved(f, info, os, js);
  os << "\nDeclared\n";
  std::vector<std::vector<std::string>> decl;
  JsonObject dj;
  write_declared_terms(f, decl, dj);
  write_masses(f.masses, decl, js);
  decl.push_back({"closed-form reference", f.closed_form ? "yes" : "no",
                  f.closed_form ? "(runs report their true error)" : ""});
  js.raw("declared", dj.str());
  js.boolean("closed_form_reference", f.closed_form);
  os << columns(decl);
  return as_json ? js.str() + "\n" : os.str();
}

}  // namespace lagrangian::scene::detail
