// Built-in models of two_body.hpp and projectile.hpp: two bodies under
// Newtonian gravity, the reduced (Kepler) problem and projectiles with and
// without drag. Each starts from the model's own default_state().
//
// Pictures (view.hpp), lengths in m: the orbits in the plane z = 0 with z (the orbit's normal) up; the
// projectiles in the vertical x–y plane with y up.

#include <cmath>
#include <string_view>
#include <vector>

#include "lagrangian/models/projectile.hpp"
#include "lagrangian/models/two_body.hpp"
#include "registry_entry.hpp"

namespace lagrangian::scene::detail {
namespace {

namespace lm = lagrangian::models;

struct TwoBodyDef {
  using Model = lm::TwoBody<2>;
  static constexpr const auto& description = lm::presets::two_body;
  static constexpr std::string_view type = "models::TwoBody<2, models::NewtonianGravity>";
  static Model build(const Parameters& p) {
    // NewtonianGravity takes any k; k <= 0 would not attract.
    return Model(p["m1"], p["m2"], lm::NewtonianGravity{require_positive("TwoBody", "k", p["k"])});
  }
  /// Centre of mass at rest at the origin, the bodies at periapsis of the
  /// relative orbit a = 1 m, e = 0.5.
  static State<4> initial(const Model& m, double) { return m.default_state(); }
  /// The two bodies at their coordinates (particles() places them).
  static view::Figure figure(const Model&) {
    return point_masses({"body1", "body2"}, {0, 0, 1});
  }
};

struct KeplerDef {
  using Model = lm::RelativeMotion<2>;
  static constexpr const auto& description = lm::presets::kepler;
  static constexpr std::string_view type = "models::RelativeMotion<2, models::NewtonianGravity>";
  static Model build(const Parameters& p) {
    return Model(p["mu"], lm::NewtonianGravity{require_positive("RelativeMotion", "k", p["k"])});
  }
  /// Periapsis of the orbit a = 1 m, e = 0.5 (GM = k/mu).
  static State<2> initial(const Model& m, double) { return m.default_state(); }
  /// The relative motion r = r2 − r1 seen from body 1: body 1 ("sun") fixed at the origin, the body of
  /// reduced mass mu ("planet") at r.
  static view::Figure figure(const Model&) {
    return point_masses({"sun", "planet"}, {0, 0, 1});
  }
  /// The sun at the origin, the planet at (x, y, 0) (m).
  static void place(const Model&, const double* q, double, view::Point* c) {
    c[0] = {0, 0, 0};
    c[1] = {q[0], q[1], 0};
  }
};

template <lm::Drag D>
struct ProjectileBase {
  using Model = lm::Projectile<D>;
  /// Launched from the origin at 20 m/s, 45 degrees above the horizontal (or
  /// halfway between the plane and the vertical on a steep slope).
  static State<2> initial(const Model& m, double) { return m.default_state(); }
  /// The projectile at (x, y, 0) (particles() places it) and the ground, the plane through the launch point
  /// at angle beta to the horizontal: normal (−sin β, cos β, 0).
  static view::Figure figure(const Model& m) {
    view::Figure f;
    f.bodies = {{.name = "projectile"}};
    f.planes = {{.name = "ground", .point = {0, 0, 0}, .normal = {-std::sin(m.beta), std::cos(m.beta), 0}}};
    f.up = {0, 1, 0};
    return f;
  }
};

struct ProjectileDef : ProjectileBase<lm::Drag::none> {
  static constexpr std::string_view type = "models::Projectile<models::Drag::none>";
  static Model build(const Parameters& p) { return Model(p["m"], p["g"], p["beta"], 0.0); }
};

struct ProjectileLinearDragDef : ProjectileBase<lm::Drag::linear> {
  static constexpr std::string_view type = "models::Projectile<models::Drag::linear>";
  static Model build(const Parameters& p) {
    // b = 0 is the projectile without drag (and its closed form would divide 0 by 0).
    return Model(p["m"], p["g"], p["beta"], require_positive("Projectile", "b", p["b"]));
  }
  static std::string_view alias(std::string_view model_parameter) { return model_parameter == "drag" ? "b" : ""; }
};

struct ProjectileQuadraticDragDef : ProjectileBase<lm::Drag::quadratic> {
  static constexpr std::string_view type = "models::Projectile<models::Drag::quadratic>";
  static Model build(const Parameters& p) {
    return Model(p["m"], p["g"], p["beta"], require_positive("Projectile", "c", p["c"]));
  }
  static std::string_view alias(std::string_view model_parameter) { return model_parameter == "drag" ? "c" : ""; }
};

}  // namespace

void add_orbit_models(std::vector<ModelEntry>& out) {
  out.push_back(entry<TwoBodyDef>());
  out.push_back(entry<KeplerDef>());
  out.push_back(entry<ProjectileDef>());
  out.push_back(entry<ProjectileLinearDragDef>());
  out.push_back(entry<ProjectileQuadraticDragDef>());
}

}  // namespace lagrangian::scene::detail
