// The catalog of built-in models: names, descriptions, coordinates and
// parameters with their defaults and units, read from each model's
// description (lagrangian/model_description.hpp) in its header, or from the
// preset a scene names (models::presets). The model headers are read for
// their descriptions only: nothing here instantiates a model's code, so the
// scene parser and the fuzzer link this file without the library's models.

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "lagrangian/model_description.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/models/two_body.hpp"
#include "lagrangian/scene/models.hpp"

namespace lagrangian::scene {

namespace {

/// A description's catalog entry.
template <std::size_t N, std::size_t P>
ModelInfo info_of(const ModelDescription<N, P>& d) {
  ModelInfo info{std::string(d.name), std::string(d.summary), {}, {}, {}};
  for (const CoordinateDescription& c : d.coordinates) {
    info.coordinates.emplace_back(c.name);
    info.units.emplace_back(c.unit);
  }
  for (const ParameterDescription& p : d.parameters)
    info.parameters.push_back({std::string(p.name), p.value, std::string(p.unit), std::string(p.meaning)});
  return info;
}

std::vector<ModelInfo> make_catalog() {
  namespace lm = lagrangian::models;
  std::vector<ModelInfo> c{
      info_of(lm::SimplePendulum::description),
      info_of(lm::HarmonicOscillator::description),
      info_of(lm::DoublePendulum::description),
      info_of(lm::SphericalPendulum::description),
      info_of(lm::ElasticPendulum::description),
      info_of(lm::BeadOnRotatingHoop::description),
      info_of(lm::KeplerPolar::description),
      info_of(lm::CartPendulum::description),
      info_of(lm::DrivenPendulum::description),
      info_of(lm::presets::pendulum_chain_3),
      info_of(lm::BeadOnRotatingWire::description),
      info_of(lm::ParticleOnSphere::description),
      info_of(lm::AtwoodMachine::description),
      info_of(lm::CartesianDoublePendulum::description),
      info_of(lm::KnifeEdge::description),
      info_of(lm::presets::direct_impact),
      info_of(lm::presets::newtons_cradle),
      info_of(lm::presets::oblique_impact),
      info_of(lm::BallAndPlane::description),
      info_of(lm::presets::spheres_in_box),
      info_of(lm::presets::two_body),
      info_of(lm::presets::kepler),
      info_of(lm::Projectile<lm::Drag::none>::description),
      info_of(lm::Projectile<lm::Drag::linear>::description),
      info_of(lm::Projectile<lm::Drag::quadratic>::description),
  };
  std::sort(c.begin(), c.end(), [](const ModelInfo& a, const ModelInfo& b) { return a.name < b.name; });
  return c;
}

}  // namespace

const std::vector<ModelInfo>& builtin_models() {
  static const std::vector<ModelInfo> catalog = make_catalog();
  return catalog;
}

const ModelInfo* find_model(const std::string& name) {
  const auto& all = builtin_models();
  const auto it = std::lower_bound(all.begin(), all.end(), name,
                                   [](const ModelInfo& m, const std::string& n) { return m.name < n; });
  return it != all.end() && it->name == name ? &*it : nullptr;
}

}  // namespace lagrangian::scene
