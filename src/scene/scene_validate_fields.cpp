// Scene validation of values, names and references: run and output options,
// a built-in [model], bodies and gas, effects, constraints, contacts and the
// engine, each failure a SceneError with a precise message; and the list of
// what a scene declares (Scene::declared).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/text/text_model.hpp"
#include "scene_gas_fill.hpp"
#include "scene_messages.hpp"
#include "scene_validate.hpp"
#include "text_model_spec.hpp"

namespace lagrangian::scene {

// -- validate ---------------------------------------------------------------------------

namespace detail {

std::string idx(const std::string& prefix, std::size_t i) { return prefix + "[" + std::to_string(i) + "]"; }

void Validator::run() {
  check_run();
  check_output();
  if (s_.model) {
    check_model();
    return;
  }
  if (s_.bodies.empty() && !s_.gas)
    fail("bodies", "a scene needs bodies ([[bodies]] or [gas]) or a built-in [model]");
  check_bodies();
  check_gas();
  check_effects();
  check_constraints();
  check_contacts();
  check_engine();
  check_initial_state();
}

[[noreturn]] void Validator::fail(const std::string& key, const std::string& what) const {
  throw SceneError(key, what, s_.source);
}

void Validator::finite(const std::string& key, double v) const {
  if (!std::isfinite(v)) fail(key, "must be finite, got " + format_value(v));
}
void Validator::finite(const std::string& key, const Vec3& v) const {
  if (!v.allFinite()) fail(key, "must be finite, got " + format_vec(v));
}
void Validator::positive(const std::string& key, double v, const std::string& why) const {
  finite(key, v);
  if (!(v > 0)) fail(key, "must be > 0" + why + ", got " + format_value(v));
}
void Validator::nonnegative(const std::string& key, double v) const {
  finite(key, v);
  if (!(v >= 0)) fail(key, "must be >= 0, got " + format_value(v));
}
void Validator::restitution(const std::string& key, double e) const {
  if (!(e >= 0 && e <= 1)) fail(key, "coefficient of restitution must be in [0, 1], got " + format_value(e));
}
void Validator::nonzero_normal(const std::string& key, const Vec3& n) const {
  finite(key, n);
  const double len = n.norm();
  if (!(len > 0) || !std::isfinite(len))
    fail(key, "must be a non-zero vector of finite length, got " + format_vec(n));
}

// -- run and output --

bool Validator::event_driven() const { return s_.run.engine == "event_driven"; }

void Validator::check_run() const {
  const RunSpec& r = s_.run;
  const std::vector<std::string> engines{"auto", "ode", "event_driven"};
  if (std::find(engines.begin(), engines.end(), r.engine) == engines.end())
    fail("run.engine", "unknown engine " + quote_text(r.engine) + detail::unknown_hint(r.engine, engines));
  // The options' own checks (SimulationOptions::validate), under the scene's keys.
  try {
    r.validate();
  } catch (const InvalidOption& e) {
    fail("run." + e.field(), e.problem());
  }
  // A scene samples its run: "only the first and last states" is not offered.
  nonnegative("run.output_interval", r.output_interval);
}

void Validator::check_output() const {
  if (s_.output.directory.empty()) fail("output.directory", "must not be empty");
  if (s_.output.plots && !s_.output.png && !s_.output.svg)
    fail("output.formats", "plots are on but no format is chosen; give png and/or svg, or set plots = false");
}

// -- model --

void Validator::check_model() const {
  const ModelSpec& m = *s_.model;
  std::vector<std::string> also;
  if (!s_.bodies.empty()) also.emplace_back("bodies");
  if (s_.gas) also.emplace_back("gas");
  for (const auto& d : s_.declared()) also.push_back(d);
  if (!also.empty())
    fail("model", "a scene is either a built-in [model] or bodies with effects, not both; this one also declares " +
                      detail::join(also));
  if (event_driven())
    fail(s_.run.engine_key, "the event-driven engine runs bodies in a box, not a built-in [model]");
  if (m.text) {
    check_text_model();
    return;
  }
  if (m.user) return;  // a C++ model with its own state (scene::run_model)
  if (m.name.empty()) fail("model.name", "missing: name a built-in model");
  const ModelInfo* info = find_model(m.name);
  if (info == nullptr) {
    std::vector<std::string> names;
    for (const auto& mi : builtin_models()) names.push_back(mi.name);
    fail("model.name", "unknown model " + quote_text(m.name) + detail::unknown_hint(m.name, names));
  }
  std::vector<std::string> params;
  for (const auto& p : info->parameters) params.push_back(p.name);
  for (const auto& [name, value] : m.parameters) {
    const std::string key = "model.parameters." + name;
    if (std::find(params.begin(), params.end(), name) == params.end())
      fail(key, "unknown parameter " + quote_text(name) + " of model '" + m.name + "'" +
                    detail::unknown_hint(name, params));
    finite(key, value);
  }
  check_state("model.q", m.q, info->coordinates);
  check_state("model.qd", m.qd, info->coordinates);
}

void Validator::check_state(const std::string& key, const std::vector<double>& v,
                            const std::vector<std::string>& coordinates) const {
  if (v.empty()) return;
  if (v.size() != coordinates.size())
    fail(key, "expected " + std::to_string(coordinates.size()) + " values (" + detail::join(coordinates) + "), got " +
                  std::to_string(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) finite(idx(key, i), v[i]);
}

void Validator::check_text_model() const {
  const ModelSpec& m = *s_.model;
  try {
    lagrangian::text::read(text_definition(m));
  } catch (const lagrangian::text::ExpressionError& e) {
    fail(e.field(), detail::scene_message(e));
  }
  if (m.q.empty()) fail("model.q", "a model stated by expressions needs its initial coordinates q");
  check_state("model.q", m.q, m.text->coordinates);
  check_state("model.qd", m.qd, m.text->coordinates);
}

// -- bodies and gas --

void Validator::check_bodies() {
  for (std::size_t i = 0; i < s_.bodies.size(); ++i) {
    const Body& b = s_.bodies[i];
    const std::string key = idx("bodies", i);
    if (b.name.empty()) fail(key + ".name", "must not be empty");
    const auto [it, fresh] = by_name_.emplace(b.name, i);
    if (!fresh)
      fail(key + ".name", "duplicate body name " + quote_text(b.name) + " (also " + idx("bodies", it->second) + ")");
    positive(key + ".mass", b.mass);
    nonnegative(key + ".radius", b.radius);
    finite(key + ".position", b.position);
    finite(key + ".velocity", b.velocity);
    // The run's monitors square speeds and positions and multiply them by
    // masses: values for which that overflows give infinite energies, not a run.
    if (!std::isfinite(b.position.squaredNorm()))
      fail(key + ".position", "|r|² overflows a double at r = " + format_vec(b.position) +
                                  " m: positions must stay below about 1e154 m");
    kinetic_energy_ += 0.5 * b.mass * b.velocity.squaredNorm();  // infinite once any term is
    if (!std::isfinite(kinetic_energy_))
      fail(key + ".velocity", "the kinetic energy ½ m |v|² overflows a double (m = " + format_value(b.mass) +
                                  " kg, v = " + format_vec(b.velocity) +
                                  " m/s): energies and momenta must stay below about 1e308");
  }
}

void Validator::check_gas() {
  if (!s_.gas) return;
  const GasFill& g = *s_.gas;
  if (g.count < 1) fail("gas.count", "must be an integer >= 1, got " + std::to_string(g.count));
  if (g.count > detail::kMaxGasCount)
    fail("gas.count", "must be at most " + std::to_string(detail::kMaxGasCount) + ", got " + std::to_string(g.count));
  positive("gas.mass", g.mass);
  positive("gas.radius", g.radius, " (gas molecules are spheres)");
  nonnegative("gas.speed", g.speed);
  if (!std::isfinite(g.speed * std::sqrt(static_cast<double>(g.count))))
    fail("gas.speed", "too large: speed * sqrt(count) must be finite, got " + format_value(g.speed));
  if (!std::isfinite(kinetic_energy_ + 0.5 * g.mass * g.speed * g.speed * static_cast<double>(g.count)))
    fail("gas.speed", "the gas's kinetic energy N ½ m v² overflows a double (N = " + std::to_string(g.count) +
                          ", m = " + format_value(g.mass) + " kg, v = " + format_value(g.speed) +
                          " m/s): energies must stay below about 1e308");
  if (g.prefix.empty()) fail("gas.prefix", "must not be empty");
  if (!s_.box) fail("gas", "needs [contacts.box] to hold the gas");
  check_box_fields();
  // The molecules fill the box, so their positions reach its corners: the
  // bound on positions (check_bodies) applies to the box.
  const Vec3 corner = s_.box->min.cwiseAbs().cwiseMax(s_.box->max.cwiseAbs());
  if (!std::isfinite(corner.squaredNorm())) {
    const bool max_is_far = s_.box->max.cwiseAbs().maxCoeff() >= s_.box->min.cwiseAbs().maxCoeff();
    fail(max_is_far ? "contacts.box.max" : "contacts.box.min",
         "the gas fills the box, and |r|² overflows a double at its far corner r = " + format_vec(corner) +
             " m: a box holding a gas must stay below about 1e154 m");
  }
  layout_ = detail::gas_layout(g, *s_.box);
  if (!layout_) {
    const double room = detail::gas_capacity(g, *s_.box);
    fail("gas.count", std::to_string(g.count) + " spheres of radius " + format_value(g.radius) +
                          " do not fit in the box " + format_vec(s_.box->min) + " to " + format_vec(s_.box->max) +
                          " at lattice spacing " + format_value(2 * g.radius) + " (room for " +
                          format_value(std::floor(room)) + ")");
  }
  for (std::size_t i = 0; i < s_.bodies.size(); ++i)
    if (detail::gas_index(g, s_.bodies[i].name) >= 0)
      fail("gas.prefix", "gas molecule name " + quote_text(s_.bodies[i].name) + " is already used by " +
                             idx("bodies", i) + "; choose another prefix");
}

std::optional<BodyRef> Validator::find(const std::string& name) const {
  if (const auto it = by_name_.find(name); it != by_name_.end())
    return BodyRef{false, static_cast<std::int64_t>(it->second)};
  if (s_.gas) {
    const std::int64_t k = detail::gas_index(*s_.gas, name);
    if (k >= 0) return BodyRef{true, k};
  }
  return std::nullopt;
}

BodyRef Validator::require_body(const std::string& key, const std::string& name) const {
  if (name.empty()) fail(key, "missing: name a body");
  if (auto r = find(name)) return *r;
  std::vector<std::string> names;
  names.reserve(s_.bodies.size());
  for (const auto& b : s_.bodies) names.push_back(b.name);
  std::string hint = detail::unknown_hint(name, names);
  if (names.size() > 20 && hint.rfind("; expected", 0) == 0) hint.clear();
  fail(key, "no body named " + quote_text(name) + hint);
}

void Validator::require_bodies(const std::string& key, const std::vector<std::string>& names) const {
  for (std::size_t i = 0; i < names.size(); ++i) require_body(idx(key, i), names[i]);
}

std::string Validator::body_name(const BodyRef& r) const {
  return r.gas ? detail::gas_name(*s_.gas, r.index) : s_.bodies[static_cast<std::size_t>(r.index)].name;
}
Vec3 Validator::position(const BodyRef& r) const {
  return r.gas ? layout_->site(r.index) : s_.bodies[static_cast<std::size_t>(r.index)].position;
}
double Validator::radius(const BodyRef& r) const {
  return r.gas ? s_.gas->radius : s_.bodies[static_cast<std::size_t>(r.index)].radius;
}
std::string Validator::position_key(const BodyRef& r) const {
  return r.gas ? std::string("gas") : idx("bodies", static_cast<std::size_t>(r.index)) + ".position";
}
std::string Validator::velocity_key(const BodyRef& r) const {
  return r.gas ? std::string("gas") : idx("bodies", static_cast<std::size_t>(r.index)) + ".velocity";
}

// -- effects, constraints, contacts --

void Validator::check_effects() const {
  if (s_.gravity) finite("gravity.g", s_.gravity->g);
  if (s_.newtonian_gravity) nonnegative("newtonian_gravity.G", s_.newtonian_gravity->G);
  for (std::size_t i = 0; i < s_.springs.size(); ++i) {
    const Spring& sp = s_.springs[i];
    const std::string key = idx("springs", i);
    require_body(key + ".a", sp.a);
    if (!sp.b.empty()) {
      require_body(key + ".b", sp.b);
      if (sp.b == sp.a) fail(key + ".b", "a spring joins two different bodies; both ends are " + quote_text(sp.a));
    } else {
      finite(key + ".anchor", sp.anchor);
    }
    positive(key + ".stiffness", sp.stiffness);
    nonnegative(key + ".rest_length", sp.rest_length);
  }
  for (std::size_t i = 0; i < s_.linear_drag.size(); ++i) {
    const std::string key = idx("linear_drag", i);
    nonnegative(key + ".coefficient", s_.linear_drag[i].coefficient);
    require_bodies(key + ".bodies", s_.linear_drag[i].bodies);
  }
  for (std::size_t i = 0; i < s_.quadratic_drag.size(); ++i) {
    const std::string key = idx("quadratic_drag", i);
    nonnegative(key + ".coefficient", s_.quadratic_drag[i].coefficient);
    require_bodies(key + ".bodies", s_.quadratic_drag[i].bodies);
  }
}

void Validator::check_constraints() const {
  for (std::size_t i = 0; i < s_.links.size(); ++i) {
    const Link& l = s_.links[i];
    const std::string key = idx("links", i);
    require_body(key + ".a", l.a);
    if (!l.b.empty()) {
      require_body(key + ".b", l.b);
      if (l.b == l.a) fail(key + ".b", "a link joins two different bodies; both ends are " + quote_text(l.a));
    } else {
      finite(key + ".anchor", l.anchor);
    }
    if (!std::isnan(l.length)) positive(key + ".length", l.length);
  }
  for (std::size_t i = 0; i < s_.surfaces.size(); ++i) {
    const Surface& sf = s_.surfaces[i];
    const std::string key = idx("surfaces", i);
    const BodyRef b = require_body(key + ".body", sf.body);
    if (b.gas && s_.gas->speed != 0 && s_.gas->count > 1)
      fail(key + ".body", quote_text(sf.body) + " is a gas molecule, whose random initial velocity is not tangent "
                          "to a surface; bind an explicit body (or set gas.speed = 0)");
    finite(key + ".point", sf.point);
    if (sf.kind == Surface::Kind::plane) {
      nonzero_normal(key + ".normal", sf.normal);
    } else if (sf.kind == Surface::Kind::sphere) {
      positive(key + ".radius", sf.radius);
    } else {
      fail(key + ".kind", "unknown surface kind " + std::to_string(static_cast<int>(sf.kind)) +
                              "; expected one of: plane, sphere");
    }
  }
}

void Validator::check_box_fields() const {
  if (!s_.box) return;
  const BoxContact& b = *s_.box;
  finite("contacts.box.min", b.min);
  finite("contacts.box.max", b.max);
  static const char* axis = "xyz";
  for (int a = 0; a < 3; ++a)
    if (!(b.max[a] > b.min[a]))
      fail("contacts.box.max", "must be greater than contacts.box.min on every axis; on " + std::string(1, axis[a]) +
                                   ": max " + format_value(b.max[a]) + " <= min " + format_value(b.min[a]));
  if (!(b.max - b.min).allFinite())
    fail("contacts.box.max", "the box " + format_vec(b.min) + " to " + format_vec(b.max) +
                                 " is too large: its size overflows");
  restitution("contacts.box.restitution", b.restitution);
}

void Validator::check_contacts() const {
  if (s_.sphere_contacts) {
    restitution("contacts.spheres.restitution", s_.sphere_contacts->restitution);
    require_bodies("contacts.spheres.bodies", s_.sphere_contacts->bodies);
  }
  for (std::size_t i = 0; i < s_.planes.size(); ++i) {
    const PlaneContact& p = s_.planes[i];
    const std::string key = idx("contacts.planes", i);
    finite(key + ".point", p.point);
    nonzero_normal(key + ".normal", p.normal);
    restitution(key + ".restitution", p.restitution);
    require_bodies(key + ".bodies", p.bodies);
  }
  check_box_fields();
}

void Validator::check_engine() const {
  if (!event_driven()) return;
  const std::string& key = s_.run.engine_key;
  std::vector<std::string> other;
  for (const auto& d : s_.declared())
    if (d != "sphere_contacts" && d != "plane_contacts" && d != "box_contacts") other.push_back(d);
  if (!other.empty())
    fail(key, "the event-driven engine needs free flight between contacts, but the scene declares " +
                  detail::join(other) + " (remove them or use engine = \"ode\")");
  if (!s_.box) fail(key, "the event-driven engine needs [contacts.box] to hold the bodies");
  // It makes every pair of spheres collide: say so in the scene.
  if (!s_.sphere_contacts || !s_.sphere_contacts->bodies.empty())
    fail(key, "the event-driven engine makes every pair of spheres collide: it needs [contacts.spheres] "
              "without a 'bodies' list (or use engine = \"ode\")");
  for (std::size_t i = 0; i < s_.bodies.size(); ++i)
    if (!(s_.bodies[i].radius > 0))
      fail("bodies[" + std::to_string(i) + "].radius",
           "the event-driven engine moves spheres: radius must be > 0, got " + format_value(s_.bodies[i].radius));
}

}  // namespace detail

using detail::Validator;

void Scene::validate() const { Validator(*this).run(); }

}  // namespace lagrangian::scene

namespace lagrangian::scene {

// -- declared ------------------------------------------------------------------------

/// The effect, constraint and contact kinds the scene declares (used by the
/// validator, inspection and the run).
std::vector<std::string> Scene::declared() const {
  std::vector<std::string> out;
  if (gravity) out.emplace_back("uniform_gravity");
  if (newtonian_gravity) out.emplace_back("newtonian_gravity");
  if (!springs.empty()) out.emplace_back("springs");
  if (!linear_drag.empty()) out.emplace_back("linear_drag");
  if (!quadratic_drag.empty()) out.emplace_back("quadratic_drag");
  if (!links.empty()) out.emplace_back("links");
  if (!surfaces.empty()) out.emplace_back("surfaces");
  if (sphere_contacts) out.emplace_back("sphere_contacts");
  if (!planes.empty()) out.emplace_back("plane_contacts");
  if (box) out.emplace_back("box_contacts");
  return out;
}

}  // namespace lagrangian::scene
