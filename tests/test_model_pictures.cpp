// The built-in models' pictures (what the animation page draws of a model, view.hpp; the registry's
// picture(), src/scene/registry_*.cpp): every registered model draws at least one body at finite positions,
// and each picture is its model's physics, checked against the model's own definition: the kinetic energy of
// the drawn point masses, with their velocities by central differences of the drawn positions along the
// motion, is the model's T(q, q̇, t); rods have the model's lengths; bodies drawn on a sphere stay on it;
// the drawn masses' height along `up` gives the model's gravitational V up to a constant (the drawing is the
// right way up, at every t); spheres have their radii; contact surfaces are the model's; planar models stay
// in their coordinate plane and `up` points against gravity.
//
// Each model is checked with the catalog's default parameters and with a second, non-default set, at three
// states: the registry's default state, the state 0.3 s into a run from it, and the default configuration
// with made-up rates q̇ (T = Σ ½ m |ṙ|² holds for any q̇, on or off the constraints' velocities).
//
// T check: every model's T is exactly that of its drawn point masses (markers and the fixed centre of the
// Kepler models drawn massless) except knife_edge, whose T adds the blade's rotational energy ½ I φ̇²; its
// drawn body is checked against the translational part T − ½ I φ̇² (T at the same q with ẋ = ẏ = 0
// subtracted). The Atwood machine's pulley is massless in the model, so its T is that of the two masses.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/models/two_body.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/view/view.hpp"

namespace {

using namespace lagrangian;
namespace lm = lagrangian::models;
using scene::ModelSpec;
using scene::detail::ModelEntry;
using view::Figure;
using view::Point;

const double not_fixed = std::nan("");  ///< a rod whose length is not a model constant

// -- the model's side ---------------------------------------------------------------

/// A state of a model: q and q̇ in its coordinates' order, at time t (s).
struct ModelState {
  std::vector<double> q, qd;
  double t = 0;
};

const ModelEntry& entry(const std::string& name) {
  const ModelEntry* e = scene::detail::find_entry(name);
  if (!e) throw std::runtime_error("no registry entry " + name);
  return *e;
}

/// A parameter of `spec`'s model: the override in spec.parameters, else the catalog's default.
double param(const ModelSpec& spec, const std::string& name) {
  if (const auto it = spec.parameters.find(name); it != spec.parameters.end()) return it->second;
  const scene::ModelInfo* info = scene::find_model(spec.name);
  if (!info) throw std::runtime_error("no catalog entry " + spec.name);
  for (const auto& p : info->parameters)
    if (p.name == name) return p.default_value;
  throw std::runtime_error(spec.name + " has no catalog parameter " + name);
}

/// The model's own T(q, q̇, t) (J), from a copy of the model.
using Kinetic = std::function<double(const ModelState&)>;
using Potential = Kinetic;
template <class M>
Kinetic kinetic_of(const M& model) {
  return [model](const ModelState& s) {
    constexpr int n = M::coordinate_count;
    Vec<double, n> q, qd;
    for (int i = 0; i < n; ++i) {
      q[i] = s.q[static_cast<std::size_t>(i)];
      qd[i] = s.qd[static_cast<std::size_t>(i)];
    }
    return model.kinetic(q, qd, s.t);
  };
}

/// The model's own V(q, t) (J), from a copy of the model.
template <class M>
Potential potential_of(const M& model) {
  return [model](const ModelState& s) {
    constexpr int n = M::coordinate_count;
    Vec<double, n> q;
    for (int i = 0; i < n; ++i) q[i] = s.q[static_cast<std::size_t>(i)];
    return model.potential(q, s.t);
  };
}

/// Thrown by the progress tick to end a run at its second sample.
struct FirstSampleTaken {};

SimulationOptions run_options(double t_end) {
  SimulationOptions o;
  o.t_end = t_end;
  o.output_interval = 0.05;
  return o;
}

/// The registry's default state of `spec` at t0 = 0: the first sample of a run (the state it starts from),
/// kept by stopping the run when its second sample arrives (the tick comes before the sample is kept).
ModelState default_state(const ModelSpec& spec) {
  scene::detail::FinalState s;
  int samples = 0;
  const scene::detail::SampleTick stop_at_second = [&](const scene::SampleRow&) {
    if (++samples == 2) throw FirstSampleTaken{};
  };
  try {
    entry(spec.name).run(spec, run_options(1.0), "", stop_at_second, &s);
  } catch (const FirstSampleTaken&) {
  }
  return {s.q, s.qd, s.t};
}

/// The state 0.3 s into a run from the default state: on the constraints, moving, at t ≠ 0.
ModelState later_state(const ModelSpec& spec) {
  scene::detail::FinalState s;
  entry(spec.name).run(spec, run_options(0.3), "", {}, &s);
  return {s.q, s.qd, s.t};
}

/// The default configuration with made-up rates q̇_i = 0.4 + 0.3 i at t = 0.7 s.
ModelState made_up_rates(const ModelState& start) {
  ModelState s = start;
  for (std::size_t i = 0; i < s.qd.size(); ++i) s.qd[i] = 0.4 + 0.3 * static_cast<double>(i);
  s.t = 0.7;
  return s;
}

// -- the picture's side -------------------------------------------------------------

/// A model's figure and its bodies' centres at some states.
struct Picture {
  Figure figure;
  std::vector<double> xyz;  ///< rows × bodies × 3 (m)
  Point at(std::size_t row, std::size_t body) const {
    const std::size_t k = (row * figure.bodies.size() + body) * 3;
    return {xyz[k], xyz[k + 1], xyz[k + 2]};
  }
};

Picture picture(const ModelSpec& spec, const std::vector<ModelState>& states) {
  std::vector<double> t, q;
  for (const ModelState& s : states) {
    t.push_back(s.t);
    q.insert(q.end(), s.q.begin(), s.q.end());
  }
  Picture p;
  p.figure = entry(spec.name).picture(spec, t.data(), q.data(), states.size(), p.xyz);
  return p;
}

double distance(const Point& a, const Point& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

/// The length of rod or spring `s` with the bodies at `row`.
double length(const Picture& p, std::size_t row, const Figure::Segment& s) {
  const Point a = p.at(row, static_cast<std::size_t>(s.a));
  return distance(a, s.b >= 0 ? p.at(row, static_cast<std::size_t>(s.b)) : s.anchor);
}

/// Σ ½ mᵢ |ṙᵢ|² of the drawn bodies at `s`, ṙᵢ by central differences along the motion: the positions at
/// (q ∓ h q̇, t ∓ h).
double drawn_kinetic(const ModelSpec& spec, const std::vector<double>& masses, const ModelState& s) {
  constexpr double h = 1e-5;
  ModelState before = s, after = s;
  for (std::size_t i = 0; i < s.q.size(); ++i) {
    before.q[i] -= h * s.qd[i];
    after.q[i] += h * s.qd[i];
  }
  before.t -= h;
  after.t += h;
  const Picture p = picture(spec, {before, after});
  double T = 0;
  for (std::size_t b = 0; b < p.figure.bodies.size(); ++b) {
    const double v = distance(p.at(1, b), p.at(0, b)) / (2 * h);
    T += 0.5 * masses.at(b) * v * v;
  }
  return T;
}

// -- what each picture must show, from the model's definition -----------------------

struct Expected {
  Kinetic kinetic;                ///< the model's T (J); for knife_edge its translational part
  Potential gravity;              ///< the model's V less its springs' energy (J), when g > 0
  double g = 0;                   ///< gravity (m/s²) along −up; 0: the model has none to check
  std::vector<double> masses;     ///< kg per drawn body (0: a marker or a fixed body)
  std::vector<double> radii;      ///< m per drawn body
  std::vector<double> rods;       ///< m per rod, in the figure's order; not_fixed: unchecked
  std::size_t springs = 0;        ///< number of springs drawn
  int plane = -1;                 ///< the axis every drawn point keeps at 0 (planar models); −1: spatial
  Point up{0, 0, 1};              ///< against gravity (or the normal of the plane of motion)
  std::vector<std::pair<std::size_t, std::size_t>> on_sphere;  ///< (body, sphere) pairs
};

/// The model's T and V, and gravity g (m/s²; 0 for none) along −up.
template <class M>
void from_model(Expected& e, const M& model, double g) {
  e.kinetic = kinetic_of(model);
  e.gravity = potential_of(model);
  e.g = g;
}

/// What the picture of `spec` must show. Planes: x = 0, y = 1, z = 2.
Expected expected(const ModelSpec& spec) {
  const std::string& name = spec.name;
  const auto p = [&](const char* key) { return param(spec, key); };
  Expected e;
  if (name == "simple_pendulum") {
    from_model(e, lm::SimplePendulum(p("m"), p("l"), p("g")), p("g"));
    e.masses = {p("m")};
    e.radii = {0};
    e.rods = {p("l")};
    e.plane = 2;
    e.up = {0, 1, 0};
  } else if (name == "harmonic_oscillator") {
    from_model(e, lm::HarmonicOscillator(p("m"), p("k")), 0);
    e.masses = {p("m")};
    e.radii = {0};
    e.springs = 1;
    e.plane = 1;  // on the x axis: z = 0 as well
  } else if (name == "double_pendulum") {
    from_model(e, lm::DoublePendulum(p("m1"), p("m2"), p("l1"), p("l2"), p("g")), p("g"));
    e.masses = {p("m1"), p("m2")};
    e.radii = {0, 0};
    e.rods = {p("l1"), p("l2")};
    e.plane = 2;
    e.up = {0, 1, 0};
  } else if (name == "spherical_pendulum") {
    from_model(e, lm::SphericalPendulum(p("m"), p("l"), p("g")), p("g"));
    e.masses = {p("m")};
    e.radii = {0};
    e.rods = {p("l")};
  } else if (name == "elastic_pendulum") {
    from_model(e, lm::ElasticPendulum(p("m"), p("k"), p("l0"), p("g")), p("g"));
    e.gravity = [V = e.gravity, k = p("k"), l0 = p("l0")](const ModelState& s) {
      return V(s) - 0.5 * k * (s.q[0] - l0) * (s.q[0] - l0);  // less the spring's ½ k (r − l0)²
    };
    e.masses = {p("m")};
    e.radii = {0};
    e.springs = 1;
    e.plane = 2;
    e.up = {0, 1, 0};
  } else if (name == "bead_on_rotating_hoop") {
    // The bead, and a massless marker on the rim joined to the axis' bearings at (0, 0, ±R).
    from_model(e, lm::BeadOnRotatingHoop(p("m"), p("R"), p("omega"), p("g")), p("g"));
    e.masses = {p("m"), 0};
    e.rods = {p("R"), std::sqrt(2.0) * p("R"), std::sqrt(2.0) * p("R")};
    e.on_sphere = {{0, 0}, {1, 0}};
  } else if (name == "kepler_polar") {
    from_model(e, lm::KeplerPolar(p("m"), p("k")), 0);
    e.masses = {0, p("m")};  // the fixed centre of force, the particle
    e.radii = {0, 0};
    e.plane = 2;
  } else if (name == "cart_pendulum") {
    from_model(e, lm::CartPendulum(p("M"), p("m"), p("l"), p("k"), p("g")), p("g"));
    e.gravity = [V = e.gravity, k = p("k")](const ModelState& s) { return V(s) - 0.5 * k * s.q[0] * s.q[0]; };
    e.masses = {p("M"), p("m")};
    e.radii = {0, 0};
    e.rods = {p("l")};
    e.springs = p("k") > 0 ? 1 : 0;
    e.plane = 2;
    e.up = {0, 1, 0};
  } else if (name == "driven_pendulum") {
    from_model(e, lm::DrivenPendulum(p("m"), p("l"), p("a"), p("Omega"), p("g")), p("g"));
    e.masses = {p("m"), 0};  // the bob, the driven support
    e.rods = {p("l")};
    e.plane = 2;
    e.up = {0, 1, 0};
  } else if (name == "pendulum_chain_3") {
    from_model(e, lm::PendulumChain<3>(p("m"), p("l"), p("g")), p("g"));
    e.masses = {p("m"), p("m"), p("m")};
    e.radii = {0, 0, 0};
    e.rods = {p("l"), p("l"), p("l")};
    e.plane = 2;
    e.up = {0, 1, 0};
  } else if (name == "bead_on_rotating_wire") {
    // The bead, and two massless markers at the wire's ends joined by the wire, 2L long through the axis.
    from_model(e, lm::BeadOnRotatingWire(p("m"), p("omega"), p("L")), 0);
    e.masses = {p("m"), 0, 0};
    e.radii = {0, 0.01 * p("L"), 0.01 * p("L")};
    e.rods = {2 * p("L")};
    e.plane = 2;
  } else if (name == "particle_on_sphere") {
    from_model(e, lm::ParticleOnSphere(p("m"), p("R"), p("g")), p("g"));
    e.masses = {p("m")};
    e.radii = {0};
    e.on_sphere = {{0, 0}};
  } else if (name == "atwood_machine") {
    from_model(e, lm::AtwoodMachine(p("m1"), p("m2"), p("g"), p("c"), p("d")), p("g"));
    e.masses = {p("m1"), p("m2")};
    e.radii = {0, 0};
    e.rods = {not_fixed, not_fixed};  // the two runs of the string: AtwoodString checks them
    e.plane = 2;
    e.up = {0, 1, 0};
  } else if (name == "cartesian_double_pendulum") {
    from_model(e, lm::CartesianDoublePendulum(p("m1"), p("m2"), p("l1"), p("l2"), p("g")), p("g"));
    e.masses = {p("m1"), p("m2")};
    e.radii = {0, 0};
    e.rods = {p("l1"), p("l2")};
    e.plane = 2;
    e.up = {0, 1, 0};
  } else if (name == "knife_edge") {
    // T − ½ I φ̇²: the model's T less its value with the contact point at rest (the rotation alone).
    const Kinetic T = kinetic_of(lm::KnifeEdge(p("m"), p("I")));
    e.kinetic = [T](const ModelState& s) {
      ModelState turning = s;
      turning.qd[0] = turning.qd[1] = 0;
      return T(s) - T(turning);
    };
    e.masses = {p("m"), 0};  // the contact point, the blade's marker
    e.rods = {0.5};          // the blade drawn (the model has no length)
    e.plane = 2;
  } else if (name == "direct_impact") {
    from_model(e, lm::SpheresOnLine<2>({p("m1"), p("m2")}, {p("r1"), p("r2")}, p("e")), 0);
    e.masses = {p("m1"), p("m2")};
    e.radii = {p("r1"), p("r2")};
    e.plane = 1;
  } else if (name == "newtons_cradle") {
    const double m = p("m"), r = p("r");
    from_model(e, lm::SpheresOnLine<5>({m, m, m, m, m}, {r, r, r, r, r}, p("e")), 0);
    e.masses = {m, m, m, m, m};
    e.radii = {r, r, r, r, r};
    e.plane = 1;
  } else if (name == "oblique_impact") {
    from_model(e, lm::TwoSpheres<2>(p("m1"), p("m2"), p("r1"), p("r2"), p("e")), 0);
    e.masses = {p("m1"), p("m2")};
    e.radii = {p("r1"), p("r2")};
    e.plane = 2;
  } else if (name == "ball_and_plane") {
    from_model(e, lm::BallAndPlane(p("m"), p("R"), p("e"), p("g"), {p("nx"), p("ny"), p("nz")}, p("offset")), p("g"));
    e.masses = {p("m")};
    e.radii = {p("R")};
  } else if (name == "spheres_in_box") {
    const double m = p("m"), r = p("r");
    from_model(e, lm::SpheresInBox<3>({m, m, m}, {r, r, r}, p("W"), p("H"), p("e_wall"), p("e_pair"), p("g")), p("g"));
    e.masses = {m, m, m};
    e.radii = {r, r, r};
    e.plane = 2;
    e.up = {0, 1, 0};
  } else if (name == "two_body") {
    from_model(e, lm::TwoBody<2>(p("m1"), p("m2"), lm::NewtonianGravity{p("k")}), 0);
    e.masses = {p("m1"), p("m2")};
    e.radii = {0, 0};
    e.plane = 2;
  } else if (name == "kepler") {
    from_model(e, lm::RelativeMotion<2>(p("mu"), lm::NewtonianGravity{p("k")}), 0);
    e.masses = {0, p("mu")};  // body 1 fixed at the origin, the body of reduced mass at r = r2 − r1
    e.radii = {0, 0};
    e.plane = 2;
  } else if (name == "projectile") {
    from_model(e, lm::Projectile<lm::Drag::none>(p("m"), p("g"), p("beta"), 0.0), p("g"));
  } else if (name == "projectile_linear_drag") {
    from_model(e, lm::Projectile<lm::Drag::linear>(p("m"), p("g"), p("beta"), p("b")), p("g"));
  } else if (name == "projectile_quadratic_drag") {
    from_model(e, lm::Projectile<lm::Drag::quadratic>(p("m"), p("g"), p("beta"), p("c")), p("g"));
  } else {
    throw std::runtime_error("no expected picture for model " + name + ": add it to expected()");
  }
  if (name.starts_with("projectile")) {
    e.masses = {p("m")};
    e.radii = {0};
    e.plane = 2;
    e.up = {0, 1, 0};
  }
  return e;
}

/// Non-default parameters for each model: lengths, masses and rates that differ from the catalog's, so that
/// a picture drawn from constants instead of the model's parameters shows.
std::map<std::string, double> other_parameters(const std::string& name) {
  static const std::map<std::string, std::map<std::string, double>> table{
      {"simple_pendulum", {{"m", 2.5}, {"l", 1.7}}},
      {"harmonic_oscillator", {{"m", 2.0}, {"k", 5.0}}},
      {"double_pendulum", {{"m1", 2.0}, {"l1", 0.6}, {"l2", 1.4}}},
      {"spherical_pendulum", {{"m", 1.5}, {"l", 0.8}}},
      {"elastic_pendulum", {{"k", 25.0}, {"l0", 0.7}}},
      {"bead_on_rotating_hoop", {{"m", 0.5}, {"R", 0.8}, {"omega", 4.0}}},
      {"kepler_polar", {{"m", 2.0}, {"k", 3.0}}},
      {"cart_pendulum", {{"M", 3.0}, {"l", 0.6}, {"k", 0.0}}},
      {"driven_pendulum", {{"l", 0.7}, {"a", 0.1}, {"Omega", 20.0}}},
      {"pendulum_chain_3", {{"m", 2.0}, {"l", 0.5}}},
      {"bead_on_rotating_wire", {{"m", 2.0}, {"omega", 3.0}, {"L", 4.0}}},
      {"particle_on_sphere", {{"m", 0.5}, {"R", 2.0}}},
      {"atwood_machine", {{"m1", 2.0}, {"m2", 5.0}, {"c", 1.0}, {"d", 2.5}}},
      {"cartesian_double_pendulum", {{"m2", 2.0}, {"l1", 0.6}, {"l2", 1.3}}},
      {"knife_edge", {{"m", 2.0}, {"I", 0.3}}},
      {"direct_impact", {{"m1", 3.0}, {"r1", 0.05}, {"r2", 0.2}}},
      {"newtons_cradle", {{"m", 0.2}, {"r", 0.02}}},
      {"oblique_impact", {{"m2", 2.0}, {"r1", 0.05}, {"r2", 0.15}}},
      {"ball_and_plane", {{"R", 0.2}, {"nx", 0.3}, {"nz", 1.0}, {"offset", 0.2}}},
      {"spheres_in_box", {{"r", 0.2}, {"W", 3.0}, {"H", 1.5}, {"g", 9.81}}},
      {"two_body", {{"m1", 3.0}, {"m2", 1.0}, {"k", 2.0}}},
      {"kepler", {{"mu", 0.5}, {"k", 2.0}}},
      {"projectile", {{"m", 2.0}, {"beta", 0.2}}},
      {"projectile_linear_drag", {{"m", 2.0}, {"beta", -0.2}}},
      {"projectile_quadratic_drag", {{"m", 2.0}, {"beta", 0.2}}},
  };
  const auto it = table.find(name);
  return it != table.end() ? it->second : std::map<std::string, double>{};
}

/// Every registered model, with the catalog's parameters and with other_parameters().
std::vector<ModelSpec> all_specs() {
  std::vector<ModelSpec> out;
  for (const ModelEntry& e : scene::detail::model_entries()) {
    ModelSpec spec;
    spec.name = e.name;
    out.push_back(spec);
    spec.parameters = other_parameters(e.name);
    if (!spec.parameters.empty()) out.push_back(spec);
  }
  return out;
}

std::string label(const ModelSpec& spec) {
  std::string s = spec.name;
  for (const auto& [key, value] : spec.parameters) s += " " + key + "=" + std::to_string(value);
  return s;
}

/// The three states each picture is checked at.
std::vector<ModelState> states_of(const ModelSpec& spec) {
  const ModelState start = default_state(spec);
  return {start, later_state(spec), made_up_rates(start)};
}

// -- tests ---------------------------------------------------------------------------

TEST(ModelPictures, EveryModelDrawsItsBodiesAtFinitePositions) {
  ASSERT_EQ(scene::detail::model_entries().size(), scene::builtin_models().size());
  for (const ModelSpec& spec : all_specs()) {
    SCOPED_TRACE(label(spec));
    ASSERT_NO_THROW((void)expected(spec)) << "every registered model has its expected picture in this test";
    const std::vector<ModelState> states = states_of(spec);
    ASSERT_EQ(states[0].q.size(), scene::find_model(spec.name)->coordinates.size());
    const Picture p = picture(spec, states);
    const Figure& f = p.figure;
    const std::size_t nb = f.bodies.size();
    ASSERT_GE(nb, 1u);
    ASSERT_EQ(p.xyz.size(), states.size() * nb * 3);
    for (double v : p.xyz) EXPECT_TRUE(std::isfinite(v));
    std::set<std::string> names;
    for (const Figure::Body& b : f.bodies) {
      EXPECT_FALSE(b.name.empty());
      EXPECT_TRUE(names.insert(b.name).second) << "body names are unique: " << b.name;
      EXPECT_TRUE(std::isfinite(b.radius) && b.radius >= 0) << b.name;
    }
    for (const auto* list : {&f.rods, &f.springs})
      for (const Figure::Segment& s : *list) {
        EXPECT_TRUE(s.a >= 0 && static_cast<std::size_t>(s.a) < nb);
        EXPECT_TRUE(s.b >= -1 && s.b < static_cast<int>(nb) && s.b != s.a);
      }
    EXPECT_NEAR(std::hypot(f.up[0], f.up[1], f.up[2]), 1.0, 1e-15);
    // The figure alone (no states, as the page asks for it first) is the same figure.
    std::vector<double> none;
    const Figure alone = entry(spec.name).picture(spec, nullptr, nullptr, 0, none);
    EXPECT_TRUE(none.empty());
    ASSERT_EQ(alone.bodies.size(), nb);
    for (std::size_t b = 0; b < nb; ++b) EXPECT_EQ(alone.bodies[b].name, f.bodies[b].name);
  }
}

TEST(ModelPictures, KineticEnergyOfTheDrawnBodiesIsTheModels) {
  for (const ModelSpec& spec : all_specs()) {
    SCOPED_TRACE(label(spec));
    const Expected e = expected(spec);
    const std::vector<ModelState> states = states_of(spec);
    ASSERT_EQ(picture(spec, states).figure.bodies.size(), e.masses.size());
    for (std::size_t k = 0; k < states.size(); ++k) {
      SCOPED_TRACE("state " + std::to_string(k) + " at t = " + std::to_string(states[k].t));
      const double T = e.kinetic(states[k]);
      const double drawn = drawn_kinetic(spec, e.masses, states[k]);
      EXPECT_NEAR(drawn, T, 1e-6 * std::max(std::abs(T), 1e-9));
      if (k > 0) {
        EXPECT_GT(T, 0) << "the state moves";
      }
    }
  }
}

TEST(ModelPictures, GravitationalEnergyOfTheDrawnBodiesIsTheModels) {
  // V_gravity(q, t) = Σ mᵢ g up·rᵢ + constant: the drawing is the right way up, at every t.
  for (const ModelSpec& spec : all_specs()) {
    const Expected e = expected(spec);
    if (e.g == 0) continue;
    SCOPED_TRACE(label(spec));
    std::vector<ModelState> states = states_of(spec);
    ModelState other = states[1];  // elsewhere, later
    for (double& q : other.q) q += 0.3;
    other.t = 1.1;
    states.push_back(other);
    const Picture p = picture(spec, states);
    const Point& up = p.figure.up;
    double constant = 0;
    for (std::size_t row = 0; row < states.size(); ++row) {
      double drawn = 0;
      for (std::size_t b = 0; b < e.masses.size(); ++b) {
        const Point r = p.at(row, b);
        drawn += e.masses[b] * e.g * (up[0] * r[0] + up[1] * r[1] + up[2] * r[2]);
      }
      const double V = e.gravity(states[row]);
      if (row == 0) constant = V - drawn;
      EXPECT_NEAR(V - drawn, constant, 1e-9 * std::max(1.0, std::abs(V))) << "state " << row;
    }
  }
}

TEST(ModelPictures, RodsHaveTheModelsLengthsAndBodiesStayOnTheirSpheres) {
  for (const ModelSpec& spec : all_specs()) {
    SCOPED_TRACE(label(spec));
    const Expected e = expected(spec);
    const std::vector<ModelState> states = states_of(spec);
    const Picture p = picture(spec, states);
    const Figure& f = p.figure;
    ASSERT_EQ(f.rods.size(), e.rods.size());
    EXPECT_EQ(f.springs.size(), e.springs);
    for (std::size_t row = 0; row < states.size(); ++row) {
      for (std::size_t r = 0; r < f.rods.size(); ++r)
        if (!std::isnan(e.rods[r])) {
          EXPECT_NEAR(length(p, row, f.rods[r]), e.rods[r], 1e-9) << "rod " << r;
        }
      for (const auto& [body, sphere] : e.on_sphere) {
        ASSERT_LT(sphere, f.spheres.size());
        const Figure::Sphere& s = f.spheres[sphere];
        EXPECT_NEAR(distance(p.at(row, body), s.centre), s.radius, 1e-9 * s.radius) << f.bodies[body].name;
      }
    }
  }
  // The spheres drawn are the models': the hoop's and the particle's sphere have radius R.
  for (const char* name : {"bead_on_rotating_hoop", "particle_on_sphere"}) {
    ModelSpec spec;
    spec.name = name;
    spec.parameters = other_parameters(name);
    const Figure f = picture(spec, {default_state(spec)}).figure;
    ASSERT_EQ(f.spheres.size(), 1u) << name;
    EXPECT_EQ(f.spheres[0].radius, param(spec, "R")) << name;
    EXPECT_EQ(f.spheres[0].centre, (Point{0, 0, 0})) << name;
  }
}

TEST(ModelPictures, SpheresHaveTheirRadiiAndUpIsAgainstGravity) {
  for (const ModelSpec& spec : all_specs()) {
    SCOPED_TRACE(label(spec));
    const Expected e = expected(spec);
    const Figure f = picture(spec, {default_state(spec)}).figure;
    EXPECT_EQ(f.up, e.up);
    ASSERT_EQ(f.bodies.size(), e.masses.size());
    for (std::size_t b = 0; b < e.radii.size(); ++b) EXPECT_EQ(f.bodies[b].radius, e.radii[b]) << f.bodies[b].name;
  }
}

TEST(ModelPictures, PlanarModelsStayInTheirCoordinatePlane) {
  for (const ModelSpec& spec : all_specs()) {
    SCOPED_TRACE(label(spec));
    const Expected e = expected(spec);
    if (e.plane < 0) continue;
    const auto axis = static_cast<std::size_t>(e.plane);
    const std::vector<ModelState> states = states_of(spec);
    const Picture p = picture(spec, states);
    const Figure& f = p.figure;
    for (std::size_t row = 0; row < states.size(); ++row)
      for (std::size_t b = 0; b < f.bodies.size(); ++b) EXPECT_EQ(p.at(row, b)[axis], 0.0) << f.bodies[b].name;
    for (const Point& pivot : f.pivots) EXPECT_EQ(pivot[axis], 0.0);
    for (const auto* list : {&f.rods, &f.springs})
      for (const Figure::Segment& s : *list)
        if (s.b < 0) {
          EXPECT_EQ(s.anchor[axis], 0.0);
        }
    for (const Figure::Box& box : f.boxes) EXPECT_EQ(box.max[axis] - box.min[axis], 0.0);
    for (const Figure::Circle& c : f.circles) EXPECT_EQ(c.centre[axis], 0.0);
    EXPECT_TRUE(f.spheres.empty());
  }
}

TEST(ModelPictures, ContactSurfacesAreTheModels) {
  // The ball's plane n·r = d, with n normalised as the model does.
  {
    ModelSpec spec;
    spec.name = "ball_and_plane";
    spec.parameters = other_parameters(spec.name);
    const Figure f = picture(spec, {default_state(spec)}).figure;
    ASSERT_EQ(f.planes.size(), 1u);
    const double nx = param(spec, "nx"), ny = param(spec, "ny"), nz = param(spec, "nz");
    const double len = std::hypot(nx, ny, nz);
    const Point n{nx / len, ny / len, nz / len};
    const Figure::Plane& plane = f.planes[0];
    const double drawn_len = std::hypot(plane.normal[0], plane.normal[1], plane.normal[2]);
    for (std::size_t a = 0; a < 3; ++a) EXPECT_NEAR(plane.normal[a] / drawn_len, n[a], 1e-15);
    EXPECT_NEAR(n[0] * plane.point[0] + n[1] * plane.point[1] + n[2] * plane.point[2], param(spec, "offset"), 1e-15);
  }
  // The discs' box [0, W] × [0, H].
  {
    ModelSpec spec;
    spec.name = "spheres_in_box";
    spec.parameters = other_parameters(spec.name);
    const Figure f = picture(spec, {default_state(spec)}).figure;
    ASSERT_EQ(f.boxes.size(), 1u);
    EXPECT_EQ(f.boxes[0].min, (Point{0, 0, 0}));
    EXPECT_EQ(f.boxes[0].max, (Point{param(spec, "W"), param(spec, "H"), 0}));
  }
  // The projectiles' ground: the plane through the launch point at angle beta to the horizontal.
  for (const char* name : {"projectile", "projectile_linear_drag", "projectile_quadratic_drag"}) {
    SCOPED_TRACE(name);
    ModelSpec spec;
    spec.name = name;
    spec.parameters = other_parameters(name);
    const Figure f = picture(spec, {default_state(spec)}).figure;
    ASSERT_EQ(f.planes.size(), 1u);
    const Figure::Plane& ground = f.planes[0];
    const double beta = param(spec, "beta");
    const Point along{std::cos(beta), std::sin(beta), 0};
    EXPECT_NEAR(ground.normal[0] * along[0] + ground.normal[1] * along[1] + ground.normal[2] * along[2], 0, 1e-15);
    EXPECT_GT(ground.normal[1], 0);  // the projectile flies on the upper side
    EXPECT_EQ(ground.normal[2], 0.0);
    EXPECT_NEAR(ground.normal[0] * ground.point[0] + ground.normal[1] * ground.point[1], 0, 1e-15);
  }
}

TEST(ModelPictures, AtwoodStringRunsFromThePulleysRimAndKeepsItsLength) {
  for (const ModelSpec& spec : all_specs()) {
    if (spec.name != "atwood_machine") continue;
    SCOPED_TRACE(label(spec));
    std::vector<ModelState> states = states_of(spec);
    ModelState moved = states[1];  // farther along: the string is the same length
    moved.q[0] -= 0.4;
    moved.q[1] += 0.4;
    states.push_back(moved);
    const Picture p = picture(spec, states);
    const Figure& f = p.figure;
    ASSERT_EQ(f.circles.size(), 1u);
    ASSERT_EQ(f.rods.size(), 2u);
    const Figure::Circle& pulley = f.circles[0];
    double total = std::nan("");
    for (std::size_t row = 0; row < states.size(); ++row) {
      double sum = 0;
      for (std::size_t r = 0; r < 2; ++r) {
        const Figure::Segment& s = f.rods[r];
        ASSERT_LT(s.b, 0);
        EXPECT_NEAR(distance(s.anchor, pulley.centre), pulley.radius, 1e-15);  // leaves the rim…
        EXPECT_EQ(p.at(row, static_cast<std::size_t>(s.a))[0], s.anchor[0]);  // …straight down
        EXPECT_GT(s.anchor[1], p.at(row, static_cast<std::size_t>(s.a))[1]);   // to a mass below the pulley
        sum += length(p, row, s);
      }
      if (row == 0) total = sum;
      EXPECT_NEAR(sum, total, 1e-12);
      EXPECT_NEAR(states[row].q[0] + states[row].q[1], param(spec, "c"), 1e-9);
    }
  }
}

TEST(ModelPictures, MovingSupportsFollowTime) {
  // The driven pendulum's support at (0, a cos Ωt, 0); the hoop's marker at azimuth ωt.
  ModelSpec driven;
  driven.name = "driven_pendulum";
  const double a = param(driven, "a"), Omega = param(driven, "Omega");
  ModelSpec hoop;
  hoop.name = "bead_on_rotating_hoop";
  const double R = param(hoop, "R"), omega = param(hoop, "omega");
  for (double t : {0.0, 0.05, 0.4, 1.3}) {
    const Picture d = picture(driven, {{{0.2}, {0.0}, t}});
    EXPECT_NEAR(d.at(0, 1)[1], a * std::cos(Omega * t), 1e-15);
    EXPECT_NEAR(distance(d.at(0, 0), d.at(0, 1)), param(driven, "l"), 1e-12);
    const Picture h = picture(hoop, {{{0.7}, {0.0}, t}});
    const Point bead = h.at(0, 0), rim = h.at(0, 1);
    EXPECT_NEAR(rim[0], R * std::cos(omega * t), 1e-15);
    EXPECT_NEAR(rim[1], R * std::sin(omega * t), 1e-15);
    EXPECT_NEAR(bead[2], -R * std::cos(0.7), 1e-15);  // θ from the bottom
    // The bead is in the hoop's plane, on the marker's side of the axis.
    EXPECT_NEAR(bead[0] * rim[1] - bead[1] * rim[0], 0, 1e-15);
    EXPECT_GT(bead[0] * rim[0] + bead[1] * rim[1], 0);
  }
}

}  // namespace
