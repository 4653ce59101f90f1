#pragma once
// Internal to the particle scenes' engine: the numbers a scene declares as
// parameters of its tangent flow (`lagrangian sensitivity --parameter
// KEY`), named by their scene keys, and the parts of their columns that the
// force kernels do not give: the impact map and the rows of links and
// surfaces along a parameter (particle_tangent.cpp).

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

/// Newton's law at an impact of contact `c` at (q, q̇⁻) along the seeded
/// parameter `p` (the state held constant): ∂q̇⁺/∂p (3N values into
/// `dqd_plus`) from
///   q̇⁺_a = q̇⁻_a + J n̂/m_a,  q̇⁺_b = q̇⁻_b − J n̂/m_b,  J = −(1 + e) v/(1/m_a + 1/m_b),
/// with the contact's own e, or e = 0 when `plastic` (the impact that
/// begins a rest); returns ∂φ/∂p of its gap φ = n̂·(r_a − p) − R (a plane
/// or a box wall) or |r_a − r_b| − R_a − R_b (a pair): −n̂·∂p/∂p for the
/// plane's point or the box's corner, −1 for a radius (m per unit of p).
double impact_along_parameter(const particles::ParticleModel& model, const particles::Contact& c,
                              const particles::Parameter& p, const double* q, const double* qd, bool plastic,
                              double* dqd_plus);

/// ∂h/∂p of the rows h = (g, ġ) of the first `rows` constraint rows (the
/// links and surfaces) at (q, q̇) along the seeded parameter `p` (2 rows
/// values into `out`): a link's length and a surface's point or radius
/// move them, nothing else does.
void rows_along_parameter(const particles::ParticleModel& model, int rows, const particles::Parameter& p,
                          const double* q, const double* qd, double* out);

}  // namespace lagrangian::scene::detail
