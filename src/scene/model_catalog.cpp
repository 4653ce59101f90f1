// The catalog of built-in models: names, descriptions, coordinates and
// parameters with their defaults and units. Plain data only: this file must
// not include the models or simulate.hpp (it is linked into light builds).
// Each default equals the default of the model's own constructor, except
// where a comment says otherwise; tests/test_scene_models.cpp checks them
// model by model.

#include <algorithm>
#include <string>
#include <vector>

#include "lagrangian/scene/models.hpp"

namespace lagrangian::scene {

namespace {

std::vector<ModelInfo> make_catalog() {
  std::vector<ModelInfo> c;

  // -- pendulums and central forces (models/lagrangian/models/pendulums.hpp) --
  c.push_back({"simple_pendulum",
               "Plane pendulum: point mass on a massless rod, theta from the downward vertical",
               {"theta"},
               {"rad"},
               {{"m", 1.0, "kg", "mass of the bob"},
                {"l", 1.0, "m", "length of the rod"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"}}});
  c.push_back({"harmonic_oscillator",
               "Harmonic oscillator: mass on a linear spring, x from the rest position (closed form)",
               {"x"},
               {"m"},
               {{"m", 1.0, "kg", "mass"}, {"k", 1.0, "N/m", "spring stiffness"}}});
  c.push_back({"double_pendulum",
               "Double pendulum: two point masses on massless rods, angles from the downward vertical",
               {"theta1", "theta2"},
               {"rad", "rad"},
               {{"m1", 1.0, "kg", "mass of the upper bob"},
                {"m2", 1.0, "kg", "mass of the lower bob"},
                {"l1", 1.0, "m", "length of the upper rod"},
                {"l2", 1.0, "m", "length of the lower rod"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"}}});
  c.push_back({"spherical_pendulum",
               "Spherical pendulum: polar angle theta from the downward vertical, azimuth phi (cyclic)",
               {"theta", "phi"},
               {"rad", "rad"},
               {{"m", 1.0, "kg", "mass of the bob"},
                {"l", 1.0, "m", "length of the rod"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"}}});
  c.push_back({"elastic_pendulum",
               "Elastic (spring) pendulum: radial distance r and angle theta of a mass on a spring",
               {"r", "theta"},
               {"m", "rad"},
               {{"m", 1.0, "kg", "mass of the bob"},
                {"k", 40.0, "N/m", "spring stiffness"},
                {"l0", 1.0, "m", "rest length of the spring"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"}}});
  c.push_back({"bead_on_rotating_hoop",
               "Bead on a hoop spinning at a constant rate about its vertical diameter (Jacobi integral conserved, "
               "T + V not)",
               {"theta"},
               {"rad"},
               {{"m", 1.0, "kg", "mass of the bead"},
                {"R", 0.5, "m", "radius of the hoop"},
                {"omega", 6.0, "rad/s", "spin rate of the hoop"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"}}});
  c.push_back({"kepler_polar",
               "Particle in the inverse-square field V = -k/r in plane polar coordinates (phi cyclic)",
               {"r", "phi"},
               {"m", "rad"},
               {{"m", 1.0, "kg", "mass of the particle"},
                {"k", 1.0, "J*m", "strength of the field, k = G M m"}}});
  c.push_back({"cart_pendulum",
               "Pendulum hanging from a cart that slides on a horizontal rail, held by a spring",
               {"x", "theta"},
               {"m", "rad"},
               {{"M", 2.0, "kg", "mass of the cart"},
                {"m", 1.0, "kg", "mass of the bob"},
                {"l", 1.0, "m", "length of the rod"},
                {"k", 10.0, "N/m", "stiffness of the spring holding the cart"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"}}});
  c.push_back({"driven_pendulum",
               "Pendulum whose pivot is driven vertically, y_p = a cos(Omega t): time-dependent Lagrangian",
               {"theta"},
               {"rad"},
               {{"m", 1.0, "kg", "mass of the bob"},
                {"l", 1.0, "m", "length of the rod"},
                {"a", 0.05, "m", "amplitude of the pivot's motion"},
                {"Omega", 30.0, "rad/s", "angular frequency of the drive"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"}}});
  c.push_back({"pendulum_chain_3",
               "Planar chain of three equal point masses on equal massless rods, angles from the downward vertical",
               {"theta1", "theta2", "theta3"},
               {"rad", "rad", "rad"},
               {{"m", 1.0, "kg", "mass of each bob"},
                {"l", 1.0, "m", "length of each rod"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"}}});

  // -- constrained systems (constrained.hpp) -----------------------------------
  c.push_back({"bead_on_rotating_wire",
               "Bead on a straight horizontal wire spinning about a vertical axis (rheonomic holonomic constraint); "
               "stops at the wire's end",
               {"x", "y"},
               {"m", "m"},
               {{"m", 1.0, "kg", "mass of the bead"},
                {"omega", 2.0, "rad/s", "spin rate of the wire"},
                {"L", 10.0, "m", "reach of the wire either side of the axis: the bead leaves its end at r = L"}}});
  c.push_back({"particle_on_sphere",
               "Particle on a sphere about the origin, gravity along -z: the spherical pendulum in Cartesian "
               "coordinates",
               {"x", "y", "z"},
               {"m", "m", "m"},
               {{"m", 1.0, "kg", "mass of the particle"},
                {"R", 1.0, "m", "radius of the sphere"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"}}});
  c.push_back({"atwood_machine",
               "Atwood machine: two masses on a string over a massless pulley, y1 + y2 = c; stops where a mass reaches "
               "the pulley",
               {"y1", "y2"},
               {"m", "m"},
               {{"m1", 3.0, "kg", "first mass"},
                {"m2", 1.0, "kg", "second mass"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"},
                {"c", 0.0, "m", "string constant: y1 + y2 = c"},
                {"d", 1.0, "m", "height of the pulley's axle above c/2: a mass reaching it stops the run"}}});
  c.push_back({"cartesian_double_pendulum",
               "Double pendulum in Cartesian coordinates with two rod constraints",
               {"x1", "y1", "x2", "y2"},
               {"m", "m", "m", "m"},
               {{"m1", 1.0, "kg", "mass of the upper bob"},
                {"m2", 1.0, "kg", "mass of the lower bob"},
                {"l1", 1.0, "m", "length of the upper rod"},
                {"l2", 1.0, "m", "length of the lower rod"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"}}});
  c.push_back({"knife_edge",
               "Knife edge (skate) on a horizontal plane: no sideslip, a nonholonomic (Pfaffian) constraint",
               {"x", "y", "phi"},
               {"m", "m", "rad"},
               {{"m", 1.0, "kg", "mass"},
                {"I", 0.1, "kg*m^2", "moment of inertia about the vertical"}}});

  // -- impacts (impacts.hpp) -----------------------------------------------------
  // SpheresOnLine, TwoSpheres and SpheresInBox have no default constructor;
  // their defaults are the registry's own.
  c.push_back({"direct_impact",
               "Direct impact of two smooth spheres on a line (Newton's law of restitution)",
               {"x1", "x2"},
               {"m", "m"},
               {{"m1", 1.0, "kg", "mass of sphere 1"},
                {"m2", 2.0, "kg", "mass of sphere 2"},
                {"r1", 0.1, "m", "radius of sphere 1"},
                {"r2", 0.1, "m", "radius of sphere 2"},
                {"e", 0.8, "1", "coefficient of restitution"}}});
  c.push_back({"newtons_cradle",
               "Newton's cradle: five equal spheres on a line, four touching, the first swung in",
               {"x1", "x2", "x3", "x4", "x5"},
               {"m", "m", "m", "m", "m"},
               {{"m", 0.1, "kg", "mass of each sphere"},
                {"r", 0.0125, "m", "radius of each sphere"},
                {"e", 1.0, "1", "coefficient of restitution"}}});
  c.push_back({"oblique_impact",
               "Oblique impact of two smooth spheres moving in a plane, no gravity",
               {"x1", "y1", "x2", "y2"},
               {"m", "m", "m", "m"},
               {{"m1", 1.0, "kg", "mass of sphere 1"},
                {"m2", 1.0, "kg", "mass of sphere 2"},
                {"r1", 0.1, "m", "radius of sphere 1"},
                {"r2", 0.1, "m", "radius of sphere 2"},
                {"e", 0.9, "1", "coefficient of restitution"}}});
  c.push_back({"ball_and_plane",
               "Smooth ball bouncing on a fixed plane n.r = offset (a floor by default) under gravity along -z",
               {"x", "y", "z"},
               {"m", "m", "m"},
               {{"m", 1.0, "kg", "mass of the ball"},
                {"R", 0.1, "m", "radius of the ball"},
                {"e", 0.5, "1", "coefficient of restitution"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"},
                {"nx", 0.0, "1", "plane normal, x component (normalised)"},
                {"ny", 0.0, "1", "plane normal, y component"},
                {"nz", 1.0, "1", "plane normal, z component"},
                {"offset", 0.0, "m", "plane offset d in n.r = d"}}});
  c.push_back({"spheres_in_box",
               "Three smooth discs in the box [0, W] x [0, H], colliding with the walls and each other",
               {"x1", "y1", "x2", "y2", "x3", "y3"},
               {"m", "m", "m", "m", "m", "m"},
               {{"m", 1.0, "kg", "mass of each disc"},
                {"r", 0.1, "m", "radius of each disc"},
                {"W", 2.0, "m", "width of the box"},
                {"H", 1.0, "m", "height of the box"},
                {"e_wall", 1.0, "1", "restitution against the walls"},
                {"e_pair", 1.0, "1", "restitution between discs"},
                {"g", 0.0, "m/s^2", "acceleration of gravity along -y"}}});

  // -- two bodies and projectiles (two_body.hpp, projectile.hpp) ------------------
  // TwoBody and RelativeMotion have no default constructor; k = 1 J*m with
  // unit masses gives an orbit of period 2*pi/sqrt(2) s (two_body) and
  // 2*pi s (kepler).
  c.push_back({"two_body",
               "Two bodies under Newtonian gravity V = -k/r in a plane",
               {"x1", "y1", "x2", "y2"},
               {"m", "m", "m", "m"},
               {{"m1", 1.0, "kg", "mass of body 1"},
                {"m2", 1.0, "kg", "mass of body 2"},
                {"k", 1.0, "J*m", "strength of the attraction, k = G m1 m2"}}});
  c.push_back({"kepler",
               "Reduced two-body problem: a body of reduced mass mu in V = -k/r, with a periapsis event",
               {"x", "y"},
               {"m", "m"},
               {{"mu", 1.0, "kg", "reduced mass m1 m2 / (m1 + m2)"},
                {"k", 1.0, "J*m", "strength of the attraction, k = G m1 m2"}}});
  c.push_back({"projectile",
               "Projectile over a plane through the launch point at angle beta, no drag; stops at landing",
               {"x", "y"},
               {"m", "m"},
               {{"m", 1.0, "kg", "mass"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"},
                {"beta", 0.0, "rad", "angle of the ground plane to the horizontal, |beta| < pi/2"}}});
  // The drag coefficients' defaults differ from the struct's (0): a drag
  // model needs a positive coefficient (with b = 0 the linear-drag closed form
  // divides 0 by 0); `projectile` is the model without drag.
  c.push_back({"projectile_linear_drag",
               "Projectile with linear air drag F = -b v; stops at landing",
               {"x", "y"},
               {"m", "m"},
               {{"m", 1.0, "kg", "mass"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"},
                {"beta", 0.0, "rad", "angle of the ground plane to the horizontal, |beta| < pi/2"},
                {"b", 0.1, "kg/s", "linear drag coefficient, > 0"}}});
  c.push_back({"projectile_quadratic_drag",
               "Projectile with quadratic air drag F = -c |v| v; stops at landing",
               {"x", "y"},
               {"m", "m"},
               {{"m", 1.0, "kg", "mass"},
                {"g", 9.81, "m/s^2", "acceleration of gravity"},
                {"beta", 0.0, "rad", "angle of the ground plane to the horizontal, |beta| < pi/2"},
                {"c", 0.01, "kg/m", "quadratic drag coefficient, > 0"}}});

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
