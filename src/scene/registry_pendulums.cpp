// Built-in models of pendulums.hpp: pendulums, a central force in polar
// coordinates and the harmonic oscillator. These models have no default state of their own; the states
// below are the registry's (documented in docs/models.md).
//
// Pictures (view.hpp), lengths in m: the plane pendulums hang in the vertical x–y plane (z = 0, y up, gravity
// along −y) from a pivot at the origin; the spherical pendulum and the rotating hoop are drawn in space with z
// up; the oscillator and the central force as each Def says.

#include <array>
#include <cmath>
#include <cstddef>
#include <string_view>
#include <utility>
#include <vector>

#include "lagrangian/models/pendulums.hpp"
#include "registry_entry.hpp"

namespace lagrangian::scene::detail {
namespace {

namespace lm = lagrangian::models;

template <int N>
State<N> at_rest(const std::array<double, N>& q) {
  State<N> s;
  for (int i = 0; i < N; ++i) s.q[i] = q[static_cast<std::size_t>(i)];
  return s;
}

/// The end of a rod of length l (m) hanging from (x0, y0) at angle θ from the downward vertical, in the x–y
/// plane with y up: (x0 + l sin θ, y0 − l cos θ, 0).
view::Point hanging(double x0, double y0, double l, double theta) {
  return {x0 + l * std::sin(theta), y0 - l * std::cos(theta), 0.0};
}

struct SimplePendulumDef {
  using Model = lm::SimplePendulum;
  static constexpr std::string_view type = "models::SimplePendulum";
  static State<1> initial(const Model&, double) { return at_rest<1>({0.5}); }
  /// The bob on its rod from the pivot at the origin.
  static view::Figure figure(const Model&) {
    return pendulum_figure({"bob"}, {0, 1, 0});
  }
  /// The bob at (l sin θ, −l cos θ, 0) (m).
  static void place(const Model& m, const double* q, double, view::Point* c) { c[0] = hanging(0, 0, m.l, q[0]); }
};

struct HarmonicOscillatorDef {
  using Model = lm::HarmonicOscillator;
  static constexpr std::string_view type = "models::HarmonicOscillator";
  /// Stretched 0.1 m, at rest.
  static State<1> initial(const Model&, double) { return at_rest<1>({0.1}); }
  /// The mass sliding along the horizontal x axis (z up), on a spring from a wall 1 m to the left of its rest
  /// position (the model states no spring length; the wall is only drawn).
  static view::Figure figure(const Model&) {
    view::Figure f;
    f.bodies = {{.name = "mass"}};
    f.springs = {{.a = 0, .anchor = {-1, 0, 0}}};
    f.pivots = {{-1, 0, 0}};
    f.up = {0, 0, 1};
    return f;
  }
  /// The mass at (x, 0, 0) (m).
  static void place(const Model&, const double* q, double, view::Point* c) { c[0] = {q[0], 0, 0}; }
};

struct DoublePendulumDef {
  using Model = lm::DoublePendulum;
  static constexpr std::string_view type = "models::DoublePendulum";
  static State<2> initial(const Model&, double) { return at_rest<2>({1.0, 0.5}); }
  /// Bob 1 on rod 1 from the pivot at the origin, bob 2 on rod 2 from bob 1.
  static view::Figure figure(const Model&) {
    return pendulum_figure({"bob1", "bob2"}, {0, 1, 0});
  }
  /// r1 = l1 (sin θ1, −cos θ1, 0), r2 = r1 + l2 (sin θ2, −cos θ2, 0) (m).
  static void place(const Model& m, const double* q, double, view::Point* c) {
    c[0] = hanging(0, 0, m.l1, q[0]);
    c[1] = hanging(c[0][0], c[0][1], m.l2, q[1]);
  }
};

struct SphericalPendulumDef {
  using Model = lm::SphericalPendulum;
  static constexpr std::string_view type = "models::SphericalPendulum";
  static State<2> initial(const Model&, double) {
    State<2> s = at_rest<2>({1.0, 0.0});
    s.qd[1] = 2.0;  // swinging round as well as out
    return s;
  }
  /// The bob on its rod from the pivot at the origin, in space with z up.
  static view::Figure figure(const Model&) {
    return pendulum_figure({"bob"}, {0, 0, 1});
  }
  /// θ from the downward vertical (−z), φ the azimuth from +x: the bob at
  /// l (sin θ cos φ, sin θ sin φ, −cos θ) (m).
  static void place(const Model& m, const double* q, double, view::Point* c) {
    const double s = std::sin(q[0]);
    c[0] = {m.l * s * std::cos(q[1]), m.l * s * std::sin(q[1]), -m.l * std::cos(q[0])};
  }
};

struct ElasticPendulumDef {
  using Model = lm::ElasticPendulum;
  static constexpr std::string_view type = "models::ElasticPendulum";
  /// 0.1 m below the hanging equilibrium r = l0 + m g / k, at 0.3 rad.
  static State<2> initial(const Model& m, double) { return at_rest<2>({m.l0 + m.m * m.g / m.k + 0.1, 0.3}); }
  /// The bob on its spring from the pivot at the origin.
  static view::Figure figure(const Model&) {
    view::Figure f = pendulum_figure({"bob"}, {0, 1, 0});
    std::swap(f.rods, f.springs);
    return f;
  }
  /// The bob at (r sin θ, −r cos θ, 0) (m).
  static void place(const Model&, const double* q, double, view::Point* c) { c[0] = hanging(0, 0, q[0], q[1]); }
};

struct BeadOnRotatingHoopDef {
  using Model = lm::BeadOnRotatingHoop;
  static constexpr std::string_view type = "models::BeadOnRotatingHoop";
  static State<1> initial(const Model&, double) { return at_rest<1>({0.5}); }
  /// In the fixed (inertial) frame, z up, the hoop's centre at the origin: the hoop turns about the z axis,
  /// so it is drawn by what stays put and by a marker that turns with it: the sphere of radius R it sweeps
  /// (the bead never leaves it), the bearings of its axis at (0, 0, ±R), the bead with its radius to the
  /// centre, and a small marker "hoop" on the rim level with the centre, joined to both bearings.
  static view::Figure figure(const Model& m) {
    view::Figure f;
    f.bodies = {{.name = "bead"}, {.name = "hoop", .radius = 0.02 * m.R}};
    f.rods = {{.a = 0, .anchor = {0, 0, 0}}, {.a = 1, .anchor = {0, 0, m.R}}, {.a = 1, .anchor = {0, 0, -m.R}}};
    f.pivots = {{0, 0, m.R}, {0, 0, -m.R}};
    f.spheres = {{.centre = {0, 0, 0}, .radius = m.R}};
    f.up = {0, 0, 1};
    return f;
  }
  /// At time t the hoop's plane is at azimuth ωt: the bead at R (sin θ cos ωt, sin θ sin ωt, −cos θ), θ from
  /// the bottom, and the marker at R (cos ωt, sin ωt, 0) (m).
  static void place(const Model& m, const double* q, double t, view::Point* c) {
    const double s = std::sin(q[0]), ca = std::cos(m.omega * t), sa = std::sin(m.omega * t);
    c[0] = {m.R * s * ca, m.R * s * sa, -m.R * std::cos(q[0])};
    c[1] = {m.R * ca, m.R * sa, 0};
  }
};

struct KeplerPolarDef {
  using Model = lm::KeplerPolar;
  static constexpr std::string_view type = "models::KeplerPolar";
  /// Periapsis of the orbit a = 1 m, e = 0.5: r = a (1 − e), speed
  /// √(GM (1 + e) / (a (1 − e))) with GM = k/m.
  static State<2> initial(const Model& m, double) {
    const double a = 1.0, e = 0.5, gm = m.k / m.m;
    const double rp = a * (1.0 - e), vp = std::sqrt(gm * (1.0 + e) / (a * (1.0 - e)));
    State<2> s = at_rest<2>({rp, 0.0});
    s.qd[1] = vp / rp;
    return s;
  }
  /// The centre of force ("sun", fixed at the origin) and the particle ("planet"), in the x–y plane; no
  /// gravity, z (the normal of the orbit) up.
  static view::Figure figure(const Model&) {
    return point_masses({"sun", "planet"}, {0, 0, 1});
  }
  /// The sun at the origin, the planet at (r cos φ, r sin φ, 0) (m).
  static void place(const Model&, const double* q, double, view::Point* c) {
    c[0] = {0, 0, 0};
    c[1] = {q[0] * std::cos(q[1]), q[0] * std::sin(q[1]), 0};
  }
};

struct CartPendulumDef {
  using Model = lm::CartPendulum;
  static constexpr std::string_view type = "models::CartPendulum";
  static State<2> initial(const Model&, double) { return at_rest<2>({0.0, 0.5}); }
  /// The cart on the rail y = 0 with the bob on its rod below it, and (when k > 0) the cart's spring from a
  /// wall at x = −l (the spring is relaxed at x = 0; its length is only drawn).
  static view::Figure figure(const Model& m) {
    view::Figure f;
    f.bodies = {{.name = "cart"}, {.name = "bob"}};
    f.rods = {{.a = 1, .b = 0}};
    if (m.k > 0) {
      f.springs = {{.a = 0, .anchor = {-m.l, 0, 0}}};
      f.pivots = {{-m.l, 0, 0}};
    }
    f.up = {0, 1, 0};
    return f;
  }
  /// The cart at (x, 0, 0), the bob at (x + l sin θ, −l cos θ, 0) (m).
  static void place(const Model& m, const double* q, double, view::Point* c) {
    c[0] = {q[0], 0, 0};
    c[1] = hanging(q[0], 0, m.l, q[1]);
  }
};

struct DrivenPendulumDef {
  using Model = lm::DrivenPendulum;
  static constexpr std::string_view type = "models::DrivenPendulum";
  static State<1> initial(const Model&, double) { return at_rest<1>({0.5}); }
  /// The bob on its rod from the moving support (a small marker), which slides on the y axis.
  static view::Figure figure(const Model& m) {
    view::Figure f;
    f.bodies = {{.name = "bob"}, {.name = "support", .radius = 0.02 * m.l}};
    f.rods = {{.a = 0, .b = 1}};
    f.up = {0, 1, 0};
    return f;
  }
  /// The support at (0, a cos Ωt, 0), the bob at (l sin θ, a cos Ωt − l cos θ, 0) (m).
  static void place(const Model& m, const double* q, double t, view::Point* c) {
    const double y = m.a * std::cos(m.Omega * t);
    c[0] = hanging(0, y, m.l, q[0]);
    c[1] = {0, y, 0};
  }
};

struct PendulumChain3Def {
  using Model = lm::PendulumChain<3>;
  static constexpr const auto& description = lm::presets::pendulum_chain_3;
  static constexpr std::string_view type = "models::PendulumChain<3>";
  static State<3> initial(const Model&, double) { return at_rest<3>({0.5, 0.4, 0.3}); }
  /// Bob 1 on its rod from the pivot at the origin, each next bob on its rod from the one before.
  static view::Figure figure(const Model&) {
    return pendulum_figure({"bob1", "bob2", "bob3"}, {0, 1, 0});
  }
  /// r_k = r_{k−1} + l_k (sin θ_k, −cos θ_k, 0), r_0 = 0 (m).
  static void place(const Model& m, const double* q, double, view::Point* c) {
    view::Point from{0, 0, 0};
    for (std::size_t k = 0; k < 3; ++k) from = c[k] = hanging(from[0], from[1], m.l[k], q[k]);
  }
};

}  // namespace

void add_pendulum_models(std::vector<ModelEntry>& out) {
  out.push_back(entry<SimplePendulumDef>());
  out.push_back(entry<DoublePendulumDef>());
  out.push_back(entry<SphericalPendulumDef>());
  out.push_back(entry<ElasticPendulumDef>());
  out.push_back(entry<BeadOnRotatingHoopDef>());
  out.push_back(entry<KeplerPolarDef>());
  out.push_back(entry<CartPendulumDef>());
  out.push_back(entry<DrivenPendulumDef>());
  out.push_back(entry<PendulumChain3Def>());
  out.push_back(entry<HarmonicOscillatorDef>());
}

}  // namespace lagrangian::scene::detail
