// Built-in models of constrained.hpp: holonomic (fixed and moving) and
// Pfaffian constraints in redundant coordinates. The default states below
// are the registry's and satisfy the constraints at t0 for any parameters.
//
// Pictures (view.hpp), lengths in m: the models in Cartesian coordinates are drawn at those coordinates (the
// planar ones on z = 0), the vertical being the model's own: −y for the Atwood machine and the double pendulum,
// −z for the particle on a sphere; the rotating wire and the knife edge lie in the horizontal plane z = 0.

#include <cmath>
#include <string_view>
#include <vector>

#include "lagrangian/models/constrained.hpp"
#include "registry_entry.hpp"

namespace lagrangian::scene::detail {
namespace {

namespace lm = lagrangian::models;

struct BeadOnRotatingWireDef {
  using Model = lm::BeadOnRotatingWire;
  static constexpr std::string_view type = "models::BeadOnRotatingWire";
  /// 1 m out along the wire at t0, turning with it (no radial speed).
  static State<2> initial(const Model& m, double t0) {
    const double c = std::cos(m.omega * t0), s = std::sin(m.omega * t0);
    State<2> x;
    x.q << c, s;
    x.qd << -m.omega * s, m.omega * c;
    return x;
  }
  /// The bead in the horizontal plane z = 0 (z up) and the whole wire, from one end to the other through the
  /// vertical axis (a pivot at the origin): two small markers at its ends, joined by a rod, turn with it.
  static view::Figure figure(const Model& m) {
    view::Figure f;
    f.bodies = {{.name = "bead"},
                {.name = "wire end 1", .radius = 0.01 * m.L},
                {.name = "wire end 2", .radius = 0.01 * m.L}};
    f.rods = {{.a = 1, .b = 2}};
    f.pivots = {{0, 0, 0}};
    f.up = {0, 0, 1};
    return f;
  }
  /// The bead at (x, y, 0) and the wire's ends at ±L (cos ωt, sin ωt, 0) (m).
  static void place(const Model& m, const double* q, double t, view::Point* c) {
    const double ca = std::cos(m.omega * t), sa = std::sin(m.omega * t);
    c[0] = {q[0], q[1], 0};
    c[1] = {m.L * ca, m.L * sa, 0};
    c[2] = {-m.L * ca, -m.L * sa, 0};
  }
};

struct ParticleOnSphereDef {
  using Model = lm::ParticleOnSphere;
  static constexpr std::string_view type = "models::ParticleOnSphere";
  /// 1 rad from the bottom, moving horizontally at 2 m/s along +y.
  static State<3> initial(const Model& m, double) {
    State<3> x;
    x.q << m.R * std::sin(1.0), 0.0, -m.R * std::cos(1.0);
    x.qd << 0.0, 2.0, 0.0;
    return x;
  }
  /// The particle (at its coordinates, as particles() places it) on the sphere of radius R about the
  /// origin; z up.
  static view::Figure figure(const Model& m) {
    view::Figure f;
    f.bodies = {{.name = "particle"}};
    f.spheres = {{.centre = {0, 0, 0}, .radius = m.R}};
    f.up = {0, 0, 1};
    return f;
  }
};

struct AtwoodMachineDef {
  using Model = lm::AtwoodMachine;
  static constexpr std::string_view type = "models::AtwoodMachine";
  /// Both masses at height c/2, at rest.
  static State<2> initial(const Model& m, double) {
    State<2> x;
    x.q << 0.5 * m.c, 0.5 * m.c;
    return x;
  }
  /// The pulley's radius (m): the model's pulley is massless and its radius does not enter the motion; it
  /// is only drawn.
  static constexpr double pulley_radius = 0.1;
  /// In the vertical x–y plane (y up): the pulley (a circle about its axle at the model's height c/2 + d, a
  /// pivot) and the masses hanging from either side of it on the string's straight runs, x = ∓pulley_radius.
  static view::Figure figure(const Model& m) {
    const double r = pulley_radius, h = m.pulley_axle();
    view::Figure f;
    f.bodies = {{.name = "mass1"}, {.name = "mass2"}};
    f.rods = {{.a = 0, .anchor = {-r, h, 0}}, {.a = 1, .anchor = {r, h, 0}}};
    f.pivots = {{0, h, 0}};
    f.circles = {{.centre = {0, h, 0}, .normal = {0, 0, 1}, .radius = r}};
    f.up = {0, 1, 0};
    return f;
  }
  /// Mass 1 at (−pulley_radius, y1, 0), mass 2 at (pulley_radius, y2, 0) (m).
  static void place(const Model&, const double* q, double, view::Point* c) {
    c[0] = {-pulley_radius, q[0], 0};
    c[1] = {pulley_radius, q[1], 0};
  }
};

struct CartesianDoublePendulumDef {
  using Model = lm::CartesianDoublePendulum;
  static constexpr std::string_view type = "models::CartesianDoublePendulum";
  /// At rest with the rods at 1 rad and 0.5 rad from the downward vertical
  /// (the default state of double_pendulum).
  static State<4> initial(const Model& m, double) {
    const double x1 = m.l1 * std::sin(1.0), y1 = -m.l1 * std::cos(1.0);
    State<4> x;
    x.q << x1, y1, x1 + m.l2 * std::sin(0.5), y1 - m.l2 * std::cos(0.5);
    return x;
  }
  /// The bobs (at their coordinates, as particles() places them) on rod 1 from the pivot at the origin and
  /// rod 2 from bob 1; y up.
  static view::Figure figure(const Model&) {
    return pendulum_figure({"bob1", "bob2"}, {0, 1, 0});
  }
};

struct KnifeEdgeDef {
  using Model = lm::KnifeEdge;
  static constexpr std::string_view type = "models::KnifeEdge";
  /// At the origin heading along +x at 1 m/s, turning at 0.5 rad/s: a circle of radius 2 m.
  static State<3> initial(const Model&, double) {
    State<3> x;
    x.qd << 1.0, 0.0, 0.5;
    return x;
  }
  /// Length of the blade drawn ahead of the contact point (m; the model has no length).
  static constexpr double blade_length = 0.5;
  /// The knife's contact point (the body, mass m) in the horizontal plane z = 0 (z up) and its blade, a rod
  /// to a small marker "blade" ahead of it along the heading φ.
  static view::Figure figure(const Model&) {
    view::Figure f;
    f.bodies = {{.name = "knife"}, {.name = "blade", .radius = 0.08 * blade_length}};
    f.rods = {{.a = 0, .b = 1}};
    f.up = {0, 0, 1};
    return f;
  }
  /// The knife at (x, y, 0), the marker at (x + blade_length cos φ, y + blade_length sin φ, 0) (m).
  static void place(const Model&, const double* q, double, view::Point* c) {
    c[0] = {q[0], q[1], 0};
    c[1] = {q[0] + blade_length * std::cos(q[2]), q[1] + blade_length * std::sin(q[2]), 0};
  }
};

}  // namespace

void add_constrained_models(std::vector<ModelEntry>& out) {
  out.push_back(entry<BeadOnRotatingWireDef>());
  out.push_back(entry<ParticleOnSphereDef>());
  out.push_back(entry<AtwoodMachineDef>());
  out.push_back(entry<CartesianDoublePendulumDef>());
  out.push_back(entry<KnifeEdgeDef>());
}

}  // namespace lagrangian::scene::detail
