// A scene of free-flying spheres as the event-driven engine's system and
// run (particle_engine.hpp: hard_sphere_system(), hard_sphere_options()).

#include <string>

#include "particle_engine.hpp"

namespace lagrangian::scene::detail {

HardSphereSystem hard_sphere_system(const Scene& scene) {
  HardSphereSystem sys;
  for (const Body& b : scene.bodies) sys.spheres.push_back({b.name, b.mass, b.radius, b.position, b.velocity});
  sys.box_min = scene.box->min;
  sys.box_max = scene.box->max;
  sys.box_restitution = scene.box->restitution;
  sys.pair_restitution = scene.sphere_contacts ? scene.sphere_contacts->restitution : 1.0;
  for (std::size_t k = 0; k < scene.planes.size(); ++k) {
    const PlaneContact& p = scene.planes[k];
    sys.walls.push_back({p.name.empty() ? "plane" + std::to_string(k) : p.name, p.point, p.normal.normalized(),
                         p.restitution});
  }
  return sys;
}

HardSphereOptions hard_sphere_options(const Scene& scene, const SimulationOptions& run) {
  HardSphereOptions o;
  o.t0 = run.t0;
  o.t_end = run.t_end;
  o.output_interval = run.output_interval;
  o.max_recorded_events = static_cast<std::size_t>(scene.output.max_events);
  return o;
}

}  // namespace lagrangian::scene::detail
