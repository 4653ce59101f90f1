// Scene files: every key reaches its field, absent keys keep their defaults,
// and every kind of bad input gets one line naming the file, the line, the
// key path and the offending value. The same checks on scenes built in C++.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/io.hpp"
#include "lagrangian/scene/models.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::scene;
namespace fs = std::filesystem;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// The message of the SceneError that parsing `text` as "bad.toml" throws.
std::string parse_error(const std::string& text) {
  try {
    parse_scene(text, "bad.toml");
  } catch (const SceneError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("<not a SceneError> ") + e.what();
  }
  return "<no error>";
}

/// The message of the SceneError that validating `s` throws.
std::string validate_error(const Scene& s) {
  try {
    s.validate();
  } catch (const SceneError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("<not a SceneError> ") + e.what();
  }
  return "<no error>";
}

/// Checks that parsing `text` fails with "bad.toml:<line>: <key>: ..." and
/// that the message contains every one of `parts`.
void expect_error(const std::string& text, int line, const std::string& key, std::vector<std::string> parts) {
  const std::string msg = parse_error(text);
  const std::string head = "bad.toml:" + std::to_string(line) + ": " + (key.empty() ? "" : key + ": ");
  if (std::getenv("SHOW_SCENE_ERRORS")) std::printf("%s\n", msg.c_str());
  EXPECT_EQ(msg.rfind(head, 0), 0u) << "expected the message to start with '" << head << "'\n got: " << msg;
  for (const auto& p : parts) EXPECT_TRUE(contains(msg, p)) << "missing '" << p << "' in: " << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
}

/// Checks that validating `s` fails with "scene: <key>: ..." containing `parts`.
void expect_cpp_error(const Scene& s, const std::string& key, std::vector<std::string> parts) {
  const std::string msg = validate_error(s);
  const std::string head = "scene: " + key + ": ";
  if (std::getenv("SHOW_SCENE_ERRORS")) std::printf("%s\n", msg.c_str());
  EXPECT_EQ(msg.rfind(head, 0), 0u) << "expected the message to start with '" << head << "'\n got: " << msg;
  for (const auto& p : parts) EXPECT_TRUE(contains(msg, p)) << "missing '" << p << "' in: " << msg;
}

/// A valid scene file of one body (line 1: [[bodies]]).
const std::string kOneBody = "[[bodies]]\nname = \"ball\"\nmass = 1\n";

Scene one_body_scene() {
  Scene s;
  s.bodies.push_back({.name = "ball", .mass = 1.0});
  return s;
}

// -- round trip and defaults ---------------------------------------------------------

TEST(SceneParse, EveryParticleKeyReachesItsField) {
  const Scene s = parse_scene(R"(name = "everything"
description = "every key of a particle scene"

[run]
method = "rk4"
engine = "ode"
t0 = 1
t_end = 3.5
dt = 2e-3
rtol = 1e-8
atol = 1e-9
output_interval = 0.05
max_steps = 1000
stabilization = "baumgarte"
baumgarte_omega = 20.0

[output]
directory = "results"
trajectory = false
plots = true
formats = ["svg"]
animation = false

[[bodies]]
name = "ball"
mass = 0.1
radius = 0.05
position = [0.5, 0.5, 0.5]
velocity = [1.0, 0.0, 0.0]

[[bodies]]
name = "bob"
mass = 2
position = [0.5, 0.5, 0.875]
velocity = [0.25, 0, 0]

[[bodies]]
name = "bead"
mass = 0.5
position = [0.25, 0.25, 0.125]
velocity = [0.0, 1.0, 0.0]

[[bodies]]
name = "planet"
mass = 3
radius = 0.1
position = [0.75, 0.75, 0.75]
velocity = [0.0, 0.5, 0.0]

[gas]
count = 8
mass = 1e-3
radius = 0.01
speed = 2.0
seed = 7
prefix = "g"

[gravity]
g = [0, 0, -1.62]

[newtonian_gravity]
G = 1e-3

[[springs]]
name = "s1"
a = "ball"
b = "planet"
stiffness = 100.0
rest_length = 0.2

[[springs]]
a = "bead"
anchor = [0, 0, 0]
stiffness = 5

[[linear_drag]]
coefficient = 0.1
bodies = ["ball"]

[[quadratic_drag]]
coefficient = 0.01

[[links]]
name = "rod"
a = "bob"
anchor = [0.5, 0.5, 1.0]
length = 0.125

[[links]]
a = "ball"
b = "bob"

[[surfaces]]
name = "table"
body = "bead"
kind = "plane"
point = [0, 0, 0.125]
normal = [0, 0, 1]

[[surfaces]]
body = "planet"
kind = "sphere"
centre = [0.5, 0.75, 0.75]
radius = 0.25

[contacts.spheres]
restitution = 0.5
bodies = ["ball", "planet", "g1"]

[[contacts.planes]]
name = "floor"
point = [0, 0, 0]
normal = [0, 0, 2]
restitution = 0.8
bodies = ["ball"]

[[contacts.planes]]
point = [0, 0, -1]

[contacts.box]
min = [0, 0, 0]
max = [1, 1, 1]
restitution = 0.9
)",
                              "every.toml");
  EXPECT_EQ(s.name, "everything");
  EXPECT_EQ(s.description, "every key of a particle scene");
  EXPECT_EQ(s.run.method, Method::rk4);
  EXPECT_EQ(s.run.engine, "ode");
  EXPECT_EQ(s.run.t0, 1.0);
  EXPECT_EQ(s.run.t_end, 3.5);
  EXPECT_EQ(s.run.dt, 2e-3);
  EXPECT_EQ(s.run.rtol, 1e-8);
  EXPECT_EQ(s.run.atol, 1e-9);
  EXPECT_EQ(s.run.output_interval, 0.05);
  EXPECT_EQ(s.run.max_steps, 1000u);
  EXPECT_EQ(s.run.stabilization, Stabilization::baumgarte);
  EXPECT_EQ(s.run.baumgarte_omega, 20.0);
  EXPECT_EQ(s.output.directory, "results");
  EXPECT_FALSE(s.output.trajectory);
  EXPECT_TRUE(s.output.plots);
  EXPECT_FALSE(s.output.png);
  EXPECT_TRUE(s.output.svg);
  EXPECT_FALSE(s.output.animation);

  ASSERT_EQ(s.bodies.size(), 4u);
  EXPECT_EQ(s.bodies[0].name, "ball");
  EXPECT_EQ(s.bodies[0].mass, 0.1);
  EXPECT_EQ(s.bodies[0].radius, 0.05);
  EXPECT_EQ(s.bodies[0].position, Vec3(0.5, 0.5, 0.5));
  EXPECT_EQ(s.bodies[0].velocity, Vec3(1, 0, 0));
  EXPECT_EQ(s.bodies[1].name, "bob");
  EXPECT_EQ(s.bodies[1].mass, 2.0);
  EXPECT_EQ(s.bodies[1].radius, 0.0);
  EXPECT_EQ(s.bodies[1].velocity, Vec3(0.25, 0, 0));
  EXPECT_EQ(s.bodies[3].position, Vec3(0.75, 0.75, 0.75));

  ASSERT_TRUE(s.gas.has_value());
  EXPECT_EQ(s.gas->count, 8);
  EXPECT_EQ(s.gas->mass, 1e-3);
  EXPECT_EQ(s.gas->radius, 0.01);
  EXPECT_EQ(s.gas->speed, 2.0);
  EXPECT_EQ(s.gas->seed, 7u);
  EXPECT_EQ(s.gas->prefix, "g");

  ASSERT_TRUE(s.gravity.has_value());
  EXPECT_EQ(s.gravity->g, Vec3(0, 0, -1.62));
  ASSERT_TRUE(s.newtonian_gravity.has_value());
  EXPECT_EQ(s.newtonian_gravity->G, 1e-3);

  ASSERT_EQ(s.springs.size(), 2u);
  EXPECT_EQ(s.springs[0].name, "s1");
  EXPECT_EQ(s.springs[0].a, "ball");
  EXPECT_EQ(s.springs[0].b, "planet");
  EXPECT_EQ(s.springs[0].stiffness, 100.0);
  EXPECT_EQ(s.springs[0].rest_length, 0.2);
  EXPECT_EQ(s.springs[1].name, "");
  EXPECT_EQ(s.springs[1].b, "");
  EXPECT_EQ(s.springs[1].anchor, Vec3(0, 0, 0));
  EXPECT_EQ(s.springs[1].stiffness, 5.0);
  EXPECT_EQ(s.springs[1].rest_length, 0.0);

  ASSERT_EQ(s.linear_drag.size(), 1u);
  EXPECT_EQ(s.linear_drag[0].coefficient, 0.1);
  EXPECT_EQ(s.linear_drag[0].bodies, std::vector<std::string>{"ball"});
  ASSERT_EQ(s.quadratic_drag.size(), 1u);
  EXPECT_EQ(s.quadratic_drag[0].coefficient, 0.01);
  EXPECT_TRUE(s.quadratic_drag[0].bodies.empty());

  ASSERT_EQ(s.links.size(), 2u);
  EXPECT_EQ(s.links[0].name, "rod");
  EXPECT_EQ(s.links[0].a, "bob");
  EXPECT_EQ(s.links[0].b, "");
  EXPECT_EQ(s.links[0].anchor, Vec3(0.5, 0.5, 1.0));
  EXPECT_EQ(s.links[0].length, 0.125);
  EXPECT_EQ(s.links[1].b, "bob");
  EXPECT_TRUE(std::isnan(s.links[1].length));

  ASSERT_EQ(s.surfaces.size(), 2u);
  EXPECT_EQ(s.surfaces[0].name, "table");
  EXPECT_EQ(s.surfaces[0].body, "bead");
  EXPECT_EQ(s.surfaces[0].kind, Surface::Kind::plane);
  EXPECT_EQ(s.surfaces[0].point, Vec3(0, 0, 0.125));
  EXPECT_EQ(s.surfaces[0].normal, Vec3(0, 0, 1));
  EXPECT_EQ(s.surfaces[1].kind, Surface::Kind::sphere);
  EXPECT_EQ(s.surfaces[1].point, Vec3(0.5, 0.75, 0.75));
  EXPECT_EQ(s.surfaces[1].radius, 0.25);

  ASSERT_TRUE(s.sphere_contacts.has_value());
  EXPECT_EQ(s.sphere_contacts->restitution, 0.5);
  EXPECT_EQ(s.sphere_contacts->bodies, (std::vector<std::string>{"ball", "planet", "g1"}));
  ASSERT_EQ(s.planes.size(), 2u);
  EXPECT_EQ(s.planes[0].name, "floor");
  EXPECT_EQ(s.planes[0].point, Vec3(0, 0, 0));
  EXPECT_EQ(s.planes[0].normal, Vec3(0, 0, 2));
  EXPECT_EQ(s.planes[0].restitution, 0.8);
  EXPECT_EQ(s.planes[0].bodies, std::vector<std::string>{"ball"});
  EXPECT_EQ(s.planes[1].point, Vec3(0, 0, -1));
  EXPECT_EQ(s.planes[1].normal, Vec3(0, 0, 1));
  EXPECT_EQ(s.planes[1].restitution, 1.0);
  ASSERT_TRUE(s.box.has_value());
  EXPECT_EQ(s.box->min, Vec3(0, 0, 0));
  EXPECT_EQ(s.box->max, Vec3(1, 1, 1));
  EXPECT_EQ(s.box->restitution, 0.9);
  EXPECT_FALSE(s.model.has_value());

  EXPECT_EQ(s.declared(), (std::vector<std::string>{"uniform_gravity", "newtonian_gravity", "springs", "linear_drag",
                                                    "quadratic_drag", "links", "surfaces", "sphere_contacts",
                                                    "plane_contacts", "box_contacts"}));

  // Lines of keys, of array elements and of tables.
  EXPECT_EQ(s.source.file, "every.toml");
  EXPECT_EQ(s.source.line_of("name"), 1);
  EXPECT_EQ(s.source.line_of("run.t_end"), 8);
  EXPECT_EQ(s.source.line_of("bodies[0]"), 24);
  EXPECT_EQ(s.source.line_of("bodies[0].mass"), 26);
  EXPECT_EQ(s.source.line_of("bodies[1].radius"), 31);  // not written: its table's line
  EXPECT_EQ(s.source.line_of("contacts.box.max"), 122);
}

TEST(SceneParse, EveryModelKeyReachesItsField) {
  const ModelInfo* info = find_model("double_pendulum");
  ASSERT_NE(info, nullptr);
  ASSERT_EQ(info->coordinates.size(), 2u);
  const std::string p0 = info->parameters.at(0).name;
  const Scene s = parse_scene("[model]\nname = \"double_pendulum\"\nq = [0.5, 0.25]\nqd = [0, -1]\n"
                              "[model.parameters]\n" +
                              p0 + " = 2\n");
  ASSERT_TRUE(s.model.has_value());
  EXPECT_EQ(s.model->name, "double_pendulum");
  EXPECT_EQ(s.model->q, (std::vector<double>{0.5, 0.25}));
  EXPECT_EQ(s.model->qd, (std::vector<double>{0.0, -1.0}));
  EXPECT_EQ(s.model->parameters, (std::map<std::string, double>{{p0, 2.0}}));
  EXPECT_TRUE(s.bodies.empty());
  EXPECT_TRUE(s.declared().empty());
  EXPECT_EQ(s.source.line_of("model.parameters." + p0), 6);
}

TEST(SceneParse, AbsentKeysKeepTheirDefaults) {
  const Scene s = parse_scene(kOneBody);
  const Scene d;
  const RunSpec r;
  const OutputSpec o;
  EXPECT_EQ(s.name, d.name);
  EXPECT_EQ(s.description, "");
  EXPECT_EQ(s.run.method, r.method);
  EXPECT_EQ(s.run.engine, r.engine);
  EXPECT_EQ(s.run.t0, r.t0);
  EXPECT_EQ(s.run.t_end, r.t_end);
  EXPECT_EQ(s.run.dt, r.dt);
  EXPECT_EQ(s.run.rtol, r.rtol);
  EXPECT_EQ(s.run.atol, r.atol);
  EXPECT_EQ(s.run.output_interval, r.output_interval);
  EXPECT_EQ(s.run.max_steps, r.max_steps);
  EXPECT_EQ(s.run.stabilization, r.stabilization);
  EXPECT_EQ(s.run.baumgarte_omega, r.baumgarte_omega);
  EXPECT_EQ(s.output.directory, o.directory);
  EXPECT_EQ(s.output.trajectory, o.trajectory);
  EXPECT_EQ(s.output.plots, o.plots);
  EXPECT_EQ(s.output.animation, o.animation);
  EXPECT_EQ(s.output.png, o.png);
  EXPECT_EQ(s.output.svg, o.svg);
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0].radius, 0.0);
  EXPECT_EQ(s.bodies[0].position, Vec3::Zero());
  EXPECT_EQ(s.bodies[0].velocity, Vec3::Zero());
  EXPECT_FALSE(s.gas || s.gravity || s.newtonian_gravity || s.sphere_contacts || s.box || s.model);
  EXPECT_TRUE(s.declared().empty());
  EXPECT_EQ(s.source.file, "<scene>");

  // Defaults inside the optional tables.
  const Scene t = parse_scene(kOneBody + "[gravity]\n[newtonian_gravity]\n[contacts.spheres]\n"
                                         "[contacts.box]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
                                         "[gas]\ncount = 3\n");
  EXPECT_EQ(t.gravity->g, UniformGravity{}.g);
  EXPECT_EQ(t.newtonian_gravity->G, NewtonianGravity{}.G);
  EXPECT_EQ(t.sphere_contacts->restitution, 1.0);
  EXPECT_TRUE(t.sphere_contacts->bodies.empty());
  EXPECT_EQ(t.box->restitution, 1.0);
  const GasFill g;
  EXPECT_EQ(t.gas->count, 3);
  EXPECT_EQ(t.gas->mass, g.mass);
  EXPECT_EQ(t.gas->radius, g.radius);
  EXPECT_EQ(t.gas->speed, g.speed);
  EXPECT_EQ(t.gas->seed, g.seed);
  EXPECT_EQ(t.gas->prefix, g.prefix);
}

TEST(SceneParse, IntegersAreAcceptedForNumbers) {
  const Scene s = parse_scene(kOneBody + "position = [1, 2, 3]\n[run]\nt_end = 4\n");
  EXPECT_EQ(s.bodies[0].position, Vec3(1, 2, 3));
  EXPECT_EQ(s.run.t_end, 4.0);
}

// -- errors, one kind at a time ------------------------------------------------------

TEST(SceneErrors, TomlSyntaxErrorGivesTheParsersLine) {
  expect_error("[[bodies]]\nname = \"ball\"\nmass = = 1\n", 3, "", {"TOML syntax error"});
  // No key part: the message is "<file>:<line>: TOML syntax error: ...".
  EXPECT_EQ(parse_error("a = [1,\n\n\nb").rfind("bad.toml:4: TOML syntax error: ", 0), 0u)
      << parse_error("a = [1,\n\n\nb");
}

TEST(SceneErrors, UnknownKeySuggestsTheNearest) {
  expect_error("nmae = \"x\"\n" + kOneBody, 1, "nmae", {"unknown key 'nmae'; did you mean 'name'?"});
  expect_error(kOneBody + "mas = 2\n", 4, "bodies[0].mas", {"unknown key 'mas'; did you mean 'mass'?"});
  expect_error(kOneBody + "[run]\nt_ned = 2\n", 5, "run.t_ned", {"unknown key 't_ned'; did you mean 't_end'?"});
  expect_error(kOneBody + "[contacts.box]\nmin = [-1,-1,-1]\nmax = [1,1,1]\nrestitutoin = 1\n", 7,
               "contacts.box.restitutoin", {"did you mean 'restitution'?"});
  expect_error(kOneBody + "[contacts.sphere]\n", 4, "contacts.sphere", {"did you mean 'spheres'?"});
  expect_error(kOneBody + "[output]\nformat = [\"png\"]\n", 5, "output.format", {"did you mean 'formats'?"});
  // No close key: the valid keys are listed.
  expect_error(kOneBody + "colour = \"red\"\n", 4, "bodies[0].colour",
               {"unknown key 'colour'", "valid keys here: name, mass, radius, position, velocity"});
}

TEST(SceneErrors, UnknownModelParameterSuggestsFromTheModel) {
  const ModelInfo* info = find_model("double_pendulum");
  ASSERT_NE(info, nullptr);
  const std::string p0 = info->parameters.at(0).name;
  const std::string typo = p0 + "x";
  expect_error("[model]\nname = \"double_pendulum\"\n[model.parameters]\n" + typo + " = 1\n", 4,
               "model.parameters." + typo,
               {"unknown parameter '" + typo + "'", "double_pendulum", "did you mean '" + p0 + "'?"});
}

TEST(SceneErrors, UnknownModelSuggestsABuiltinModel) {
  expect_error("[model]\nname = \"double_pendulm\"\n", 2, "model.name",
               {"unknown model 'double_pendulm'", "did you mean 'double_pendulum'?"});
}

TEST(SceneErrors, MissingRequiredKey) {
  expect_error("[[bodies]]\nname = \"ball\"\n", 1, "bodies[0].mass", {"missing required key 'mass'"});
  expect_error(kOneBody + "[[springs]]\na = \"ball\"\nanchor = [0, 0, 0]\n", 4, "springs[0].stiffness",
               {"missing required key 'stiffness'"});
  expect_error(kOneBody + "[contacts.box]\nmin = [0, 0, 0]\n", 4, "contacts.box.max", {"missing required key 'max'"});
  expect_error(kOneBody + "[gas]\nmass = 1\n", 4, "gas.count", {"missing required key 'count'"});
  expect_error("[model]\nq = [1]\n", 1, "model.name", {"missing required key 'name'"});
}

TEST(SceneErrors, WrongType) {
  expect_error(kOneBody + "[run]\nt_end = \"abc\"\n", 5, "run.t_end", {"expected a number, got string \"abc\""});
  expect_error("[[bodies]]\nname = 3\nmass = 1\n", 2, "bodies[0].name", {"expected a string, got integer 3"});
  expect_error(kOneBody + "[output]\nplots = \"yes\"\n", 5, "output.plots",
               {"expected true or false, got string \"yes\""});
  expect_error(kOneBody + "[gas]\ncount = 2.5\n", 5, "gas.count", {"expected an integer, got float 2.5"});
  expect_error("run = 3\n" + kOneBody, 1, "run", {"expected a table, got integer 3"});
  expect_error("bodies = 1\n", 1, "bodies", {"expected an array of tables ([[bodies]]), got integer 1"});
  expect_error(kOneBody + "velocity = [1, \"x\", 0]\n", 4, "bodies[0].velocity[1]",
               {"expected a number, got string \"x\""});
}

TEST(SceneErrors, WrongVectorLength) {
  expect_error(kOneBody + "position = [1, 2]\n", 4, "bodies[0].position",
               {"expected an array of 3 numbers [x, y, z]", "got an array of 2 [1, 2]"});
  expect_error(kOneBody + "[gravity]\ng = [0, 0, -9.81, 1]\n", 5, "gravity.g",
               {"expected an array of 3 numbers", "got an array of 4 [0, 0, -9.81, 1]"});
  const ModelInfo* info = find_model("double_pendulum");
  ASSERT_NE(info, nullptr);
  expect_error("[model]\nname = \"double_pendulum\"\nq = [1, 2, 3]\n", 3, "model.q",
               {"expected " + std::to_string(info->coordinates.size()) + " values", "got 3"});
}

TEST(SceneErrors, NonPositiveMass) {
  expect_error("[[bodies]]\nname = \"ball\"\nmass = -1\n", 3, "bodies[0].mass", {"must be > 0, got -1"});
  expect_error(kOneBody + "[[bodies]]\nname = \"b\"\nmass = 0\n", 6, "bodies[1].mass", {"must be > 0, got 0"});
}

TEST(SceneErrors, NegativeRadiusAndZeroGasRadius) {
  expect_error(kOneBody + "radius = -0.25\n", 4, "bodies[0].radius", {"must be >= 0, got -0.25"});
  expect_error(kOneBody + "[contacts.box]\nmin = [0,0,0]\nmax = [1,1,1]\n[gas]\ncount = 2\nradius = 0\n", 9,
               "gas.radius", {"must be > 0", "spheres", "got 0"});
}

TEST(SceneErrors, RestitutionOutsideZeroOne) {
  expect_error(kOneBody + "[contacts.spheres]\nrestitution = 1.5\n", 5, "contacts.spheres.restitution",
               {"must be in [0, 1], got 1.5"});
  expect_error(kOneBody + "[[contacts.planes]]\nrestitution = -0.1\n", 5, "contacts.planes[0].restitution",
               {"must be in [0, 1], got -0.1"});
  expect_error(kOneBody + "[contacts.box]\nmin = [-1,-1,-1]\nmax = [1,1,1]\nrestitution = 2\n", 7,
               "contacts.box.restitution", {"got 2"});
}

TEST(SceneErrors, OverlappingSpheresInContact) {
  const std::string two = R"([[bodies]]
name = "a"
mass = 1
radius = 0.5
[[bodies]]
name = "b"
mass = 1
radius = 0.25
position = [0.5, 0, 0]
)";
  expect_error(two + "[contacts.spheres]\n", 9, "bodies[1].position",
               {"'a' and 'b' overlap", "distance 0.5 < R1 + R2 = 0.75"});
  // Not in contact with each other: no error.
  EXPECT_NO_THROW(parse_scene(two));
  EXPECT_NO_THROW(parse_scene(two + "[[bodies]]\nname = \"c\"\nmass = 1\nposition = [9, 0, 0]\n"
                                    "[contacts.spheres]\nbodies = [\"a\", \"c\"]\n"));
  // Touching is allowed.
  EXPECT_NO_THROW(parse_scene(R"([[bodies]]
name = "a"
mass = 1
radius = 0.1
[[bodies]]
name = "b"
mass = 1
radius = 0.2
position = [0.1, 0.2, 0.2]
[contacts.spheres]
)"));
}

TEST(SceneErrors, BodyOutsideTheBox) {
  expect_error(R"([[bodies]]
name = "ball"
mass = 1
radius = 0.25
position = [0.9, 0.5, 0.5]
[contacts.box]
min = [0, 0, 0]
max = [1, 1, 1]
)",
               5, "bodies[0].position",
               {"'ball' (radius 0.25)", "[0.9, 0.5, 0.5]", "outside the box", "x + R = 1.15 > max 1"});
}

TEST(SceneErrors, TEndNotAfterT0) {
  expect_error(kOneBody + "[run]\nt0 = 2\nt_end = 1\n", 6, "run.t_end", {"greater than t0 = 2, got 1"});
  expect_error(kOneBody + "[run]\nt_end = 0\n", 5, "run.t_end", {"greater than t0 = 0, got 0"});
}

TEST(SceneErrors, TolerancesMustBePositive) {
  expect_error(kOneBody + "[run]\nrtol = 0\n", 5, "run.rtol", {"must be > 0, got 0"});
  expect_error(kOneBody + "[run]\natol = -1e-9\n", 5, "run.atol", {"must be > 0, got -1e-09"});
}

TEST(SceneErrors, StepMustBePositive) {
  expect_error(kOneBody + "[run]\ndt = 0\n", 5, "run.dt", {"must be > 0, got 0"});
  expect_error(kOneBody + "[run]\ndt = -0.5\n", 5, "run.dt", {"must be > 0, got -0.5"});
}

TEST(SceneErrors, UnknownStepperSuggestsTheNearest) {
  expect_error(kOneBody + "[run]\nmethod = \"dopri\"\n", 5, "run.method",
               {"unknown stepper 'dopri'; did you mean 'dopri5'?"});
  expect_error(kOneBody + "[run]\nmethod = \"euler\"\n", 5, "run.method", {"unknown stepper 'euler'", "rk4"});
}

TEST(SceneErrors, UnknownEngine) {
  expect_error(kOneBody + "[run]\nengine = \"odee\"\n", 5, "run.engine",
               {"unknown engine 'odee'; did you mean 'ode'?"});
}

TEST(SceneErrors, OtherUnknownNames) {
  expect_error(kOneBody + "[run]\nstabilization = \"projektion\"\n", 5, "run.stabilization",
               {"unknown stabilization 'projektion'; did you mean 'projection'?"});
  expect_error(kOneBody + "[output]\nformats = [\"png\", \"jpg\"]\n", 5, "output.formats[1]",
               {"unknown format 'jpg'"});
  expect_error(kOneBody + "[[surfaces]]\nbody = \"ball\"\nkind = \"plain\"\n", 6, "surfaces[0].kind",
               {"unknown surface kind 'plain'; did you mean 'plane'?"});
}

TEST(SceneErrors, ReferenceToAMissingBody) {
  expect_error(kOneBody + "[[springs]]\na = \"bal\"\nanchor = [0, 0, 1]\nstiffness = 1\n", 5, "springs[0].a",
               {"no body named 'bal'; did you mean 'ball'?"});
  expect_error(kOneBody + "[[linear_drag]]\ncoefficient = 1\nbodies = [\"ball\", \"wall\"]\n", 6,
               "linear_drag[0].bodies[1]", {"no body named 'wall'"});
  expect_error(kOneBody + "[contacts.spheres]\nbodies = [\"ball\", \"bowl\"]\n", 5, "contacts.spheres.bodies[1]",
               {"no body named 'bowl'"});
  expect_error(kOneBody + "[[links]]\na = \"ball\"\nb = \"ghost\"\n", 6, "links[0].b", {"no body named 'ghost'"});
  expect_error(kOneBody + "[[surfaces]]\nbody = \"nobody\"\nkind = \"plane\"\n", 5, "surfaces[0].body",
               {"no body named 'nobody'"});
}

TEST(SceneErrors, DuplicateBodyNames) {
  expect_error(kOneBody + "[[bodies]]\nname = \"ball\"\nmass = 2\n", 5, "bodies[1].name",
               {"duplicate body name 'ball'", "bodies[0]"});
}

TEST(SceneErrors, SpringOrLinkWithBothOrNeitherEnd) {
  expect_error(kOneBody + "[[bodies]]\nname = \"b\"\nmass = 1\n[[springs]]\na = \"ball\"\nb = \"b\"\n"
                          "anchor = [0, 0, 0]\nstiffness = 1\n",
               10, "springs[0].anchor", {"either 'b'", "not both"});
  expect_error(kOneBody + "[[springs]]\na = \"ball\"\nstiffness = 1\n", 4, "springs[0]",
               {"give either 'b' (a second body) or 'anchor'"});
  expect_error(kOneBody + "[[links]]\na = \"ball\"\n", 4, "links[0]", {"give either 'b'"});
}

TEST(SceneErrors, LinkLengthDisagreesWithTheInitialDistance) {
  expect_error(kOneBody + "position = [0, 0, -1]\n[[links]]\na = \"ball\"\nanchor = [0, 0, 0]\nlength = 1.5\n", 8,
               "links[0].length", {"length 1.5", "initial distance 1", "'ball'", "anchor [0, 0, 0]"});
  // Equal to the distance: fine; absent: the distance.
  EXPECT_NO_THROW(
      parse_scene(kOneBody + "position = [0, 0, -1]\n[[links]]\na = \"ball\"\nanchor = [0, 0, 0]\nlength = 1\n"));
  expect_error(kOneBody + "[[links]]\na = \"ball\"\nanchor = [0, 0, 0]\n", 4, "links[0]", {"initial distance", "0"});
}

TEST(SceneErrors, BodyOffItsSurfaceOrNotTangent) {
  expect_error(kOneBody + "position = [0, 0, 0.5]\n[[surfaces]]\nbody = \"ball\"\nkind = \"plane\"\n", 4,
               "bodies[0].position", {"'ball'", "[0, 0, 0.5]", "not on surfaces[0]", "distance 0.5"});
  expect_error(kOneBody + "position = [2, 0, 0]\n[[surfaces]]\nbody = \"ball\"\nkind = \"sphere\"\nradius = 1\n", 4,
               "bodies[0].position", {"not on surfaces[0]", "sphere of radius 1", "distance from the centre is 2"});
  expect_error(kOneBody + "velocity = [1, 0, 0.5]\n[[surfaces]]\nbody = \"ball\"\nkind = \"plane\"\n", 4,
               "bodies[0].velocity", {"velocity [1, 0, 0.5]", "not tangent to surfaces[0]", "normal component 0.5"});
  expect_error(kOneBody + "position = [1, 0, 0]\nvelocity = [1, 1, 0]\n[[surfaces]]\nbody = \"ball\"\n"
                          "kind = \"sphere\"\ncentre = [0, 0, 0]\nradius = 1\n",
               5, "bodies[0].velocity", {"not tangent", "normal component 1"});
  expect_error(kOneBody + "[[surfaces]]\nbody = \"ball\"\nkind = \"sphere\"\nnormal = [0, 0, 1]\nradius = 1\n", 7,
               "surfaces[0].normal", {"'normal' is for kind = \"plane\""});
}

TEST(SceneErrors, ModelTogetherWithBodies) {
  expect_error(kOneBody + "[gravity]\n[model]\nname = \"double_pendulum\"\n", 5, "model",
               {"either a built-in [model] or bodies", "bodies, uniform_gravity"});
}

TEST(SceneErrors, NeitherBodiesNorModel) {
  const std::string msg = parse_error("name = \"empty\"\n[run]\nt_end = 1\n");
  EXPECT_EQ(msg.rfind("bad.toml: bodies: ", 0), 0u) << msg;
  EXPECT_TRUE(contains(msg, "needs bodies ([[bodies]] or [gas]) or a built-in [model]")) << msg;
}

TEST(SceneErrors, GasWithoutABox) {
  expect_error(kOneBody + "[gas]\ncount = 10\n", 4, "gas", {"needs [contacts.box]"});
}

TEST(SceneErrors, GasCountCappedAndGasThatDoesNotFit) {
  const std::string box = "[contacts.box]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n";
  expect_error(box + "[gas]\ncount = 100000000000\n", 5, "gas.count", {"at most 10000000", "got 100000000000"});
  expect_error(box + "[gas]\ncount = 0\n", 5, "gas.count", {"must be an integer >= 1, got 0"});
  expect_error(box + "[gas]\ncount = 28\nradius = 0.2\n", 5, "gas.count",
               {"28 spheres of radius 0.2 do not fit", "room for 8"});
  EXPECT_NO_THROW(parse_scene(box + "[gas]\ncount = 8\nradius = 0.2\n"));
  // The largest count, in a box big enough: checked without placing it.
  EXPECT_NO_THROW(parse_scene("[contacts.box]\nmin = [0, 0, 0]\nmax = [1000, 1000, 1000]\n[gas]\ncount = 10000000\n"));
}

TEST(SceneErrors, EventDrivenEngineNeedsFreeFlightInABox) {
  const std::string box = "[contacts.box]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n";
  expect_error(kOneBody + box + "[gravity]\n[run]\nengine = \"event_driven\"\n", 9, "run.engine",
               {"free flight", "uniform_gravity"});
  expect_error(kOneBody + "[run]\nengine = \"event_driven\"\n", 5, "run.engine", {"needs [contacts.box]"});
  expect_error(kOneBody + box + "[[links]]\na = \"ball\"\nanchor = [0, 0, 0.5]\n[run]\nmethod = \"event_driven\"\n",
               11, "run.method", {"links"});
  // It makes every pair of spheres collide, so the scene must declare that, and its bodies are spheres.
  expect_error(kOneBody + "radius = 0.1\n" + box + "[run]\nengine = \"event_driven\"\n", 9, "run.engine",
               {"[contacts.spheres]"});
  expect_error(kOneBody + box + "[contacts.spheres]\n[run]\nengine = \"event_driven\"\n", 1, "bodies[0].radius",
               {"radius must be > 0", "got 0"});
  EXPECT_NO_THROW(parse_scene(kOneBody + "radius = 0.1\n" + box +
                              "[contacts.spheres]\n[[contacts.planes]]\npoint = [0, 0, -1]\n"
                              "[run]\nengine = \"event_driven\"\n"));
}

TEST(SceneErrors, UnreadableFile) {
  const fs::path dir = fs::temp_directory_path() / "lagrangian_test_scene_parse_unreadable";
  fs::create_directories(dir);
  const std::string missing = (dir / "no_such_scene.toml").string();
  try {
    load_scene(missing);
    ADD_FAILURE() << "no error for a missing file";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(missing + ": cannot read the scene file", 0), 0u) << e.what();
    EXPECT_TRUE(contains(e.what(), "No such file")) << e.what();
  }
  try {
    load_scene(dir.string());
    ADD_FAILURE() << "no error for a directory";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(dir.string() + ": cannot read the scene file: it is a directory", 0), 0u)
        << e.what();
  }
  // A readable file is parsed with its path in the messages.
  const std::string good = (dir / "ok.toml").string();
  {
    std::ofstream(good) << kOneBody << "radius = -1\n";
  }
  try {
    load_scene(good);
    ADD_FAILURE() << "no error for a negative radius";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(good + ":4: bodies[0].radius: ", 0), 0u) << e.what();
  }
  fs::remove_all(dir);
}

TEST(SceneErrors, NanAndInfinityAreRejected) {
  expect_error(kOneBody + "[run]\nt_end = nan\n", 5, "run.t_end", {"finite", "got nan"});
  expect_error(kOneBody + "position = [inf, 0, 0]\n", 4, "bodies[0].position[0]", {"finite", "got inf"});
  expect_error(kOneBody + "[gravity]\ng = [0, 0, -inf]\n", 5, "gravity.g[2]", {"got -inf"});
  expect_error(kOneBody + "[[links]]\na = \"ball\"\nanchor = [0, 0, 1]\nlength = nan\n", 7, "links[0].length",
               {"got nan"});
}

TEST(SceneErrors, MessagesAreSceneErrorsAndOptionErrors) {
  try {
    parse_scene(kOneBody + "mass = 2\n", "dup.toml");
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line(), 4);  // TOML itself rejects the duplicate key
    EXPECT_EQ(e.key(), "");
  }
  try {
    parse_scene(kOneBody + "radius = -1\n", "r.toml");
    ADD_FAILURE();
  } catch (const OptionError& e) {
    const auto& se = dynamic_cast<const SceneError&>(e);
    EXPECT_EQ(se.key(), "bodies[0].radius");
    EXPECT_EQ(se.line(), 4);
  }
}

// -- the same checks on scenes built in C++ ---------------------------------------------

TEST(SceneCpp, InvalidValuesNameTheKeyWithoutAFile) {
  {
    Scene s = one_body_scene();
    s.bodies[0].mass = -1;
    expect_cpp_error(s, "bodies[0].mass", {"must be > 0, got -1"});
  }
  {
    Scene s = one_body_scene();
    s.bodies[0].radius = -0.5;
    expect_cpp_error(s, "bodies[0].radius", {"must be >= 0, got -0.5"});
  }
  {
    Scene s = one_body_scene();
    s.run.t_end = -1;
    expect_cpp_error(s, "run.t_end", {"greater than t0 = 0, got -1"});
  }
  {
    Scene s = one_body_scene();
    s.run.rtol = 0;
    expect_cpp_error(s, "run.rtol", {"must be > 0, got 0"});
  }
  {
    Scene s = one_body_scene();
    s.run.dt = -1;
    expect_cpp_error(s, "run.dt", {"got -1"});
  }
  {
    Scene s = one_body_scene();
    s.run.rtol = 2;  // the options' own check, under the scene's key
    expect_cpp_error(s, "run.rtol", {"must be < 1, got 2"});
  }
  {
    Scene s = one_body_scene();
    s.run.engine = "fast";
    expect_cpp_error(s, "run.engine", {"unknown engine 'fast'"});
  }
  {
    Scene s = one_body_scene();
    s.bodies[0].position.x() = std::numeric_limits<double>::quiet_NaN();
    expect_cpp_error(s, "bodies[0].position", {"must be finite, got [nan, 0, 0]"});
  }
  {
    Scene s = one_body_scene();
    s.bodies.push_back({.name = "ball", .mass = 2});
    expect_cpp_error(s, "bodies[1].name", {"duplicate body name 'ball'"});
  }
  {
    Scene s = one_body_scene();
    s.sphere_contacts = SphereContacts{.restitution = 1.5};
    expect_cpp_error(s, "contacts.spheres.restitution", {"got 1.5"});
  }
  {
    Scene s = one_body_scene();
    s.bodies[0].radius = 1;
    s.bodies.push_back({.name = "b", .mass = 1, .radius = 1, .position = {1, 0, 0}});
    s.sphere_contacts = SphereContacts{};
    expect_cpp_error(s, "bodies[1].position", {"'ball' and 'b' overlap", "distance 1 < R1 + R2 = 2"});
  }
  {
    Scene s = one_body_scene();
    s.bodies[0].position = {2, 0, 0};
    s.box = BoxContact{};
    expect_cpp_error(s, "bodies[0].position", {"outside the box", "x + R = 2 > max 1"});
  }
  {
    Scene s = one_body_scene();
    s.springs.push_back({.a = "bal", .stiffness = 1});
    expect_cpp_error(s, "springs[0].a", {"no body named 'bal'; did you mean 'ball'?"});
  }
  {
    Scene s = one_body_scene();
    s.links.push_back({.a = "ball", .anchor = {0, 0, 1}, .length = 2});
    expect_cpp_error(s, "links[0].length", {"length 2", "initial distance 1"});
  }
  {
    Scene s = one_body_scene();
    s.bodies[0].velocity = {0, 0, 1};
    s.surfaces.push_back({.body = "ball"});
    expect_cpp_error(s, "bodies[0].velocity", {"not tangent"});
  }
  {
    Scene s = one_body_scene();
    s.model = ModelSpec{.name = "double_pendulum"};
    expect_cpp_error(s, "model", {"not both"});
  }
  {
    Scene s;
    expect_cpp_error(s, "bodies", {"needs bodies"});
  }
  {
    Scene s;
    s.model = ModelSpec{.name = "double_pendulm"};
    expect_cpp_error(s, "model.name", {"did you mean 'double_pendulum'?"});
  }
  {
    Scene s;
    s.gas = GasFill{.count = 5};
    expect_cpp_error(s, "gas", {"needs [contacts.box]"});
  }
  {
    Scene s;
    s.gas = GasFill{.count = GasFill::max_count + 1};
    s.box = BoxContact{};
    expect_cpp_error(s, "gas.count", {"at most 10000000"});
  }
  {
    Scene s;
    s.gas = GasFill{.count = 10, .radius = 0};
    s.box = BoxContact{};
    expect_cpp_error(s, "gas.radius", {"must be > 0", "got 0"});
  }
  {
    Scene s = one_body_scene();
    s.gravity = UniformGravity{};
    s.box = BoxContact{.min = {-1, -1, -1}};
    s.run.engine = "event_driven";
    expect_cpp_error(s, "run.engine", {"uniform_gravity"});
  }
  {
    Scene s = one_body_scene();
    s.planes.push_back({.normal = {0, 0, 0}});
    expect_cpp_error(s, "contacts.planes[0].normal", {"non-zero", "[0, 0, 0]"});
  }
  {
    Scene s = one_body_scene();
    s.box = BoxContact{.min = {0, 2, 0}, .max = {1, 1, 1}};
    expect_cpp_error(s, "contacts.box.max", {"on y: max 1 <= min 2"});
  }
}

TEST(SceneCpp, AValidSceneAndItsErrorObject) {
  Scene s;
  s.bodies.push_back({.name = "ball", .mass = 0.2, .position = {0, 0, 1}, .velocity = {10, 0, 10}});
  s.gravity = UniformGravity{};
  s.run.t_end = 2.0;
  EXPECT_NO_THROW(s.validate());
  s.bodies[0].mass = 0;
  try {
    s.validate();
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "bodies[0].mass");
    EXPECT_EQ(e.line(), 0);
    EXPECT_STREQ(e.what(), "scene: bodies[0].mass: must be > 0, got 0");
  }
}

TEST(SceneCpp, DeclaredListsOnlyWhatIsDeclaredInOrder) {
  Scene s = one_body_scene();
  EXPECT_TRUE(s.declared().empty());
  s.box = BoxContact{};
  s.linear_drag.push_back({.coefficient = 1});
  s.gravity = UniformGravity{};
  EXPECT_EQ(s.declared(), (std::vector<std::string>{"uniform_gravity", "linear_drag", "box_contacts"}));
}

// -- helpers -------------------------------------------------------------------------------

TEST(SceneHelpers, NearestByEditDistance) {
  EXPECT_EQ(nearest("mas", {"name", "mass", "radius"}), "mass");
  EXPECT_EQ(nearest("dopri", stepper_names()), "dopri5");
  EXPECT_EQ(nearest("xyz", {"name", "mass"}), "");
  EXPECT_EQ(nearest("anything", {}), "");
  EXPECT_EQ(nearest("velocty", {"position", "velocity"}), "velocity");
  EXPECT_EQ(nearest(std::string(5000, 'a'), {std::string(5000, 'a')}), "");  // too long to compare: no hint
}

TEST(SceneHelpers, LineOfFallsBackToTheParent) {
  SourceMap m;
  m.file = "f.toml";
  m.lines = {{"bodies[2]", 10}, {"bodies[2].mass", 12}, {"run", 3}};
  EXPECT_EQ(m.line_of("bodies[2].mass"), 12);
  EXPECT_EQ(m.line_of("bodies[2].radius"), 10);
  EXPECT_EQ(m.line_of("bodies[2].position[1]"), 10);
  EXPECT_EQ(m.line_of("run.t_end"), 3);
  EXPECT_EQ(m.line_of("gas.count"), 0);
  EXPECT_EQ(SceneError("gas.count", "bad", m).what(), std::string("f.toml: gas.count: bad"));
  EXPECT_EQ(SceneError("run.t_end", "bad", m).what(), std::string("f.toml:3: run.t_end: bad"));
}

// -- expand_gas ------------------------------------------------------------------------------

Scene gas_scene(int count, double radius, double speed, std::uint64_t seed) {
  Scene s;
  s.box = BoxContact{.min = {-1, 0, 2}, .max = {1, 0.5, 3}};
  s.gas = GasFill{.count = count, .mass = 0.01, .radius = radius, .speed = speed, .seed = seed, .prefix = "m"};
  s.sphere_contacts = SphereContacts{};
  return s;
}

TEST(SceneGas, ExpandGasPlacesCountSpheresWithoutOverlapInsideTheBox) {
  for (const int count : {1, 2, 7, 100, 1000}) {
    Scene s = gas_scene(count, 0.01, 3.0, 42);
    ASSERT_NO_THROW(s.validate());
    s.expand_gas();
    EXPECT_FALSE(s.gas.has_value());
    ASSERT_EQ(s.bodies.size(), static_cast<std::size_t>(count));
    std::set<std::string> names;
    Vec3 momentum = Vec3::Zero();
    double sq = 0;
    for (const Body& b : s.bodies) {
      names.insert(b.name);
      EXPECT_EQ(b.mass, 0.01);
      EXPECT_EQ(b.radius, 0.01);
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(b.position[a] - b.radius, s.box->min[a]) << b.name;
        EXPECT_LE(b.position[a] + b.radius, s.box->max[a]) << b.name;
      }
      momentum += b.mass * b.velocity;
      sq += b.velocity.squaredNorm();
    }
    EXPECT_EQ(names.size(), static_cast<std::size_t>(count));
    EXPECT_TRUE(names.count("m1") && names.count("m" + std::to_string(count)));
    for (std::size_t i = 0; i < s.bodies.size(); ++i)
      for (std::size_t j = i + 1; j < s.bodies.size(); ++j)
        ASSERT_GE((s.bodies[i].position - s.bodies[j].position).norm(), 2 * 0.01) << i << " " << j;
    EXPECT_LE(momentum.norm(), 1e-12 * 0.01 * 3.0 * count);
    if (count > 1) {
      EXPECT_NEAR(std::sqrt(sq / count), 3.0, 1e-12);
    }
    // The expanded scene is valid as it is.
    EXPECT_NO_THROW(s.validate()) << count;
  }
}

TEST(SceneGas, SameSeedSameGasOtherSeedOtherGas) {
  Scene a = gas_scene(50, 0.02, 1.0, 9), b = gas_scene(50, 0.02, 1.0, 9), c = gas_scene(50, 0.02, 1.0, 10);
  a.expand_gas();
  b.expand_gas();
  c.expand_gas();
  bool differ = false;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    EXPECT_EQ(a.bodies[i].position, b.bodies[i].position);
    EXPECT_EQ(a.bodies[i].velocity, b.bodies[i].velocity);
    differ = differ || a.bodies[i].velocity != c.bodies[i].velocity;
  }
  EXPECT_TRUE(differ);
}

TEST(SceneGas, GasKeepsTheExplicitBodiesAndTheirNames) {
  Scene s = gas_scene(20, 0.01, 1.0, 1);
  s.bodies.push_back({.name = "piston", .mass = 1, .radius = 0.05, .position = {0.9, 0.25, 2.5}});
  ASSERT_NO_THROW(s.validate());
  s.expand_gas();
  ASSERT_EQ(s.bodies.size(), 21u);
  EXPECT_EQ(s.bodies[0].name, "piston");
  EXPECT_EQ(s.bodies[1].name, "m1");
  EXPECT_EQ(s.bodies[20].name, "m20");

  // A gas name taken by an explicit body.
  Scene t = gas_scene(20, 0.01, 1.0, 1);
  t.bodies.push_back({.name = "m3", .mass = 1, .position = {0.5, 0.25, 2.5}});
  expect_cpp_error(t, "gas.prefix", {"'m3'", "bodies[0]"});
}

TEST(SceneGas, ExplicitSphereOverlappingTheGasIsAnError) {
  Scene s = gas_scene(1000, 0.01, 1.0, 1);
  s.bodies.push_back({.name = "big", .mass = 1, .radius = 0.2, .position = {0, 0.25, 2.5}});
  expect_cpp_error(s, "bodies[0].position", {"'big' and 'm", "(gas) overlap"});
  // Without sphere contacts they pass through each other.
  s.sphere_contacts.reset();
  EXPECT_NO_THROW(s.validate());
}

TEST(SceneGas, GasMoleculesInConstraintsAndLists) {
  // Gas names are bodies: in lists, links and (at rest) surfaces.
  Scene s = gas_scene(8, 0.01, 1.0, 5);
  s.linear_drag.push_back({.coefficient = 1, .bodies = {"m1", "m8"}});
  EXPECT_NO_THROW(s.validate());
  s.linear_drag[0].bodies.push_back("m9");
  expect_cpp_error(s, "linear_drag[0].bodies[2]", {"no body named 'm9'"});
  s.linear_drag.clear();
  s.surfaces.push_back({.body = "m2", .kind = Surface::Kind::plane, .point = {0, 0, 0}, .normal = {1, 0, 0}});
  expect_cpp_error(s, "surfaces[0].body", {"'m2' is a gas molecule", "gas.speed = 0"});
  s.gas->speed = 0;
  expect_cpp_error(s, "gas", {"'m2'", "not on surfaces[0]"});
}

TEST(SceneGas, AbsurdSizesAreRejectedNotComputed) {
  Scene s = gas_scene(1000, 0.01, 1e307, 1);
  expect_cpp_error(s, "gas.speed", {"too large"});
  Scene t = gas_scene(10, 0.01, 1, 1);
  t.box = BoxContact{.min = {-1e308, 0, 0}, .max = {1e308, 1, 1}};
  expect_cpp_error(t, "contacts.box.max", {"too large"});
  Scene u = one_body_scene();
  u.planes.push_back({.normal = {1e300, 0, 0}});
  expect_cpp_error(u, "contacts.planes[0].normal", {"finite length"});
}

TEST(SceneGas, ParsedGasExpands) {
  Scene s = parse_scene(R"([contacts.box]
min = [0, 0, 0]
max = [1, 1, 1]
[contacts.spheres]
[gas]
count = 27
radius = 0.05
speed = 2
seed = 3
prefix = "n"
)");
  s.expand_gas();
  ASSERT_EQ(s.bodies.size(), 27u);
  EXPECT_EQ(s.bodies[26].name, "n27");
  EXPECT_NO_THROW(s.validate());
}

// -- the example scenes ------------------------------------------------------------------------

TEST(SceneExamples, EveryExampleSceneParses) {
  const fs::path dir = fs::path(LAGRANGIAN_SOURCE_DIR) / "examples" / "scenes";
  if (!fs::is_directory(dir)) GTEST_SKIP() << dir << " does not exist";
  int n = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {  // text/ too
    if (entry.path().extension() != ".toml") continue;
    ++n;
    EXPECT_NO_THROW({
      try {
        load_scene(entry.path().string());
      } catch (const std::exception& e) {
        ADD_FAILURE() << e.what();
        throw;
      }
    }) << entry.path();
  }
  if (n == 0) GTEST_SKIP() << "no scene files in " << dir;
}

}  // namespace
