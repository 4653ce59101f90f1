// Scene files in TOML: every key is read into a Scene field, its line is
// recorded in Scene::source, and anything unexpected is a SceneError naming
// the file, the line, the key path and the value (docs/scenes.md).

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/io.hpp"
#include "scene_messages.hpp"
#include "text.hpp"
#include "toml_document.hpp"

namespace lagrangian::scene {

namespace {

std::string quote_text(std::string_view s, char quote = '"') { return text::quoted(s, quote); }
using text::join;

using detail::format_value;

std::string idx(const std::string& prefix, std::size_t i) { return prefix + "[" + std::to_string(i) + "]"; }
std::string sub(const std::string& prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : prefix + "." + std::string(key);
}

/// Reads a parsed document into a Scene.
class Reader {
 public:
  explicit Reader(Scene& s) : s_(s) {}

  void read(const toml::table& root) {
    keys(root, "",
         {"name", "description", "run", "output", "bodies", "gas", "gravity", "newtonian_gravity", "springs",
          "linear_drag", "quadratic_drag", "links", "surfaces", "contacts", "model"});
    if (auto* n = get(root, "", "name")) s_.name = string(*n, "name");
    if (auto* n = get(root, "", "description")) s_.description = string(*n, "description");
    if (auto* t = table(root, "", "run")) read_run(*t);
    if (auto* t = table(root, "", "output")) read_output(*t);
    for_each_table(root, "bodies", [&](const toml::table& t, const std::string& p) { read_body(t, p); });
    if (auto* t = table(root, "", "gas")) read_gas(*t);
    if (auto* t = table(root, "", "gravity")) {
      keys(*t, "gravity", {"g"});
      UniformGravity g;
      if (auto* n = get(*t, "gravity", "g")) g.g = vec3(*n, "gravity.g");
      s_.gravity = g;
    }
    if (auto* t = table(root, "", "newtonian_gravity")) {
      keys(*t, "newtonian_gravity", {"G"});
      NewtonianGravity g;
      if (auto* n = get(*t, "newtonian_gravity", "G")) g.G = number(*n, "newtonian_gravity.G");
      s_.newtonian_gravity = g;
    }
    for_each_table(root, "springs", [&](const toml::table& t, const std::string& p) { read_spring(t, p); });
    for_each_table(root, "linear_drag", [&](const toml::table& t, const std::string& p) {
      LinearDrag d;
      read_drag(t, p, d.coefficient, d.bodies);
      s_.linear_drag.push_back(std::move(d));
    });
    for_each_table(root, "quadratic_drag", [&](const toml::table& t, const std::string& p) {
      QuadraticDrag d;
      read_drag(t, p, d.coefficient, d.bodies);
      s_.quadratic_drag.push_back(std::move(d));
    });
    for_each_table(root, "links", [&](const toml::table& t, const std::string& p) { read_link(t, p); });
    for_each_table(root, "surfaces", [&](const toml::table& t, const std::string& p) { read_surface(t, p); });
    if (auto* t = table(root, "", "contacts")) read_contacts(*t);
    if (auto* t = table(root, "", "model")) read_model(*t);
  }

 private:
  Scene& s_;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(key, what, s_.source);
  }

  void record(const std::string& key, const toml::node& n) {
    const auto line = n.source().begin.line;
    if (line > 0 && line <= static_cast<toml::source_index>(std::numeric_limits<int>::max()))
      s_.source.lines[key] = static_cast<int>(line);
  }

  /// Every key of t must be one of `allowed`.
  void keys(const toml::table& t, const std::string& prefix, std::initializer_list<const char*> allowed) {
    for (auto&& [k, v] : t) {
      const std::string_view name = k.str();
      if (std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return name == a; })) continue;
      const std::string key = sub(prefix, name);
      const auto line = k.source().begin.line > 0 ? k.source().begin.line : v.source().begin.line;
      if (line > 0 && line <= static_cast<toml::source_index>(std::numeric_limits<int>::max()))
        s_.source.lines[key] = static_cast<int>(line);
      std::vector<std::string> names(allowed.begin(), allowed.end());
      const std::string near = nearest(std::string(name), names);
      fail(key, "unknown key " + quote_text(name, '\'') +
                    (near.empty() ? "; valid keys here: " + join(names) : "; did you mean '" + near + "'?"));
    }
  }

  /// The node at t[name] (recording its line), or nullptr.
  const toml::node* get(const toml::table& t, const std::string& prefix, const char* name) {
    const toml::node* n = t.get(name);
    if (n != nullptr) record(sub(prefix, name), *n);
    return n;
  }

  const toml::node& required(const toml::table& t, const std::string& prefix, const char* name) {
    const toml::node* n = get(t, prefix, name);
    if (n == nullptr) fail(sub(prefix, name), "missing required key '" + std::string(name) + "'");
    return *n;
  }

  const toml::table* table(const toml::table& t, const std::string& prefix, const char* name) {
    const toml::node* n = get(t, prefix, name);
    if (n == nullptr) return nullptr;
    if (!n->is_table()) fail(sub(prefix, name), "expected a table, got " + detail::describe_value(*n));
    return n->as_table();
  }

  /// Calls fn(table, "name[i]") for every table of the array of tables t[name].
  template <class Fn>
  void for_each_table(const toml::table& t, const char* name, Fn fn, const std::string& prefix = "") {
    const toml::node* n = get(t, prefix, name);
    if (n == nullptr) return;
    const std::string key = sub(prefix, name);
    if (!n->is_array())
      fail(key, "expected an array of tables ([[" + key + "]]), got " + detail::describe_value(*n));
    const toml::array& a = *n->as_array();
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::string p = idx(key, i);
      const toml::node& e = *a.get(i);
      record(p, e);
      if (!e.is_table()) fail(p, "expected a table, got " + detail::describe_value(e));
      fn(*e.as_table(), p);
    }
  }

  double number(const toml::node& n, const std::string& key) const {
    double v = 0;
    if (n.is_integer()) {
      v = static_cast<double>(n.as_integer()->get());
    } else if (n.is_floating_point()) {
      v = n.as_floating_point()->get();
    } else {
      fail(key, "expected a number, got " + detail::describe_value(n));
    }
    if (!std::isfinite(v)) fail(key, "must be a finite number, got " + format_value(v));
    return v;
  }

  std::int64_t integer(const toml::node& n, const std::string& key) const {
    if (!n.is_integer()) fail(key, "expected an integer, got " + detail::describe_value(n));
    return n.as_integer()->get();
  }

  std::string string(const toml::node& n, const std::string& key) const {
    if (!n.is_string()) fail(key, "expected a string, got " + detail::describe_value(n));
    return n.as_string()->get();
  }

  bool boolean(const toml::node& n, const std::string& key) const {
    if (!n.is_boolean()) fail(key, "expected true or false, got " + detail::describe_value(n));
    return n.as_boolean()->get();
  }

  Vec3 vec3(const toml::node& n, const std::string& key) {
    if (!n.is_array() || n.as_array()->size() != 3)
      fail(key, "expected an array of 3 numbers [x, y, z], got " + detail::describe_value(n));
    const toml::array& a = *n.as_array();
    Vec3 v;
    for (int i = 0; i < 3; ++i) {
      const toml::node& e = *a.get(static_cast<std::size_t>(i));
      record(idx(key, static_cast<std::size_t>(i)), e);
      v[i] = number(e, idx(key, static_cast<std::size_t>(i)));
    }
    return v;
  }

  std::vector<double> numbers(const toml::node& n, const std::string& key) {
    if (!n.is_array()) fail(key, "expected an array of numbers, got " + detail::describe_value(n));
    std::vector<double> out;
    const toml::array& a = *n.as_array();
    for (std::size_t i = 0; i < a.size(); ++i) {
      record(idx(key, i), *a.get(i));
      out.push_back(number(*a.get(i), idx(key, i)));
    }
    return out;
  }

  std::vector<std::string> strings(const toml::node& n, const std::string& key) {
    if (!n.is_array()) fail(key, "expected an array of strings, got " + detail::describe_value(n));
    std::vector<std::string> out;
    const toml::array& a = *n.as_array();
    for (std::size_t i = 0; i < a.size(); ++i) {
      record(idx(key, i), *a.get(i));
      out.push_back(string(*a.get(i), idx(key, i)));
    }
    return out;
  }

  /// A string that must be one of `choices`.
  std::string choice(const toml::node& n, const std::string& key, const std::vector<std::string>& choices,
                     const char* what) const {
    const std::string v = string(n, key);
    if (std::find(choices.begin(), choices.end(), v) != choices.end()) return v;
    const std::string near = nearest(v, choices);
    fail(key, std::string("unknown ") + what + " " + quote_text(v, '\'') +
                  (near.empty() ? "; expected one of: " + join(choices) : "; did you mean '" + near + "'?"));
  }

  // -- sections --

  void read_run(const toml::table& t) {
    const std::string p = "run";
    keys(t, p,
         {"method", "engine", "t0", "t_end", "dt", "rtol", "atol", "output_interval", "max_steps", "stabilization",
          "baumgarte_omega"});
    RunSpec& r = s_.run;
    if (auto* n = get(t, p, "engine")) r.engine = string(*n, "run.engine");
    if (auto* n = get(t, p, "method")) {
      // A stepper (method.hpp), or the event-driven engine by another name.
      std::vector<std::string> names = stepper_names();
      names.emplace_back("event_driven");
      const std::string v = choice(*n, "run.method", names, "stepper");
      if (v != "event_driven") {
        r.method = *find_method(v);
      } else if (r.engine == "ode") {
        fail("run.method", "'event_driven' is the event-driven engine, which contradicts engine = \"ode\"");
      } else {
        r.engine = "event_driven";
        r.engine_key = "run.method";
      }
    }
    if (auto* n = get(t, p, "t0")) r.t0 = number(*n, "run.t0");
    if (auto* n = get(t, p, "t_end")) r.t_end = number(*n, "run.t_end");
    if (auto* n = get(t, p, "dt")) r.dt = number(*n, "run.dt");
    if (auto* n = get(t, p, "rtol")) r.rtol = number(*n, "run.rtol");
    if (auto* n = get(t, p, "atol")) r.atol = number(*n, "run.atol");
    if (auto* n = get(t, p, "output_interval")) r.output_interval = number(*n, "run.output_interval");
    if (auto* n = get(t, p, "max_steps")) {
      const std::int64_t v = integer(*n, "run.max_steps");
      if (v <= 0) fail("run.max_steps", "must be an integer > 0, got " + std::to_string(v));
      r.max_steps = static_cast<std::uint64_t>(v);
    }
    if (auto* n = get(t, p, "stabilization")) {
      const std::string v =
          choice(*n, "run.stabilization", {"none", "baumgarte", "projection"}, "stabilization");
      r.stabilization = v == "none" ? Stabilization::none
                        : v == "baumgarte" ? Stabilization::baumgarte
                                           : Stabilization::projection;
    }
    if (auto* n = get(t, p, "baumgarte_omega")) r.baumgarte_omega = number(*n, "run.baumgarte_omega");
  }

  void read_output(const toml::table& t) {
    const std::string p = "output";
    keys(t, p, {"directory", "trajectory", "plots", "formats", "max_events", "animation"});
    OutputSpec& o = s_.output;
    if (auto* n = get(t, p, "directory")) o.directory = string(*n, "output.directory");
    if (auto* n = get(t, p, "trajectory")) o.trajectory = boolean(*n, "output.trajectory");
    if (auto* n = get(t, p, "plots")) o.plots = boolean(*n, "output.plots");
    if (auto* n = get(t, p, "animation")) o.animation = boolean(*n, "output.animation");
    if (auto* n = get(t, p, "max_events")) {
      const std::int64_t v = integer(*n, "output.max_events");
      if (v < 0) fail("output.max_events", "must be an integer >= 0, got " + std::to_string(v));
      o.max_events = static_cast<std::uint64_t>(v);
    }
    if (auto* n = get(t, p, "formats")) {
      const auto formats = strings(*n, "output.formats");
      o.png = o.svg = false;
      for (std::size_t i = 0; i < formats.size(); ++i) {
        const std::string f = choice(*n->as_array()->get(i), idx("output.formats", i), {"png", "svg"}, "format");
        (f == "png" ? o.png : o.svg) = true;
      }
    }
  }

  void read_body(const toml::table& t, const std::string& p) {
    keys(t, p, {"name", "mass", "radius", "position", "velocity"});
    Body b;
    b.name = string(required(t, p, "name"), p + ".name");
    b.mass = number(required(t, p, "mass"), p + ".mass");
    if (auto* n = get(t, p, "radius")) b.radius = number(*n, p + ".radius");
    if (auto* n = get(t, p, "position")) b.position = vec3(*n, p + ".position");
    if (auto* n = get(t, p, "velocity")) b.velocity = vec3(*n, p + ".velocity");
    s_.bodies.push_back(std::move(b));
  }

  void read_gas(const toml::table& t) {
    const std::string p = "gas";
    keys(t, p, {"count", "mass", "radius", "speed", "seed", "prefix"});
    GasFill g;
    const std::int64_t count = integer(required(t, p, "count"), "gas.count");
    if (count < 1) fail("gas.count", "must be an integer >= 1, got " + std::to_string(count));
    if (count > GasFill::max_count)
      fail("gas.count", "must be at most " + std::to_string(GasFill::max_count) + ", got " + std::to_string(count));
    g.count = static_cast<int>(count);
    if (auto* n = get(t, p, "mass")) g.mass = number(*n, "gas.mass");
    if (auto* n = get(t, p, "radius")) g.radius = number(*n, "gas.radius");
    if (auto* n = get(t, p, "speed")) g.speed = number(*n, "gas.speed");
    if (auto* n = get(t, p, "seed")) {
      const std::int64_t seed = integer(*n, "gas.seed");
      if (seed < 0) fail("gas.seed", "must be an integer >= 0, got " + std::to_string(seed));
      g.seed = static_cast<std::uint64_t>(seed);
    }
    if (auto* n = get(t, p, "prefix")) g.prefix = string(*n, "gas.prefix");
    s_.gas = g;
  }

  /// Reads `b` or `anchor` (exactly one) of a spring or link.
  void other_end(const toml::table& t, const std::string& p, std::string& b, Vec3& anchor) {
    const toml::node* nb = get(t, p, "b");
    const toml::node* na = get(t, p, "anchor");
    if (nb != nullptr && na != nullptr)
      fail(p + ".anchor", "give either 'b' (a second body) or 'anchor' (a fixed point), not both");
    if (nb == nullptr && na == nullptr)
      fail(p, "missing the other end: give either 'b' (a second body) or 'anchor' (a fixed point)");
    if (nb != nullptr) {
      b = string(*nb, p + ".b");
      if (b.empty()) fail(p + ".b", "must name a body, got an empty string");
    } else {
      anchor = vec3(*na, p + ".anchor");
    }
  }

  void read_spring(const toml::table& t, const std::string& p) {
    keys(t, p, {"name", "a", "b", "anchor", "stiffness", "rest_length"});
    Spring s;
    if (auto* n = get(t, p, "name")) s.name = string(*n, p + ".name");
    s.a = string(required(t, p, "a"), p + ".a");
    other_end(t, p, s.b, s.anchor);
    s.stiffness = number(required(t, p, "stiffness"), p + ".stiffness");
    if (auto* n = get(t, p, "rest_length")) s.rest_length = number(*n, p + ".rest_length");
    s_.springs.push_back(std::move(s));
  }

  void read_drag(const toml::table& t, const std::string& p, double& coefficient, std::vector<std::string>& bodies) {
    keys(t, p, {"coefficient", "bodies"});
    coefficient = number(required(t, p, "coefficient"), p + ".coefficient");
    if (auto* n = get(t, p, "bodies")) bodies = strings(*n, p + ".bodies");
  }

  void read_link(const toml::table& t, const std::string& p) {
    keys(t, p, {"name", "a", "b", "anchor", "length"});
    Link l;
    if (auto* n = get(t, p, "name")) l.name = string(*n, p + ".name");
    l.a = string(required(t, p, "a"), p + ".a");
    other_end(t, p, l.b, l.anchor);
    if (auto* n = get(t, p, "length")) l.length = number(*n, p + ".length");
    s_.links.push_back(std::move(l));
  }

  void read_surface(const toml::table& t, const std::string& p) {
    keys(t, p, {"name", "body", "kind", "point", "centre", "normal", "radius"});
    Surface s;
    if (auto* n = get(t, p, "name")) s.name = string(*n, p + ".name");
    s.body = string(required(t, p, "body"), p + ".body");
    const std::string kind = choice(required(t, p, "kind"), p + ".kind", {"plane", "sphere"}, "surface kind");
    s.kind = kind == "plane" ? Surface::Kind::plane : Surface::Kind::sphere;
    const toml::node* point = get(t, p, "point");
    const toml::node* centre = get(t, p, "centre");
    const toml::node* normal = get(t, p, "normal");
    const toml::node* radius = get(t, p, "radius");
    if (s.kind == Surface::Kind::plane) {
      if (centre != nullptr) fail(p + ".centre", "'centre' is for kind = \"sphere\"; a plane takes 'point'");
      if (radius != nullptr) fail(p + ".radius", "'radius' is for kind = \"sphere\"; a plane has none");
      if (point != nullptr) s.point = vec3(*point, p + ".point");
      if (normal != nullptr) s.normal = vec3(*normal, p + ".normal");
    } else {
      if (normal != nullptr) fail(p + ".normal", "'normal' is for kind = \"plane\"; a sphere has none");
      if (point != nullptr && centre != nullptr)
        fail(p + ".centre", "give the sphere's centre as either 'point' or 'centre', not both");
      if (point != nullptr) s.point = vec3(*point, p + ".point");
      if (centre != nullptr) s.point = vec3(*centre, p + ".centre");
      if (centre != nullptr) s_.source.lines.emplace(p + ".point", s_.source.line_of(p + ".centre"));
      s.radius = number(required(t, p, "radius"), p + ".radius");
    }
    s_.surfaces.push_back(std::move(s));
  }

  void read_contacts(const toml::table& t) {
    keys(t, "contacts", {"spheres", "planes", "box"});
    if (auto* sp = table(t, "contacts", "spheres")) {
      const std::string p = "contacts.spheres";
      keys(*sp, p, {"restitution", "bodies"});
      SphereContacts c;
      if (auto* n = get(*sp, p, "restitution")) c.restitution = number(*n, p + ".restitution");
      if (auto* n = get(*sp, p, "bodies")) c.bodies = strings(*n, p + ".bodies");
      s_.sphere_contacts = c;
    }
    for_each_table(
        t, "planes",
        [&](const toml::table& pt, const std::string& p) {
          keys(pt, p, {"name", "point", "normal", "restitution", "bodies"});
          PlaneContact c;
          if (auto* n = get(pt, p, "name")) c.name = string(*n, p + ".name");
          if (auto* n = get(pt, p, "point")) c.point = vec3(*n, p + ".point");
          if (auto* n = get(pt, p, "normal")) c.normal = vec3(*n, p + ".normal");
          if (auto* n = get(pt, p, "restitution")) c.restitution = number(*n, p + ".restitution");
          if (auto* n = get(pt, p, "bodies")) c.bodies = strings(*n, p + ".bodies");
          s_.planes.push_back(std::move(c));
        },
        "contacts");
    if (auto* bt = table(t, "contacts", "box")) {
      const std::string p = "contacts.box";
      keys(*bt, p, {"min", "max", "restitution"});
      BoxContact b;
      b.min = vec3(required(*bt, p, "min"), p + ".min");
      b.max = vec3(required(*bt, p, "max"), p + ".max");
      if (auto* n = get(*bt, p, "restitution")) b.restitution = number(*n, p + ".restitution");
      s_.box = b;
    }
  }

  void read_model(const toml::table& t) {
    const std::string p = "model";
    keys(t, p,
         {"name", "q", "qd", "parameters", "coordinates", "units", "kinetic", "potential", "forces", "dissipation",
          "holonomic", "pfaffian", "constraint_names", "constraint_units", "contacts", "points", "rods"});
    ModelSpec m;
    if (get(t, p, "kinetic") || get(t, p, "coordinates")) {
      // A model stated by expressions (TextModelSpec).
      if (get(t, p, "name"))
        fail("model.name",
             "names a built-in model; a model stated by its kinetic energy has none (the scene's top-level name "
             "names it)");
      TextModelSpec x;
      x.coordinates = strings(required(t, p, "coordinates"), "model.coordinates");
      x.kinetic = string(required(t, p, "kinetic"), "model.kinetic");
      if (auto* n = get(t, p, "units")) x.units = strings(*n, "model.units");
      if (auto* n = get(t, p, "potential")) x.potential = string(*n, "model.potential");
      if (auto* n = get(t, p, "forces")) x.forces = strings(*n, "model.forces");
      if (auto* n = get(t, p, "dissipation")) x.dissipation = string(*n, "model.dissipation");
      if (auto* n = get(t, p, "holonomic")) x.holonomic = strings(*n, "model.holonomic");
      if (auto* n = get(t, p, "pfaffian")) x.pfaffian = strings(*n, "model.pfaffian");
      if (auto* n = get(t, p, "constraint_names")) x.constraint_names = strings(*n, "model.constraint_names");
      if (auto* n = get(t, p, "constraint_units")) x.constraint_units = strings(*n, "model.constraint_units");
      if (auto* n = get(t, p, "rods")) x.rods = boolean(*n, "model.rods");
      for_each_table(
          t, "contacts",
          [&](const toml::table& ct, const std::string& key) {
            keys(ct, key, {"name", "gap", "restitution", "unit"});
            lagrangian::text::Contact c;
            if (auto* n = get(ct, key, "name")) c.name = string(*n, key + ".name");
            c.gap = string(required(ct, key, "gap"), key + ".gap");
            c.restitution = number(required(ct, key, "restitution"), key + ".restitution");
            if (auto* n = get(ct, key, "unit")) c.unit = string(*n, key + ".unit");
            x.contacts.push_back(std::move(c));
          },
          p);
      for_each_table(
          t, "points",
          [&](const toml::table& pt, const std::string& key) {
            keys(pt, key, {"name", "mass", "x", "y", "z"});
            TextModelSpec::Point point;
            point.name = string(required(pt, key, "name"), key + ".name");
            if (auto* n = get(pt, key, "mass")) point.mass = number(*n, key + ".mass");
            if (auto* n = get(pt, key, "x")) point.x = string(*n, key + ".x");
            if (auto* n = get(pt, key, "y")) point.y = string(*n, key + ".y");
            if (auto* n = get(pt, key, "z")) point.z = string(*n, key + ".z");
            x.points.push_back(std::move(point));
          },
          p);
      m.text = std::move(x);
    } else {
      for (const char* key : {"units", "potential", "forces", "dissipation", "holonomic", "pfaffian", "constraint_names",
                              "constraint_units", "contacts", "points", "rods"})
        if (get(t, p, key))
          fail(std::string("model.") + key,
               "belongs to a model stated by expressions, which needs 'coordinates' and 'kinetic'");
      m.name = string(required(t, p, "name"), "model.name");
    }
    if (auto* n = get(t, p, "q")) m.q = numbers(*n, "model.q");
    if (auto* n = get(t, p, "qd")) m.qd = numbers(*n, "model.qd");
    if (auto* pt = table(t, p, "parameters")) {
      // Names are checked against the model by validate(), which knows its parameters.
      for (auto&& [k, v] : *pt) {
        const std::string key = "model.parameters." + std::string(k.str());
        record(key, v);
        m.parameters[std::string(k.str())] = number(v, key);
      }
    }
    s_.model = std::move(m);
  }
};

}  // namespace

Scene parse_scene(std::string_view text, const std::string& file) {
  return detail::scene_from_document(detail::parse_document(text, file), file);
}

Scene detail::scene_from_document(const toml::table& root, const std::string& file,
                                  const std::map<std::string, std::string>& overrides) {
  Scene scene;
  scene.source.file = file;
  scene.source.overrides = overrides;
  Reader(scene).read(root);
  scene.validate();
  return scene;
}

Scene load_scene(const std::string& path) {
  return parse_scene(detail::read_scene_text(path), path == "-" ? "<stdin>" : path);
}

}  // namespace lagrangian::scene
