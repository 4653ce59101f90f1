#pragma once
// Internal to the particle scenes' engine: the numbers a scene declares as
// parameters of its tangent flow (`lagrangian sensitivity --parameter
// KEY`), named by their scene keys, and the parts of their columns that the
// force kernels do not give: the rows of links and surfaces along a
// parameter (particle_tangent.cpp; the impact map's are particle_impact.hpp's).

#include <string>
#include <vector>

#include "lagrangian/scene/scene.hpp"
#include "particle_model.hpp"

namespace lagrangian::scene::detail {

/// One parameter of a particle scene: its scene key (as `run --set` takes
/// it: `gravity.g[2]`, `bodies[0].mass`, `contacts.planes[0].restitution`),
/// what it is and its value.
struct SceneParameter {
  std::string name;
  particles::Parameter which;
  double value = 0;
};

/// Every parameter the scene declares, in the order of its file's tables:
/// the bodies' masses (and radii where contacts meet them), g, G, the
/// springs' stiffnesses and rest lengths, the drags' coefficients, the
/// links' lengths, the surfaces' points and radii, and the contacts'
/// restitution coefficients, planes' points and the box's corners; the
/// values as `model`, built from the scene, holds them.
std::vector<SceneParameter> scene_parameters(const Scene& scene, const particles::ParticleModel& model);

/// ∂h/∂p of the rows h = (g, ġ) of the first `rows` constraint rows (the
/// links and surfaces) at (q, q̇) along the seeded parameter `p` (2 rows
/// values into `out`): a link's length and a surface's point or radius
/// move them, nothing else does.
void rows_along_parameter(const particles::ParticleModel& model, int rows, const particles::Parameter& p,
                          const double* q, const double* qd, double* out);

}  // namespace lagrangian::scene::detail
