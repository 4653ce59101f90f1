// Built-in models of constrained.hpp: holonomic (fixed and moving) and
// Pfaffian constraints in redundant coordinates. The default states below
// are the registry's and satisfy the constraints at t0 for any parameters.

#include <cmath>
#include <string_view>
#include <vector>

#include "lagrangian/models/constrained.hpp"
#include "registry_common.hpp"

namespace lagrangian::scene::detail {
namespace {

namespace lm = lagrangian::models;

struct BeadOnRotatingWireDef {
  using Model = lm::BeadOnRotatingWire;
  static constexpr std::string_view name = "bead_on_rotating_wire";
  static constexpr std::string_view type = "models::BeadOnRotatingWire";
  static Model build(const Parameters& p) { return Model(p["m"], p["omega"]); }
  /// 1 m out along the wire at t0, turning with it (no radial speed).
  static State<2> initial(const Model& m, double t0) {
    const double c = std::cos(m.omega * t0), s = std::sin(m.omega * t0);
    State<2> x;
    x.q << c, s;
    x.qd << -m.omega * s, m.omega * c;
    return x;
  }
};

struct ParticleOnSphereDef {
  using Model = lm::ParticleOnSphere;
  static constexpr std::string_view name = "particle_on_sphere";
  static constexpr std::string_view type = "models::ParticleOnSphere";
  static Model build(const Parameters& p) { return Model(p["m"], p["R"], p["g"]); }
  /// 1 rad from the bottom, moving horizontally at 2 m/s along +y.
  static State<3> initial(const Model& m, double) {
    State<3> x;
    x.q << m.R * std::sin(1.0), 0.0, -m.R * std::cos(1.0);
    x.qd << 0.0, 2.0, 0.0;
    return x;
  }
};

struct AtwoodMachineDef {
  using Model = lm::AtwoodMachine;
  static constexpr std::string_view name = "atwood_machine";
  static constexpr std::string_view type = "models::AtwoodMachine";
  static Model build(const Parameters& p) { return Model(p["m1"], p["m2"], p["g"], p["c"]); }
  /// Both masses at height c/2, at rest.
  static State<2> initial(const Model& m, double) {
    State<2> x;
    x.q << 0.5 * m.c, 0.5 * m.c;
    return x;
  }
};

struct CartesianDoublePendulumDef {
  using Model = lm::CartesianDoublePendulum;
  static constexpr std::string_view name = "cartesian_double_pendulum";
  static constexpr std::string_view type = "models::CartesianDoublePendulum";
  static Model build(const Parameters& p) { return Model(p["m1"], p["m2"], p["l1"], p["l2"], p["g"]); }
  /// At rest with the rods at 1 rad and 0.5 rad from the downward vertical
  /// (the default state of double_pendulum).
  static State<4> initial(const Model& m, double) {
    const double x1 = m.l1 * std::sin(1.0), y1 = -m.l1 * std::cos(1.0);
    State<4> x;
    x.q << x1, y1, x1 + m.l2 * std::sin(0.5), y1 - m.l2 * std::cos(0.5);
    return x;
  }
};

struct KnifeEdgeDef {
  using Model = lm::KnifeEdge;
  static constexpr std::string_view name = "knife_edge";
  static constexpr std::string_view type = "models::KnifeEdge";
  static Model build(const Parameters& p) { return Model(p["m"], p["I"]); }
  /// At the origin heading along +x at 1 m/s, turning at 0.5 rad/s: a circle of radius 2 m.
  static State<3> initial(const Model&, double) {
    State<3> x;
    x.qd << 1.0, 0.0, 0.5;
    return x;
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
