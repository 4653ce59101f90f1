// Built-in models of impacts.hpp: smooth spheres colliding on a line, in a
// plane, with a fixed plane and inside a box (Newton's law of restitution).
// The default states are the registry's and leave every contact open at t0.
//
// Pictures (view.hpp), lengths in m: the spheres are drawn with their radii at their coordinates (particles()
// places them; a line is the x axis, a plane z = 0 unless the model's gravity makes it vertical), named as
// the contacts name them ("s1", "s2", …, "ball") so that the page flashes them at their impacts.

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "lagrangian/models/impacts.hpp"
#include "registry_entry.hpp"

namespace lagrangian::scene::detail {
namespace {

namespace lm = lagrangian::models;

struct DirectImpactDef {
  using Model = lm::SpheresOnLine<2>;
  static constexpr const auto& description = lm::presets::direct_impact;
  static constexpr std::string_view type = "models::SpheresOnLine<2>";
  static Model build(const Parameters& p) { return Model({p["m1"], p["m2"]}, {p["r1"], p["r2"]}, p["e"]); }
  /// 0.5 m apart (surface to surface), closing at 1.5 m/s: impact at t = 1/3 s.
  static State<2> initial(const Model& m, double) {
    State<2> x;
    x.q << 0.0, m.r[0] + m.r[1] + 0.5;
    x.qd << 1.0, -0.5;
    return x;
  }
  /// The two spheres on the x axis, z up.
  static view::Figure figure(const Model& m) {
    view::Figure f;
    f.bodies = {{.name = "s1", .radius = m.r[0]}, {.name = "s2", .radius = m.r[1]}};
    f.up = {0, 0, 1};
    return f;
  }
};

struct NewtonsCradleDef {
  using Model = lm::SpheresOnLine<5>;
  static constexpr const auto& description = lm::presets::newtons_cradle;
  static constexpr std::string_view type = "models::SpheresOnLine<5>";
  static Model build(const Parameters& p) {
    const double m = p["m"], r = p["r"];
    return Model({m, m, m, m, m}, {r, r, r, r, r}, p["e"]);
  }
  /// Spheres 2–5 touching at rest; sphere 1 0.1 m away, arriving at 1 m/s.
  static State<5> initial(const Model& m, double) {
    const double r = m.r[0];
    State<5> x;
    x.q << -0.1, 2 * r, 4 * r, 6 * r, 8 * r;
    x.qd << 1.0, 0.0, 0.0, 0.0, 0.0;
    return x;
  }
  /// The five spheres on the x axis, z up.
  static view::Figure figure(const Model& m) {
    view::Figure f;
    for (std::size_t i = 0; i < m.r.size(); ++i)
      f.bodies.push_back({.name = "s" + std::to_string(i + 1), .radius = m.r[i]});
    f.up = {0, 0, 1};
    return f;
  }
};

struct ObliqueImpactDef {
  using Model = lm::TwoSpheres<2>;
  static constexpr const auto& description = lm::presets::oblique_impact;
  static constexpr std::string_view type = "models::TwoSpheres<2>";
  /// Sphere 1 at the origin moving along +x at 1 m/s; sphere 2 at rest,
  /// offset sideways by half the sum of the radii: the common normal at
  /// impact is at 30 degrees to the line of motion.
  static State<4> initial(const Model& m, double) {
    const double d = m.r1 + m.r2;
    State<4> x;
    x.q << 0.0, 0.0, d + 0.5, 0.5 * d;
    x.qd << 1.0, 0.0, 0.0, 0.0;
    return x;
  }
  /// The two spheres in the plane z = 0 (no gravity; z, the plane's normal, up).
  static view::Figure figure(const Model& m) {
    view::Figure f;
    f.bodies = {{.name = "s1", .radius = m.r1}, {.name = "s2", .radius = m.r2}};
    f.up = {0, 0, 1};
    return f;
  }
};

struct BallAndPlaneDef {
  using Model = lm::BallAndPlane;
  static constexpr std::string_view type = "models::BallAndPlane";
  static Model build(const Parameters& p) {
    return Model(p["m"], p["R"], p["e"], p["g"], {p["nx"], p["ny"], p["nz"]}, p["offset"]);
  }
  static std::string_view alias(std::string_view model_parameter) {
    return model_parameter == "|normal|" ? "nz" : "";
  }
  /// At rest with its surface 1 m from the plane along the normal.
  static State<3> initial(const Model& m, double) {
    const double h = m.d + m.R + 1.0;
    const std::array<double, 3> n = m.normal();
    State<3> x;
    x.q << n[0] * h, n[1] * h, n[2] * h;
    return x;
  }
  /// The ball and the plane n·r = d (through d n, normal n); gravity along −z.
  static view::Figure figure(const Model& m) {
    view::Figure f;
    f.bodies = {{.name = "ball", .radius = m.R}};
    const std::array<double, 3> n = m.normal();
    f.planes = {{.name = "plane", .point = {m.d * n[0], m.d * n[1], m.d * n[2]}, .normal = n}};
    f.up = {0, 0, 1};
    return f;
  }
};

struct SpheresInBoxDef {
  using Model = lm::SpheresInBox<3>;
  static constexpr const auto& description = lm::presets::spheres_in_box;
  static constexpr std::string_view type = "models::SpheresInBox<3>";
  static Model build(const Parameters& p) {
    const double m = p["m"], r = p["r"];
    return Model({m, m, m}, {r, r, r}, p["W"], p["H"], p["e_wall"], p["e_pair"], p["g"]);
  }
  /// "sphere i (radius …) does not fit in the box" names no parameter.
  static std::string_view alias(std::string_view model_parameter) { return model_parameter.empty() ? "r" : ""; }
  /// Centres at (0.2 W, 0.5 H), (0.5 W, 0.3 H), (0.8 W, 0.7 H) with
  /// velocities (1, 0.5), (-0.7, 0.8), (0.3, -1) m/s.
  static State<6> initial(const Model& m, double) {
    State<6> x;
    x.q << 0.2 * m.W, 0.5 * m.H, 0.5 * m.W, 0.3 * m.H, 0.8 * m.W, 0.7 * m.H;
    x.qd << 1.0, 0.5, -0.7, 0.8, 0.3, -1.0;
    return x;
  }
  /// The discs in the box [0, W] × [0, H] of the plane z = 0 (drawn flat); gravity, when given, along −y.
  static view::Figure figure(const Model& m) {
    view::Figure f;
    for (std::size_t i = 0; i < m.r.size(); ++i)
      f.bodies.push_back({.name = "s" + std::to_string(i + 1), .radius = m.r[i]});
    f.boxes = {{.min = {0, 0, 0}, .max = {m.W, m.H, 0}}};
    f.up = {0, 1, 0};
    return f;
  }
};

}  // namespace

void add_impact_models(std::vector<ModelEntry>& out) {
  out.push_back(entry<DirectImpactDef>());
  out.push_back(entry<NewtonsCradleDef>());
  out.push_back(entry<ObliqueImpactDef>());
  out.push_back(entry<BallAndPlaneDef>());
  out.push_back(entry<SpheresInBoxDef>());
}

}  // namespace lagrangian::scene::detail
