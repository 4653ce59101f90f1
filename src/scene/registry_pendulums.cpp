// Built-in models of pendulums.hpp: pendulums, a central force in polar
// coordinates and the harmonic oscillator. These models have no default state of their own; the states
// below are the registry's (documented in docs/models.md).

#include <array>
#include <cmath>
#include <string_view>
#include <vector>

#include "lagrangian/models/pendulums.hpp"
#include "registry_common.hpp"

namespace lagrangian::scene::detail {
namespace {

namespace lm = lagrangian::models;

template <int N>
State<N> at_rest(const std::array<double, N>& q) {
  State<N> s;
  for (int i = 0; i < N; ++i) s.q[i] = q[static_cast<std::size_t>(i)];
  return s;
}

struct SimplePendulumDef {
  using Model = lm::SimplePendulum;
  static constexpr std::string_view name = "simple_pendulum";
  static constexpr std::string_view type = "models::SimplePendulum";
  static Model build(const Parameters& p) { return Model(p["m"], p["l"], p["g"]); }
  static State<1> initial(const Model&, double) { return at_rest<1>({0.5}); }
};

struct HarmonicOscillatorDef {
  using Model = lm::HarmonicOscillator;
  static constexpr std::string_view name = "harmonic_oscillator";
  static constexpr std::string_view type = "models::HarmonicOscillator";
  static Model build(const Parameters& p) { return Model(p["m"], p["k"]); }
  /// Stretched 0.1 m, at rest.
  static State<1> initial(const Model&, double) { return at_rest<1>({0.1}); }
};

struct DoublePendulumDef {
  using Model = lm::DoublePendulum;
  static constexpr std::string_view name = "double_pendulum";
  static constexpr std::string_view type = "models::DoublePendulum";
  static Model build(const Parameters& p) { return Model(p["m1"], p["m2"], p["l1"], p["l2"], p["g"]); }
  static State<2> initial(const Model&, double) { return at_rest<2>({1.0, 0.5}); }
};

struct SphericalPendulumDef {
  using Model = lm::SphericalPendulum;
  static constexpr std::string_view name = "spherical_pendulum";
  static constexpr std::string_view type = "models::SphericalPendulum";
  static Model build(const Parameters& p) { return Model(p["m"], p["l"], p["g"]); }
  static State<2> initial(const Model&, double) {
    State<2> s = at_rest<2>({1.0, 0.0});
    s.qd[1] = 2.0;  // swinging round as well as out
    return s;
  }
};

struct ElasticPendulumDef {
  using Model = lm::ElasticPendulum;
  static constexpr std::string_view name = "elastic_pendulum";
  static constexpr std::string_view type = "models::ElasticPendulum";
  static Model build(const Parameters& p) { return Model(p["m"], p["k"], p["l0"], p["g"]); }
  /// 0.1 m below the hanging equilibrium r = l0 + m g / k, at 0.3 rad.
  static State<2> initial(const Model& m, double) { return at_rest<2>({m.l0 + m.m * m.g / m.k + 0.1, 0.3}); }
};

struct BeadOnRotatingHoopDef {
  using Model = lm::BeadOnRotatingHoop;
  static constexpr std::string_view name = "bead_on_rotating_hoop";
  static constexpr std::string_view type = "models::BeadOnRotatingHoop";
  static Model build(const Parameters& p) { return Model(p["m"], p["R"], p["omega"], p["g"]); }
  static State<1> initial(const Model&, double) { return at_rest<1>({0.5}); }
};

struct KeplerPolarDef {
  using Model = lm::KeplerPolar;
  static constexpr std::string_view name = "kepler_polar";
  static constexpr std::string_view type = "models::KeplerPolar";
  static Model build(const Parameters& p) { return Model(p["m"], p["k"]); }
  /// Periapsis of the orbit a = 1 m, e = 0.5: r = a (1 − e), speed
  /// √(GM (1 + e) / (a (1 − e))) with GM = k/m.
  static State<2> initial(const Model& m, double) {
    const double a = 1.0, e = 0.5, gm = m.k / m.m;
    const double rp = a * (1.0 - e), vp = std::sqrt(gm * (1.0 + e) / (a * (1.0 - e)));
    State<2> s = at_rest<2>({rp, 0.0});
    s.qd[1] = vp / rp;
    return s;
  }
};

struct CartPendulumDef {
  using Model = lm::CartPendulum;
  static constexpr std::string_view name = "cart_pendulum";
  static constexpr std::string_view type = "models::CartPendulum";
  static Model build(const Parameters& p) { return Model(p["M"], p["m"], p["l"], p["k"], p["g"]); }
  static State<2> initial(const Model&, double) { return at_rest<2>({0.0, 0.5}); }
};

struct DrivenPendulumDef {
  using Model = lm::DrivenPendulum;
  static constexpr std::string_view name = "driven_pendulum";
  static constexpr std::string_view type = "models::DrivenPendulum";
  static Model build(const Parameters& p) { return Model(p["m"], p["l"], p["a"], p["Omega"], p["g"]); }
  static State<1> initial(const Model&, double) { return at_rest<1>({0.5}); }
};

/// PendulumChain<3> with its coordinates named (the template names none).
struct PendulumChain3 : lm::PendulumChain<3> {
  PendulumChain3(double mass, double length, double gravity) : lm::PendulumChain<3>(mass, length, gravity) {}
  std::array<std::string_view, 3> coordinate_names() const { return {"theta1", "theta2", "theta3"}; }
};

struct PendulumChain3Def {
  using Model = PendulumChain3;
  static constexpr std::string_view name = "pendulum_chain_3";
  static constexpr std::string_view type = "models::PendulumChain<3>";
  static Model build(const Parameters& p) { return Model(p["m"], p["l"], p["g"]); }
  static State<3> initial(const Model&, double) { return at_rest<3>({0.5, 0.4, 0.3}); }
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
