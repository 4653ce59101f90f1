// Inspection of particle scenes (`lagrangian inspect`), and the test for
// the exact event-driven engine.

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "json_object.hpp"
#include "lagrangian/integrate/detail/point_momenta_monitor.hpp"
#include "lagrangian/mechanics/constraints.hpp"
#include "particle_engine.hpp"
#include "particle_model.hpp"

namespace lagrangian::scene::detail {

bool event_driven_eligible(const Scene& scene) {
  // The conditions Scene::validate() demands of engine = "event_driven".
  if (scene.model || !scene.box || !scene.sphere_contacts || !scene.sphere_contacts->bodies.empty()) return false;
  for (const auto& kind : scene.declared())
    if (kind != "sphere_contacts" && kind != "plane_contacts" && kind != "box_contacts") return false;
  return std::all_of(scene.bodies.begin(), scene.bodies.end(), [](const Body& b) { return b.radius > 0; });
}

namespace {

/// The bodies (the first 20 in the text, all in the JSON): m, R, r, v, p.
void inspect_bodies(const Scene& scene, std::ostringstream& os, JsonObject& js) {
  const int n = static_cast<int>(scene.bodies.size());
  const int shown = std::min(n, 20);
  for (int i = 0; i < shown; ++i) {
    const Body& b = scene.bodies[static_cast<std::size_t>(i)];
    os << "  " << b.name << ": m = " << b.mass << " kg";
    if (b.radius > 0) os << ", R = " << b.radius << " m";
    os << ", r = (" << b.position.transpose() << ") m, v = (" << b.velocity.transpose() << ") m/s"
       << ", p = m v = (" << (b.mass * b.velocity).transpose() << ") kg*m/s\n";
  }
  if (n > shown) os << "  … " << n - shown << " more\n";
  {
    std::vector<std::string> items;
    for (const Body& b : scene.bodies) {
      JsonObject bj;
      bj.string("name", b.name);
      bj.number("mass", b.mass);
      bj.number("radius", b.radius);
      bj.raw("position", json_numbers(b.position.data(), 3));
      bj.raw("velocity", json_numbers(b.velocity.data(), 3));
      const Eigen::Vector3d p = b.mass * b.velocity;
      bj.raw("momentum", json_numbers(p.data(), 3));
      items.push_back(bj.str());
    }
    js.raw("bodies", json_array(items));
  }
}

/// Degrees of freedom from the rank of the constraint Jacobian at the state x (t0).
void inspect_constraints(const std::vector<particles::Row>& rows, const std::vector<double>& x, int n,
                         std::ostringstream& os, JsonObject& js) {
  Eigen::MatrixXd C;
  particles::jacobian(rows, x.data(), 3 * n, C);
  const int rank = lagrangian::detail::numeric_rank(C);
  os << "constraints  " << rows.size() << " holonomic";
  if (!rows.empty()) {
    os << " (";
    for (std::size_t k = 0; k < rows.size(); ++k) os << (k ? ", " : "") << rows[k].name;
    os << ")";
  }
  os << "\n";
  os << "rank         " << rank << " (redundant constraints: " << static_cast<int>(rows.size()) - rank << ")\n";
  os << "DOF          " << 3 * n - rank << " = " << 3 * n << " coordinates − rank " << rank << "\n";
  {
    JsonObject cj;
    cj.integer("coordinates", 3 * n);
    std::vector<std::string> names;
    for (const auto& r : rows) names.push_back(r.name);
    cj.raw("holonomic", json_strings(names));
    cj.integer("rank", rank);
    cj.integer("redundant", static_cast<int>(rows.size()) - rank);
    cj.integer("degrees_of_freedom", 3 * n - rank);
    js.raw("constraints", cj.str());
  }
}

/// Conserved quantities: what no declared effect can change.
std::vector<std::string> conserved_quantities(const Scene& scene) {
  std::vector<std::string> conserved;
  const bool walls = !scene.planes.empty() || scene.box.has_value();
  const bool anchored = std::any_of(scene.links.begin(), scene.links.end(), [](const Link& l) { return l.b.empty(); }) ||
                        !scene.surfaces.empty() ||
                        std::any_of(scene.springs.begin(), scene.springs.end(), [](const Spring& s) { return s.b.empty(); });
  const bool drag = !scene.linear_drag.empty() || !scene.quadratic_drag.empty();
  const bool lossy_contacts = (scene.sphere_contacts && scene.sphere_contacts->restitution < 1) ||
                              std::any_of(scene.planes.begin(), scene.planes.end(),
                                          [](const PlaneContact& p) { return p.restitution < 1; }) ||
                              (scene.box && scene.box->restitution < 1);
  if (!drag) conserved.push_back(lossy_contacts ? "E = T + V between impacts (impacts with e < 1 remove energy)"
                                                : "E = T + V (no dissipative effect declared)");
  if (!walls && !anchored && !drag) {
    if (!scene.gravity) {
      conserved.push_back("linear momentum P (no external force)");
      conserved.push_back("angular momentum L (internal forces are central)");
    } else {
      conserved.push_back("the components of P perpendicular to g (gravity is the only external force)");
      conserved.push_back("the component of L along g about any point");
    }
  }
  return conserved;
}

}  // namespace

std::string inspect_particles(const Scene& scene, bool as_json) {
  particles::ParticleModel sys(scene);
  std::ostringstream os;
  os.precision(6);
  const int n = sys.bodies();
  JsonObject js;  // the same facts as JSON (inspect --json)
  js.string("scene", scene.name);
  js.string("description", scene.description);
  const std::string engine =
      scene.run.engine == "auto" ? (event_driven_eligible(scene) ? "event_driven" : "ode") : scene.run.engine;
  js.string("engine", engine);
  js.number("t0", scene.run.t0);
  os << "scene        " << scene.name << "\n";
  if (!scene.description.empty()) os << "description  " << scene.description << "\n";
  os << "engine       " << engine << "\n";
  os << "bodies       " << n << " (" << 3 * n << " Cartesian coordinates)\n";
  inspect_bodies(scene, os, js);
  // Degrees of freedom from the rank of the constraint Jacobian at t0.
  const auto& rows = sys.rows();
  const std::vector<double> x = initial_state(scene);
  inspect_constraints(rows, x, n, os, js);
  // P and L about the origin, summed as the runs sum them.
  lagrangian::detail::PointMomenta momenta({0.0, 0.0, 0.0});
  for (const Body& b : scene.bodies) momenta.add(b.mass, b.position.data(), b.velocity.data());
  const Eigen::Map<const Eigen::Vector3d> P(momenta.linear().data()), L(momenta.angular().data());
  os << "momentum     P = (" << P.transpose() << ") kg*m/s, L about the origin = (" << L.transpose() << ") kg*m^2/s\n";
  const double T = sys.kinetic(x.data()), V = sys.potential(x.data());
  os << "energy       T = " << T << " J, V = " << V << " J, E = T + V = " << T + V << " J\n";
  js.raw("P", json_numbers(P.data(), 3));
  js.raw("L", json_numbers(L.data(), 3));
  {
    JsonObject e;
    e.number("T", T);
    e.number("V", V);
    e.number("E", T + V);
    js.raw("energy", e.str());
  }

  const std::vector<std::string> conserved = conserved_quantities(scene);
  os << "conserved    " << (conserved.empty() ? std::string("none detected") : conserved.front()) << "\n";
  for (std::size_t k = 1; k < conserved.size(); ++k) os << "             " << conserved[k] << "\n";

  const auto declared = scene.declared();
  os << "active       ";
  if (declared.empty()) os << "none (free flight)";
  for (std::size_t k = 0; k < declared.size(); ++k) os << (k ? ", " : "") << declared[k];
  os << "\n";
  js.raw("conserved", json_strings(conserved));
  js.raw("active", json_strings(declared));
  return as_json ? js.str() + "\n" : os.str();
}

}  // namespace lagrangian::scene::detail

