// The parameters of a particle scene's tangent flow (particle_parameters.hpp).

#include "particle_parameters.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "lagrangian/ad/cmath.hpp"
#include "lagrangian/ad/eigen.hpp"
#include "lagrangian/ad/jet.hpp"

namespace lagrangian::scene::detail {

using particles::Parameter;
using Kind = particles::Parameter::Kind;

std::vector<SceneParameter> scene_parameters(const Scene& scene, const particles::ParticleModel& model) {
  std::vector<SceneParameter> out;
  const auto add = [&](std::string name, Kind kind, int index, int component, double value) {
    out.push_back({std::move(name), Parameter{kind, index, component}, value});
  };
  const auto vector = [&](const std::string& key, Kind kind, int index, const Eigen::Vector3d& value) {
    for (int c = 0; c < 3; ++c) add(key + "[" + std::to_string(c) + "]", kind, index, c, value[c]);
  };
  const auto entry = [](const char* table, std::size_t i, const char* key) {
    return std::string(table) + "[" + std::to_string(i) + "]." + key;
  };
  const bool contacts = scene.sphere_contacts || !scene.planes.empty() || scene.box;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const int b = static_cast<int>(i);
    add(entry("bodies", i, "mass"), Kind::mass, b, 0, scene.bodies[i].mass);
    if (contacts) add(entry("bodies", i, "radius"), Kind::radius, b, 0, scene.bodies[i].radius);
  }
  if (scene.gravity) vector("gravity.g", Kind::gravity, 0, scene.gravity->g);
  if (scene.newtonian_gravity) add("newtonian_gravity.G", Kind::newton_G, 0, 0, scene.newtonian_gravity->G);
  for (std::size_t i = 0; i < scene.springs.size(); ++i) {
    add(entry("springs", i, "stiffness"), Kind::stiffness, static_cast<int>(i), 0, scene.springs[i].stiffness);
    add(entry("springs", i, "rest_length"), Kind::rest_length, static_cast<int>(i), 0, scene.springs[i].rest_length);
  }
  for (std::size_t i = 0; i < scene.linear_drag.size(); ++i)
    add(entry("linear_drag", i, "coefficient"), Kind::linear_drag, static_cast<int>(i), 0,
        scene.linear_drag[i].coefficient);
  for (std::size_t i = 0; i < scene.quadratic_drag.size(); ++i)
    add(entry("quadratic_drag", i, "coefficient"), Kind::quadratic_drag, static_cast<int>(i), 0,
        scene.quadratic_drag[i].coefficient);
  for (std::size_t i = 0; i < scene.links.size(); ++i)  // (the engine's L: the distance at t0 when not given)
    add(entry("links", i, "length"), Kind::link_length, static_cast<int>(i), 0, model.rows()[i].length);
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    vector(entry("surfaces", i, "point"), Kind::surface_point, static_cast<int>(i), s.point);
    if (s.kind == Surface::Kind::sphere)
      add(entry("surfaces", i, "radius"), Kind::surface_radius, static_cast<int>(i), 0, s.radius);
  }
  if (scene.sphere_contacts)
    add("contacts.spheres.restitution", Kind::sphere_restitution, 0, 0, scene.sphere_contacts->restitution);
  for (std::size_t i = 0; i < scene.planes.size(); ++i) {
    add(entry("contacts.planes", i, "restitution"), Kind::plane_restitution, static_cast<int>(i), 0,
        scene.planes[i].restitution);
    vector(entry("contacts.planes", i, "point"), Kind::plane_point, static_cast<int>(i), scene.planes[i].point);
  }
  if (scene.box) {
    add("contacts.box.restitution", Kind::box_restitution, 0, 0, scene.box->restitution);
    vector("contacts.box.min", Kind::box_min, 0, scene.box->min);
    vector("contacts.box.max", Kind::box_max, 0, scene.box->max);
  }
  return out;
}

double impact_along_parameter(const particles::ParticleModel& model, const particles::Contact& c,
                              const Parameter& p, const double* q, const double* qd, bool plastic,
                              double* dqd_plus) {
  using D = ad::Jet<double, 1, 1>;
  using particles::at;
  const bool own_e = c.pair ? p.is(Kind::sphere_restitution)
                     : c.plane >= 0 ? p.is(Kind::plane_restitution, c.plane)
                                    : p.is(Kind::box_restitution);
  const D e = plastic ? D(0.0) : particles::seeded<D>(c.e, own_e);
  const std::vector<double>& mass = model.mass();
  const D inv_a = particles::inverse_mass<D>(1.0 / mass[static_cast<std::size_t>(c.a)], c.a, p);
  const D inv_b = c.pair ? particles::inverse_mass<D>(1.0 / mass[static_cast<std::size_t>(c.b)], c.b, p) : D(0.0);
  const Eigen::Vector3d normal = c.pair ? Eigen::Vector3d((at(q, c.a) - at(q, c.b)).normalized()) : c.n;
  const double v = normal.dot(at(qd, c.a) - (c.pair ? at(qd, c.b) : Eigen::Vector3d::Zero()));
  const D impulse = -(1.0 + e) * v / (inv_a + inv_b);
  std::fill(dqd_plus, dqd_plus + model.dim(), 0.0);
  const double da = (inv_a * impulse).g[0], db = (inv_b * impulse).g[0];
  for (int k = 0; k < 3; ++k) {
    dqd_plus[3 * c.a + k] = da * normal[k];
    if (c.pair) dqd_plus[3 * c.b + k] = -db * normal[k];
  }
  double dphi = 0;
  if (p.kind == Kind::radius && (p.index == c.a || (c.pair && p.index == c.b))) dphi = -1.0;
  if (!c.pair) {
    // The wall's point: its plane's, or the box's lower corner for a wall
    // whose normal points along +axis and its upper corner for one along −axis.
    const double side = c.n.sum();
    if ((c.plane >= 0 && p.kind == Kind::plane_point && p.index == c.plane) ||
        (c.plane < 0 && ((p.kind == Kind::box_min && side > 0) || (p.kind == Kind::box_max && side < 0))))
      dphi -= c.n[p.component];
  }
  return dphi;
}

void rows_along_parameter(const particles::ParticleModel& model, int rows, const Parameter& p, const double* q,
                          const double* qd, double* out) {
  using D = ad::Jet<double, 1, 1>;
  std::vector<D> r;  // (once per run: the start's check)
  for (int i = 0; i < model.dim(); ++i) r.emplace_back(q[i]);
  for (int i = 0; i < rows; ++i) {
    const particles::Row& row = model.rows()[static_cast<std::size_t>(i)];
    const D g = row.value(r.data(), p);
    const particles::Vector3<D> grad = row.grad(r.data(), p);
    D rate(0.0);
    for (int c = 0; c < 3; ++c) rate += grad[c] * (qd[3 * row.a + c] - (row.b >= 0 ? qd[3 * row.b + c] : 0.0));
    out[i] = g.g[0];
    out[rows + i] = rate.g[0];
  }
}

}  // namespace lagrangian::scene::detail
