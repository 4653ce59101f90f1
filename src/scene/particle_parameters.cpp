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
