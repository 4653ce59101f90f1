// Scene vocabulary: validation with precise messages, gas expansion, the
// list of declared kinds, source lines and "did you mean" hints.

#include "lagrangian/scene.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <unordered_map>

#include "lagrangian/scene_models.hpp"
#include "text.hpp"

namespace lagrangian::scene {

// -- formatting helpers ---------------------------------------------------------

namespace detail {
namespace {

std::string quote_text(std::string_view s, char quote = '\'') { return text::quoted(s, quote); }
using text::join;

constexpr std::int64_t kMaxGasCount = GasFill::max_count;

/// Where the molecules of a gas sit: a cubic lattice of n[0] × n[1] × n[2]
/// sites with spacing `spacing`, site (0, 0, 0) at `first`, filled x fastest,
/// then y, then z, with the first `count` sites.
struct GasLayout {
  double spacing = 0;
  std::array<std::int64_t, 3> n{};
  Vec3 first = Vec3::Zero();
  std::int64_t count = 0;
  /// A box of site indices [lo, hi) per axis.
  struct Block {
    std::array<std::int64_t, 3> lo, hi;
  };
  Vec3 site(std::int64_t k) const;
  Vec3 site(std::int64_t ix, std::int64_t iy, std::int64_t iz) const;
  std::int64_t index(std::int64_t ix, std::int64_t iy, std::int64_t iz) const;
  /// The filled sites as at most three blocks.
  std::vector<Block> blocks() const;
};

/// Mean of the random unit directions and 1/rms of the directions less
/// their mean: molecule k moves with speed·(d_k − mean)·inv_rms, so that the
/// total momentum is zero and the rms speed is `speed`. |(d_k − mean)·inv_rms|
/// ≤ √count, so no intermediate overflows when speed·√count is finite.
struct GasVelocity {
  Vec3 mean = Vec3::Zero();
  double inv_rms = 0;
  Vec3 velocity(const Vec3& direction, double speed) const { return ((direction - mean) * inv_rms) * speed; }
};

std::string format_value(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

/// A computed quantity (a distance, a sum): 15 significant digits, so that
/// rounding noise such as 0.21000000000000002 reads 0.21.
std::string format_derived(double v) {
  if (!std::isfinite(v)) return format_value(v);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

std::string format_vec(const Vec3& v) {
  return "[" + format_value(v.x()) + ", " + format_value(v.y()) + ", " + format_value(v.z()) + "]";
}



std::string unknown_hint(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string near = nearest(word, candidates);
  if (!near.empty()) return "; did you mean '" + near + "'?";
  if (candidates.empty()) return "";
  return "; expected one of: " + join(candidates);
}

// -- the gas lattice ------------------------------------------------------------

constexpr double kLatticeMargin = 1e-6;  // spacing ≥ 2R(1 + margin), walls ≥ R(1 + margin) away

/// Sites per axis at spacing s (capped at `count`, as doubles: no overflow).
std::array<double, 3> sites_per_axis(const Vec3& usable, double s, double count) {
  std::array<double, 3> n{};
  for (int a = 0; a < 3; ++a) {
    if (!(usable[a] >= 0)) {
      n[a] = 0;
    } else {
      n[a] = std::min(std::floor(usable[a] / s) + 1.0, count);
    }
  }
  return n;
}

double capacity(const std::array<double, 3>& n) { return n[0] * n[1] * n[2]; }

double gas_capacity(const GasFill& gas, const BoxContact& box) {
  const double s = 2.0 * gas.radius * (1.0 + kLatticeMargin);
  const Vec3 usable = (box.max - box.min).array() - s;
  return capacity(sites_per_axis(usable, s, std::max(1.0, static_cast<double>(gas.count))));
}

std::optional<GasLayout> gas_layout(const GasFill& gas, const BoxContact& box) {
  if (gas.count < 1 || !(gas.radius > 0) || !std::isfinite(gas.radius)) return std::nullopt;
  const double count = static_cast<double>(gas.count);
  const double s_min = 2.0 * gas.radius * (1.0 + kLatticeMargin);
  const Vec3 usable = (box.max - box.min).array() - s_min;
  if (!usable.allFinite() || !std::isfinite(s_min)) return std::nullopt;
  if (capacity(sites_per_axis(usable, s_min, count)) < count) return std::nullopt;

  // The widest spacing that still holds `count` sites spreads the gas over the box.
  double lo = s_min;
  if (gas.count > 1) {
    double hi = s_min + usable.maxCoeff();
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
      const double mid = lo + 0.5 * (hi - lo);
      if (capacity(sites_per_axis(usable, mid, count)) >= count) {
        lo = mid;
      } else {
        hi = mid;
      }
    }
  }
  GasLayout layout;
  layout.spacing = lo;
  layout.count = gas.count;
  const auto n = sites_per_axis(usable, lo, count);
  for (int a = 0; a < 3; ++a) {
    layout.n[a] = static_cast<std::int64_t>(n[a]);
    layout.first[a] = 0.5 * (box.min[a] + box.max[a]) - 0.5 * static_cast<double>(layout.n[a] - 1) * lo;
  }
  return layout;
}

Vec3 GasLayout::site(std::int64_t k) const {
  const std::int64_t ix = k % n[0];
  const std::int64_t iy = (k / n[0]) % n[1];
  const std::int64_t iz = k / (n[0] * n[1]);
  return site(ix, iy, iz);
}

Vec3 GasLayout::site(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
  return {first[0] + static_cast<double>(ix) * spacing, first[1] + static_cast<double>(iy) * spacing,
          first[2] + static_cast<double>(iz) * spacing};
}

std::vector<GasLayout::Block> GasLayout::blocks() const {
  // Sites are filled x fastest, then y, then z: full layers, full rows of the
  // next layer, then part of a row.
  std::vector<Block> out;
  const std::int64_t layer = n[0] * n[1];
  const std::int64_t layers = count / layer;
  const std::int64_t rem = count % layer;
  const std::int64_t rows = rem / n[0];
  const std::int64_t part = rem % n[0];
  if (layers > 0) out.push_back({{0, 0, 0}, {n[0], n[1], layers}});
  if (rows > 0) out.push_back({{0, 0, layers}, {n[0], rows, layers + 1}});
  if (part > 0) out.push_back({{0, rows, layers}, {part, rows + 1, layers + 1}});
  return out;
}

std::int64_t GasLayout::index(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
  return ix + n[0] * (iy + n[1] * iz);
}

/// Uniform double in [0, 1) from the top 53 bits of one draw.
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

Vec3 random_direction(std::mt19937_64& rng) {
  const double z = 2.0 * unit(rng) - 1.0;
  const double phi = 2.0 * std::numbers::pi * unit(rng);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

GasVelocity gas_velocity(const GasFill& gas) {
  GasVelocity out;
  if (gas.count < 1) return out;
  const double n = static_cast<double>(gas.count);
  std::mt19937_64 rng(gas.seed);
  Vec3 sum = Vec3::Zero();
  for (std::int64_t k = 0; k < gas.count; ++k) sum += random_direction(rng);
  out.mean = sum / n;
  rng.seed(gas.seed);
  double sq = 0;
  for (std::int64_t k = 0; k < gas.count; ++k) sq += (random_direction(rng) - out.mean).squaredNorm();
  const double rms = std::sqrt(sq / n);
  // One sphere (or directions that cancel to rounding) cannot move with zero momentum.
  out.inv_rms = rms > 1e-12 ? 1.0 / rms : 0.0;
  return out;
}

std::string gas_name(const GasFill& gas, std::int64_t k) { return gas.prefix + std::to_string(k + 1); }

std::int64_t gas_index(const GasFill& gas, const std::string& name) {
  if (name.size() <= gas.prefix.size() || name.compare(0, gas.prefix.size(), gas.prefix) != 0) return -1;
  const std::string digits = name.substr(gas.prefix.size());
  if (digits.size() > 9 || digits[0] == '0') return -1;
  std::int64_t v = 0;
  for (const char c : digits) {
    if (c < '0' || c > '9') return -1;
    v = v * 10 + (c - '0');
  }
  if (v < 1 || v > gas.count) return -1;
  return v - 1;
}

}  // namespace
}  // namespace detail

using detail::format_value;
using detail::format_derived;
using detail::format_vec;
using detail::quote_text;

// -- SourceMap, SceneError, nearest -----------------------------------------------

int SourceMap::line_of(const std::string& key) const {
  std::string k = key;
  for (;;) {
    if (const auto it = lines.find(k); it != lines.end() && it->second > 0) return it->second;
    if (k.empty()) return 0;
    // Parent: drop a trailing "[i]" or ".name".
    std::size_t cut = std::string::npos;
    if (k.back() == ']') {
      cut = k.rfind('[');
    } else {
      cut = k.rfind('.');
    }
    if (cut == std::string::npos || cut == 0) return 0;
    k.resize(cut);
  }
}

namespace {

std::string scene_message(const std::string& key, const std::string& what, const SourceMap& source, int line) {
  std::string where;
  if (source.file.empty()) {
    where = "scene: ";
  } else if (line > 0) {
    where = source.file + ":" + std::to_string(line) + ": ";
  } else {
    where = source.file + ": ";
  }
  return where + (key.empty() ? "" : key + ": ") + what;
}

}  // namespace

SceneError::SceneError(const std::string& key, const std::string& what, const SourceMap& source)
    : OptionError(scene_message(key, what, source, source.line_of(key))),
      key_(key),
      message_(what),
      line_(source.line_of(key)) {}

std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
  constexpr std::size_t kMaxCells = 1u << 16;  // long words get no hint rather than a slow one
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  std::string best;
  std::size_t best_d = limit + 1;
  std::vector<std::size_t> prev, cur;
  for (const auto& c : candidates) {
    const std::size_t diff = c.size() > word.size() ? c.size() - word.size() : word.size() - c.size();
    if (diff >= best_d || (word.size() + 1) * (c.size() + 1) > kMaxCells) continue;
    prev.resize(c.size() + 1);
    cur.resize(c.size() + 1);
    for (std::size_t j = 0; j <= c.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      cur[0] = i;
      for (std::size_t j = 1; j <= c.size(); ++j) {
        const std::size_t sub = prev[j - 1] + (word[i - 1] == c[j - 1] ? 0 : 1);
        cur[j] = std::min({sub, prev[j] + 1, cur[j - 1] + 1});
      }
      std::swap(prev, cur);
    }
    if (prev[c.size()] < best_d) {
      best_d = prev[c.size()];
      best = c;
    }
  }
  return best_d <= limit ? best : std::string();
}

// -- declared ------------------------------------------------------------------------

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

// -- validate ---------------------------------------------------------------------------

namespace {

std::string idx(const std::string& prefix, std::size_t i) { return prefix + "[" + std::to_string(i) + "]"; }

/// A body as the checks see it: explicit or a molecule of the gas.
struct BodyRef {
  bool gas = false;
  std::int64_t index = -1;  // into bodies, or the gas molecule index
};

class Validator {
 public:
  explicit Validator(const Scene& s) : s_(s) {}

  void run() {
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

 private:
  const Scene& s_;
  std::unordered_map<std::string, std::size_t> by_name_;
  std::optional<detail::GasLayout> layout_;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(key, what, s_.source);
  }

  void finite(const std::string& key, double v) const {
    if (!std::isfinite(v)) fail(key, "must be finite, got " + format_value(v));
  }
  void finite(const std::string& key, const Vec3& v) const {
    if (!v.allFinite()) fail(key, "must be finite, got " + format_vec(v));
  }
  void positive(const std::string& key, double v, const std::string& why = "") const {
    finite(key, v);
    if (!(v > 0)) fail(key, "must be > 0" + why + ", got " + format_value(v));
  }
  void nonnegative(const std::string& key, double v) const {
    finite(key, v);
    if (!(v >= 0)) fail(key, "must be >= 0, got " + format_value(v));
  }
  void restitution(const std::string& key, double e) const {
    if (!(e >= 0 && e <= 1)) fail(key, "coefficient of restitution must be in [0, 1], got " + format_value(e));
  }
  void nonzero_normal(const std::string& key, const Vec3& n) const {
    finite(key, n);
    const double len = n.norm();
    if (!(len > 0) || !std::isfinite(len))
      fail(key, "must be a non-zero vector of finite length, got " + format_vec(n));
  }

  // -- run and output --

  bool event_driven() const { return s_.run.engine == "event_driven" || s_.run.method == "event_driven"; }

  void check_run() const {
    const RunSpec& r = s_.run;
    auto steppers = stepper_names();
    steppers.emplace_back("event_driven");
    if (std::find(steppers.begin(), steppers.end(), r.method) == steppers.end())
      fail("run.method", "unknown stepper " + quote_text(r.method) + detail::unknown_hint(r.method, steppers));
    const std::vector<std::string> engines{"auto", "ode", "event_driven"};
    if (std::find(engines.begin(), engines.end(), r.engine) == engines.end())
      fail("run.engine", "unknown engine " + quote_text(r.engine) + detail::unknown_hint(r.engine, engines));
    if (r.method == "event_driven" && r.engine == "ode")
      fail("run.method", "'event_driven' is the event-driven engine, which contradicts engine = \"ode\"");
    finite("run.t0", r.t0);
    finite("run.t_end", r.t_end);
    if (!(r.t_end > r.t0))
      fail("run.t_end", "must be greater than t0 = " + format_value(r.t0) + ", got " + format_value(r.t_end));
    positive("run.dt", r.dt);
    positive("run.rtol", r.rtol);
    if (!(r.rtol < 1)) fail("run.rtol", "must be < 1, got " + format_value(r.rtol));
    positive("run.atol", r.atol);
    nonnegative("run.output_interval", r.output_interval);
    if (r.max_steps == 0) fail("run.max_steps", "must be an integer > 0, got 0");
    if (r.stabilization != Stabilization::none && r.stabilization != Stabilization::baumgarte &&
        r.stabilization != Stabilization::projection)
      fail("run.stabilization", "unknown stabilization " +
                                    std::to_string(static_cast<int>(r.stabilization)) +
                                    "; expected one of: none, baumgarte, projection");
    positive("run.baumgarte_omega", r.baumgarte_omega);
  }

  void check_output() const {
    if (s_.output.directory.empty()) fail("output.directory", "must not be empty");
    if (s_.output.plots && !s_.output.png && !s_.output.svg)
      fail("output.formats", "plots are on but no format is chosen; give png and/or svg, or set plots = false");
  }

  // -- model --

  void check_model() const {
    const ModelSpec& m = *s_.model;
    std::vector<std::string> also;
    if (!s_.bodies.empty()) also.emplace_back("bodies");
    if (s_.gas) also.emplace_back("gas");
    for (const auto& d : s_.declared()) also.push_back(d);
    if (!also.empty())
      fail("model", "a scene is either a built-in [model] or bodies with effects, not both; this one also declares " +
                        detail::join(also));
    if (event_driven())
      fail(s_.run.engine == "event_driven" ? "run.engine" : "run.method",
           "the event-driven engine runs bodies in a box, not a built-in [model]");
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
    const std::size_t n = info->coordinates.size();
    auto check_state = [&](const std::string& key, const std::vector<double>& v) {
      if (v.empty()) return;
      if (v.size() != n)
        fail(key, "expected " + std::to_string(n) + " values (" + detail::join(info->coordinates) + "), got " +
                      std::to_string(v.size()));
      for (std::size_t i = 0; i < v.size(); ++i) finite(idx(key, i), v[i]);
    };
    check_state("model.q", m.q);
    check_state("model.qd", m.qd);
  }

  // -- bodies and gas --

  void check_bodies() {
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
    }
  }

  void check_gas() {
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
    if (g.prefix.empty()) fail("gas.prefix", "must not be empty");
    if (!s_.box) fail("gas", "needs [contacts.box] to hold the gas");
    check_box_fields();
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

  std::optional<BodyRef> find(const std::string& name) const {
    if (const auto it = by_name_.find(name); it != by_name_.end())
      return BodyRef{false, static_cast<std::int64_t>(it->second)};
    if (s_.gas) {
      const std::int64_t k = detail::gas_index(*s_.gas, name);
      if (k >= 0) return BodyRef{true, k};
    }
    return std::nullopt;
  }

  BodyRef require_body(const std::string& key, const std::string& name) const {
    if (name.empty()) fail(key, "missing: name a body");
    if (auto r = find(name)) return *r;
    std::vector<std::string> names;
    names.reserve(s_.bodies.size());
    for (const auto& b : s_.bodies) names.push_back(b.name);
    std::string hint = detail::unknown_hint(name, names);
    if (names.size() > 20 && hint.rfind("; expected", 0) == 0) hint.clear();
    fail(key, "no body named " + quote_text(name) + hint);
  }

  void require_bodies(const std::string& key, const std::vector<std::string>& names) const {
    for (std::size_t i = 0; i < names.size(); ++i) require_body(idx(key, i), names[i]);
  }

  std::string body_name(const BodyRef& r) const {
    return r.gas ? detail::gas_name(*s_.gas, r.index) : s_.bodies[static_cast<std::size_t>(r.index)].name;
  }
  Vec3 position(const BodyRef& r) const {
    return r.gas ? layout_->site(r.index) : s_.bodies[static_cast<std::size_t>(r.index)].position;
  }
  double radius(const BodyRef& r) const {
    return r.gas ? s_.gas->radius : s_.bodies[static_cast<std::size_t>(r.index)].radius;
  }
  std::string position_key(const BodyRef& r) const {
    return r.gas ? std::string("gas") : idx("bodies", static_cast<std::size_t>(r.index)) + ".position";
  }
  std::string velocity_key(const BodyRef& r) const {
    return r.gas ? std::string("gas") : idx("bodies", static_cast<std::size_t>(r.index)) + ".velocity";
  }

  // -- effects, constraints, contacts --

  void check_effects() const {
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

  void check_constraints() const {
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

  void check_box_fields() const {
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

  void check_contacts() const {
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

  void check_engine() const {
    if (!event_driven()) return;
    const std::string key = s_.run.engine == "event_driven" ? "run.engine" : "run.method";
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

  // -- the initial state --

  void check_initial_state() const {
    check_in_box();
    check_overlaps();
    check_planes();
    check_links();
    check_surfaces();
  }

  void check_in_box() const {
    if (!s_.box) return;
    const BoxContact& box = *s_.box;
    static const char* axis = "xyz";
    for (std::size_t i = 0; i < s_.bodies.size(); ++i) {
      const Body& b = s_.bodies[i];
      const double scale = std::max({box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff(), b.radius});
      const double tol = 1e-12 * scale;
      for (int a = 0; a < 3; ++a) {
        const double lo = b.position[a] - b.radius, hi = b.position[a] + b.radius;
        std::string what;
        if (lo < box.min[a] - tol) {
          what = std::string(1, axis[a]) + " - R = " + format_derived(lo) + " < min " + format_value(box.min[a]);
        } else if (hi > box.max[a] + tol) {
          what = std::string(1, axis[a]) + " + R = " + format_derived(hi) + " > max " + format_value(box.max[a]);
        }
        if (!what.empty())
          fail(idx("bodies", i) + ".position", "body " + quote_text(b.name) + " (radius " + format_value(b.radius) +
                                                   ") at " + format_vec(b.position) + " is outside the box " +
                                                   format_vec(box.min) + " to " + format_vec(box.max) + ": " + what);
      }
    }
  }

  void overlap_failure(const BodyRef& a, const BodyRef& b, double d) const {
    const double sum = radius(a) + radius(b);
    fail(position_key(b), "spheres " + quote_text(body_name(a)) + " and " + quote_text(body_name(b)) +
                              " overlap at t0: distance " + format_derived(d) + " < R1 + R2 = " + format_derived(sum));
  }

  static bool overlapping(double d, double sum) { return d < sum * (1.0 - 1e-12); }

  /// Finds a pair of overlapping spheres among `set` in time linear in its
  /// size for usual scenes: spheres are sorted into grids by size class
  /// (radius in [2^k, 2^(k+1)), cells of 2^(k+2)), and each sphere looks only
  /// at the few cells around it in its own class and in every larger one.
  /// Point masses overlap nothing but the inside of spheres.
  void check_pairs(const std::vector<BodyRef>& set) const {
    using Key = std::array<std::int64_t, 3>;
    struct KeyHash {
      std::size_t operator()(const Key& k) const noexcept {
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (const auto v : k) h = (h ^ static_cast<std::uint64_t>(v)) * 0xff51afd7ed558ccdull;
        return static_cast<std::size_t>(h ^ (h >> 29));
      }
    };
    struct Level {
      double cell = 0;
      double rmax = 0;
      std::unordered_map<Key, std::vector<std::size_t>, KeyHash> cells;
    };
    // Cell index along one axis; far cells are lumped (2^50 keeps the
    // arithmetic exact, so a neighbourhood is at most 4 cells wide).
    auto cell_of = [](double x, double cell) {
      return static_cast<std::int64_t>(std::clamp(std::floor(x / cell), -0x1p50, 0x1p50));
    };
    std::vector<Vec3> p(set.size());
    std::vector<double> r(set.size());
    for (std::size_t i = 0; i < set.size(); ++i) {
      p[i] = position(set[i]);
      r[i] = radius(set[i]);
    }
    std::map<int, Level> levels;
    for (std::size_t i = 0; i < set.size(); ++i) {
      if (!(r[i] > 0)) continue;
      const int k = std::ilogb(r[i]);
      Level& L = levels[k];
      L.cell = std::ldexp(1.0, k + 2);
      L.rmax = std::max(L.rmax, r[i]);
      L.cells[{cell_of(p[i].x(), L.cell), cell_of(p[i].y(), L.cell), cell_of(p[i].z(), L.cell)}].push_back(i);
    }
    for (std::size_t i = 0; i < set.size(); ++i) {
      const bool point = !(r[i] > 0);
      const int own = point ? 0 : std::ilogb(r[i]);
      for (auto it = point ? levels.begin() : levels.find(own); it != levels.end(); ++it) {
        const Level& L = it->second;
        const bool same = !point && it->first == own;
        const double reach = r[i] + L.rmax;
        Key lo, hi;
        for (int a = 0; a < 3; ++a) {
          lo[static_cast<std::size_t>(a)] = cell_of(p[i][a] - reach, L.cell);
          hi[static_cast<std::size_t>(a)] = cell_of(p[i][a] + reach, L.cell);
        }
        for (std::int64_t cx = lo[0]; cx <= hi[0]; ++cx)
          for (std::int64_t cy = lo[1]; cy <= hi[1]; ++cy)
            for (std::int64_t cz = lo[2]; cz <= hi[2]; ++cz) {
              const auto found = L.cells.find({cx, cy, cz});
              if (found == L.cells.end()) continue;
              for (const std::size_t j : found->second) {
                if (same && j >= i) continue;                   // each pair once, from its later sphere
                if (set[i].gas && set[j].gas) continue;        // lattice sites never overlap
                const double d = (p[i] - p[j]).norm();
                if (overlapping(d, r[i] + r[j])) overlap_failure(set[std::min(i, j)], set[std::max(i, j)], d);
              }
            }
      }
    }
  }

  void check_overlaps() const {
    if (!s_.sphere_contacts) return;
    // The spheres that collide with each other.
    std::vector<BodyRef> set;
    bool all_gas = false;
    if (s_.sphere_contacts->bodies.empty()) {
      for (std::size_t i = 0; i < s_.bodies.size(); ++i) set.push_back({false, static_cast<std::int64_t>(i)});
      all_gas = s_.gas.has_value();
    } else {
      std::set<std::pair<bool, std::int64_t>> seen;
      for (const auto& name : s_.sphere_contacts->bodies) {
        const auto r = find(name);
        if (r && seen.insert({r->gas, r->index}).second) set.push_back(*r);
      }
    }
    // Pairs among explicit bodies and listed molecules.
    if (set.size() > 1) check_pairs(set);
    // Every molecule collides: compare each explicit body with the nearest
    // lattice site of each block of filled sites.
    if (all_gas) {
      for (std::size_t i = 0; i < s_.bodies.size(); ++i) {
        const Body& b = s_.bodies[i];
        for (const auto& blk : layout_->blocks()) {
          std::array<std::int64_t, 3> near{};
          for (int a = 0; a < 3; ++a) {
            const double t = std::round((b.position[a] - layout_->first[a]) / layout_->spacing);
            const double c = std::clamp(t, static_cast<double>(blk.lo[a]), static_cast<double>(blk.hi[a] - 1));
            near[a] = static_cast<std::int64_t>(c);
          }
          const Vec3 p = layout_->site(near[0], near[1], near[2]);
          const double d = (p - b.position).norm();
          if (overlapping(d, b.radius + s_.gas->radius))
            fail(idx("bodies", i) + ".position",
                 "spheres " + quote_text(b.name) + " and " +
                     quote_text(detail::gas_name(*s_.gas, layout_->index(near[0], near[1], near[2]))) +
                     " (gas) overlap at t0: distance " + format_derived(d) +
                     " < R1 + R2 = " + format_derived(b.radius + s_.gas->radius));
        }
      }
    }
  }

  void check_planes() const {
    for (std::size_t k = 0; k < s_.planes.size(); ++k) {
      const PlaneContact& pl = s_.planes[k];
      const Vec3 n = pl.normal.normalized();
      const std::string label = idx("contacts.planes", k) + (pl.name.empty() ? "" : " (" + quote_text(pl.name) + ")");
      auto check = [&](const std::string& key, const std::string& name, const Vec3& r, double R) {
        const double phi = n.dot(r - pl.point) - R;
        const double tol = 1e-12 * std::max({R, r.cwiseAbs().maxCoeff(), pl.point.cwiseAbs().maxCoeff()});
        if (!(phi >= -tol))
          fail(key, "body " + quote_text(name) + " (radius " + format_value(R) + ") at " + format_vec(r) +
                        " is on the wrong side of " + label + " at t0: n.(r - p) - R = " + format_derived(phi) +
                        " < 0");
      };
      if (pl.bodies.empty()) {
        for (std::size_t i = 0; i < s_.bodies.size(); ++i)
          check(idx("bodies", i) + ".position", s_.bodies[i].name, s_.bodies[i].position, s_.bodies[i].radius);
        if (s_.gas) {
          // A linear function is least at a corner of each block of sites.
          for (const auto& blk : layout_->blocks())
            for (int c = 0; c < 8; ++c) {
              const std::int64_t ix = (c & 1) ? blk.hi[0] - 1 : blk.lo[0];
              const std::int64_t iy = (c & 2) ? blk.hi[1] - 1 : blk.lo[1];
              const std::int64_t iz = (c & 4) ? blk.hi[2] - 1 : blk.lo[2];
              check("gas", detail::gas_name(*s_.gas, layout_->index(ix, iy, iz)), layout_->site(ix, iy, iz),
                    s_.gas->radius);
            }
        }
      } else {
        for (const auto& name : pl.bodies) {
          const auto r = find(name);
          if (r) check(position_key(*r), name, position(*r), radius(*r));
        }
      }
    }
  }

  void check_links() const {
    for (std::size_t i = 0; i < s_.links.size(); ++i) {
      const Link& l = s_.links[i];
      const std::string key = idx("links", i);
      const BodyRef a = *find(l.a);
      const Vec3 pa = position(a);
      Vec3 pb = l.anchor;
      std::string other = "anchor " + format_vec(l.anchor);
      if (!l.b.empty()) {
        const BodyRef b = *find(l.b);
        pb = position(b);
        other = quote_text(l.b);
      }
      const double d = (pa - pb).norm();
      if (std::isnan(l.length)) {
        if (!(d > 0))
          fail(key, "the initial distance between " + quote_text(l.a) + " and " + other +
                        " is 0; give the link a length or separate its ends");
      } else if (!(std::abs(d - l.length) <= 1e-9 * l.length)) {
        fail(key + ".length", "length " + format_value(l.length) + " disagrees with the initial distance " +
                                  format_derived(d) + " between " + quote_text(l.a) + " and " + other +
                                  " (more than 1e-9 relative)");
      }
    }
  }

  void check_surfaces() const {
    for (std::size_t i = 0; i < s_.surfaces.size(); ++i) {
      const Surface& sf = s_.surfaces[i];
      const std::string key = idx("surfaces", i);
      const BodyRef b = *find(sf.body);
      const Vec3 r = position(b);
      // A gas molecule on a surface must be at rest (checked in check_constraints).
      const Vec3 v = b.gas ? Vec3::Zero() : s_.bodies[static_cast<std::size_t>(b.index)].velocity;
      const std::string who = "body " + quote_text(sf.body);
      Vec3 n;
      if (sf.kind == Surface::Kind::plane) {
        n = sf.normal.normalized();
        const double g = n.dot(r - sf.point);
        const double tol = 1e-9 * std::max(r.cwiseAbs().maxCoeff(), sf.point.cwiseAbs().maxCoeff());
        if (!(std::abs(g) <= tol))
          fail(position_key(b), who + " at " + format_vec(r) + " is not on " + key + " (plane through " +
                                    format_vec(sf.point) + " with normal " + format_vec(sf.normal) +
                                    ") at t0: distance " + format_derived(g) + " (tolerance 1e-9 relative)");
      } else {
        const Vec3 rel = r - sf.point;
        const double d = rel.norm();
        if (!(std::abs(d - sf.radius) <= 1e-9 * sf.radius))
          fail(position_key(b), who + " at " + format_vec(r) + " is not on " + key + " (sphere of radius " +
                                    format_value(sf.radius) + " about " + format_vec(sf.point) +
                                    ") at t0: its distance from the centre is " + format_derived(d) +
                                    " (tolerance 1e-9 relative)");
        n = rel / d;
      }
      const double vn = n.dot(v);
      if (!(std::abs(vn) <= 1e-9 * v.norm()))
        fail(velocity_key(b), who + " has velocity " + format_vec(v) + " not tangent to " + key +
                                  " at t0: normal component " + format_derived(vn) + " (tolerance 1e-9 relative)");
    }
  }
};

}  // namespace

void Scene::validate() const { Validator(*this).run(); }

// -- expand_gas ------------------------------------------------------------------------

void Scene::expand_gas() {
  if (!gas) return;
  const GasFill& g = *gas;
  if (g.count < 1 || g.count > detail::kMaxGasCount)
    throw SceneError("gas.count", "must be in [1, " + std::to_string(detail::kMaxGasCount) + "], got " +
                                      std::to_string(g.count), source);
  if (!box) throw SceneError("gas", "needs [contacts.box] to hold the gas", source);
  const auto layout = detail::gas_layout(g, *box);
  if (!layout)
    throw SceneError("gas.count", std::to_string(g.count) + " spheres of radius " + format_value(g.radius) +
                                      " do not fit in the box",
                     source);
  const detail::GasVelocity gv = detail::gas_velocity(g);
  std::mt19937_64 rng(g.seed);
  bodies.reserve(bodies.size() + static_cast<std::size_t>(g.count));
  for (std::int64_t k = 0; k < g.count; ++k) {
    Body b;
    b.name = detail::gas_name(g, k);
    b.mass = g.mass;
    b.radius = g.radius;
    b.position = layout->site(k);
    b.velocity = gv.velocity(detail::random_direction(rng), g.speed);
    bodies.push_back(std::move(b));
  }
  gas.reset();
}

}  // namespace lagrangian::scene
