// Scenes whose [model] is stated by expressions (TextModelSpec): read, run
// and inspected like a built-in model, and checked against one.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/io.hpp"
#include "lagrangian/scene/run.hpp"

namespace {

using namespace lagrangian::scene;

// Runs here write nothing: ctest runs these tests side by side, and a
// shared output directory would have one run remove another's files.
RunResult run_quietly(const Scene& scene) {
  RunControls quiet;
  quiet.write_outputs = false;
  return run(scene, quiet);
}

const char* kOutputsOff = R"toml(
[run]
t_end = 5.0
rtol = 1e-12
atol = 1e-12
[output]
# (the runs write nothing: run_quietly)
trajectory = false
plots = false
animation = false
)toml";

// The state and parameters both spherical pendulums below share.
const char* kStateAndParameters = R"toml(
q = [1.0, 0.0]
qd = [0.0, 2.0]
[model.parameters]
m = 1.5
l = 0.8
g = 9.81
)toml";

std::string spherical_text(const std::string& kinetic) {
  return std::string("name = \"spherical pendulum\"\n") + kOutputsOff + R"toml(
[model]
coordinates = ["theta", "phi"]
units = ["rad", "rad"]
kinetic = ")toml" + kinetic + R"toml("
potential = "-m*g*l*cos(theta)")toml" + kStateAndParameters;
}

TEST(TextScene, RunsAsTheBuiltInSphericalPendulumDoes) {
  const Scene text = parse_scene(spherical_text("0.5*m*l^2*(theta_dot^2 + sin(theta)^2*phi_dot^2)"));
  ASSERT_TRUE(text.model && text.model->text);
  const Scene built_in = parse_scene(std::string("name = \"built-in\"\n") + kOutputsOff +
                                     "[model]\nname = \"spherical_pendulum\"" + kStateAndParameters);
  const RunResult a = run_quietly(text), b = run_quietly(built_in);
  EXPECT_EQ(a.engine, "model");
  ASSERT_EQ(a.q_final.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(a.q_final[i], b.q_final[i], 1e-9);
    EXPECT_NEAR(a.qd_final[i], b.qd_final[i], 1e-9);
  }
  EXPECT_TRUE(a.report.conservative);
  EXPECT_LE(a.report.energy_drift_max, 1e-9);
  EXPECT_EQ(a.report.coordinates, (std::vector<std::string>{"theta", "phi"}));
}

TEST(TextScene, InspectShowsTheMomentaAndTheCyclicCoordinate) {
  const std::string out = inspect(parse_scene(spherical_text("0.5*m*l^2*(theta_dot^2 + sin(theta)^2*phi_dot^2)")));
  // p_φ = m l² sin²θ φ̇ = 1.5 · 0.64 · sin²(1) · 2 at the initial state.
  const double p_phi = 1.5 * 0.64 * std::sin(1.0) * std::sin(1.0) * 2.0;
  char expected[64];
  std::snprintf(expected, sizeof expected, "p_phi = %.12g kg*m^2/s (conserved)", p_phi);
  EXPECT_NE(out.find(expected), std::string::npos) << out;
  EXPECT_NE(out.find("text::TextModel"), std::string::npos) << out;
  // The state table has a row per coordinate, with p: the row of φ ends in p_φ.
  char row_end[64];
  std::snprintf(row_end, sizeof row_end, "%.12g  kg*m^2/s\n", p_phi);
  const std::size_t state = out.find("Initial state");
  ASSERT_NE(state, std::string::npos);
  EXPECT_NE(out.find("\n  theta ", state), std::string::npos) << out;
  const std::size_t phi_row = out.find("\n  phi ", state);
  ASSERT_NE(phi_row, std::string::npos) << out;
  EXPECT_EQ(out.find(row_end, phi_row), out.find('\n', phi_row + 1) - std::string(row_end).size() + 1) << out;
}

std::string with_points(const std::string& points) {
  std::string toml = spherical_text("0.5*m*l^2*(theta_dot^2 + sin(theta)^2*phi_dot^2)");
  toml.replace(toml.find("[model.parameters]"), 0, points);
  return toml;
}

const char* kBob = R"toml(
[[model.points]]
name = "bob"
mass = 1.5
x = "l*sin(theta)*cos(phi)"
y = "l*sin(theta)*sin(phi)"
z = "-l*cos(theta)"
)toml";

TEST(TextScene, PointsArePlacedByTheirExpressions) {
  const Scene scene = parse_scene(with_points(kBob));
  const auto& entry = detail::text_entry();
  const double t[2] = {0.0, 1.0}, q[4] = {1.0, 0.0, 0.4, 2.5};
  std::vector<double> xyz;
  const lagrangian::view::Figure f = entry.picture(*scene.model, t, q, 2, xyz);
  ASSERT_EQ(f.bodies.size(), 1u);
  EXPECT_EQ(f.bodies[0].name, "bob");
  EXPECT_TRUE(f.rods.empty());  // rods not asked for
  EXPECT_EQ(f.up[2], 1.0);
  ASSERT_EQ(xyz.size(), 6u);
  const double l = 0.8;
  for (int r = 0; r < 2; ++r) {
    const double th = q[2 * r], ph = q[2 * r + 1];
    EXPECT_NEAR(xyz[3 * r + 0], l * std::sin(th) * std::cos(ph), 1e-15);
    EXPECT_NEAR(xyz[3 * r + 1], l * std::sin(th) * std::sin(ph), 1e-15);
    EXPECT_NEAR(xyz[3 * r + 2], -l * std::cos(th), 1e-15);
  }
}

// The bob of mass m at θ = 1, φ = 0 moving with φ̇ = 2 (l = 0.8 m):
// r = (l sin θ, 0, −l cos θ), v = (0, l sin θ φ̇, 0), so P = m v and
// L = m r × v = m (l² sin θ cos θ φ̇, 0, l² sin² θ φ̇): L_z is p_φ.
TEST(TextScene, InspectSumsThePointMassesIntoPAndL) {
  const std::string out = inspect(parse_scene(with_points(kBob)));
  const double m = 1.5, l = 0.8, th = 1.0, w = 2.0;
  char expected[256];
  std::snprintf(expected, sizeof expected,
                "P = [0, %.12g, 0] kg*m/s, L = [%.12g, 0, %.12g] kg*m^2/s about the origin; centre of mass [%.12g, 0, "
                "%.12g] m",
                m * l * std::sin(th) * w, m * l * l * std::sin(th) * std::cos(th) * w,
                m * l * l * std::sin(th) * std::sin(th) * w, l * std::sin(th), -l * std::cos(th));
  EXPECT_NE(out.find(expected), std::string::npos) << expected << "\n" << out;
}

// Called without validation, the registry's entry words a bad expression
// as validation does.
TEST(TextScene, TheEntryNamesABadExpressionAsValidationDoes) {
  Scene s = parse_scene(spherical_text("0.5*m*theta_dot^2"));
  s.model->text->kinetic = "0.5*m*thta_dot^2";  // (parse_scene validates; the entry alone does not)
  std::string key, message;
  try {
    detail::text_entry().inspect(*s.model, 0.0, false);
  } catch (const SceneError& e) {
    key = e.key();
    message = e.message();
  }
  EXPECT_EQ(key, "model.kinetic");
  EXPECT_EQ(message.substr(0, 66), "column 7: unknown name 'thta_dot', did you mean 'theta_dot'?; the ");
}

std::string error_of(const std::string& toml) {
  try {
    parse_scene(toml, "pendulum.toml").validate();
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(TextScene, ErrorsNameTheFileLineKeyAndColumn) {
  const std::string unknown = error_of(spherical_text("0.5*m*l^2*(thta_dot^2 + sin(theta)^2*phi_dot^2)"));
  EXPECT_NE(unknown.find("pendulum.toml:16"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("model.kinetic"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("column 12: unknown name 'thta_dot'"), std::string::npos) << unknown;
  std::string named = spherical_text("0.5*m*l^2*theta_dot^2");
  named.replace(named.find("[model]\n"), 8, "[model]\nname = \"spherical_pendulum\"\n");
  EXPECT_NE(error_of(named).find("model.name"), std::string::npos) << error_of(named);
  std::string no_q = spherical_text("0.5*m*l^2*theta_dot^2");
  no_q.erase(no_q.find("q = [1.0, 0.0]\n"), 15);
  EXPECT_NE(error_of(no_q).find("model.q: a model stated by expressions needs its initial coordinates q"),
            std::string::npos)
      << error_of(no_q);
  std::string moving = kBob;
  moving.replace(moving.find("l*sin(theta)*cos(phi)"), 21, "theta_dot");
  EXPECT_NE(error_of(with_points(moving)).find("model.points[0].x: a point's position depends on q and t only"),
            std::string::npos)
      << error_of(with_points(moving));
  EXPECT_NE(error_of(with_points(std::string(kBob) + kBob)).find("model.points[1].name: 'bob' names two points"),
            std::string::npos)
      << error_of(with_points(std::string(kBob) + kBob));
}

}  // namespace

namespace {

// A run of `model` (a [model] table's body) with the outputs off, to t_end.
RunResult run_model_text(const std::string& model, double t_end) {
  std::string s = std::string("name = \"points\"\n") + kOutputsOff + "[model]\n" + model;
  const std::string from = "t_end = 5.0", to = "t_end = " + std::to_string(t_end);
  s.replace(s.find(from), from.size(), to);
  return run_quietly(parse_scene(s));
}

// Two statements of one system: a built-in particle model (particles() at
// its Cartesian coordinates) and its text twin with a point of the same
// mass at each particle. The run reports the same P0, L0, the same verdicts
// on which components are conserved (from the forces and, for the tilted
// plane, the contact's impulse along its normal) and keeps them both.
void expect_same_momenta(const std::string& name, const std::string& parameters, const std::string& state,
                         const std::string& text) {
  SCOPED_TRACE(name);
  const RunResult a = run_model_text("name = \"" + name + "\"\n" + state + parameters, 2.0);
  std::string twin = text;  // (the state goes where "STATE" is, before the tables)
  twin.replace(twin.find("STATE"), 5, state);
  const RunResult b = run_model_text(twin + parameters, 2.0);
  ASSERT_TRUE(a.report.has_particles);
  ASSERT_TRUE(b.report.has_particles);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(b.report.linear_momentum_initial[k], a.report.linear_momentum_initial[k], 1e-14) << k;
    EXPECT_NEAR(b.report.angular_momentum_initial[k], a.report.angular_momentum_initial[k], 1e-14) << k;
    EXPECT_EQ(b.report.linear_momentum_conserved[k], a.report.linear_momentum_conserved[k]) << "P, axis " << k;
    EXPECT_EQ(b.report.angular_momentum_conserved[k], a.report.angular_momentum_conserved[k]) << "L, axis " << k;
  }
  EXPECT_LE(b.report.linear_momentum_drift_max, 1e-9);
  EXPECT_LE(b.report.angular_momentum_drift_max, 1e-9);
}

TEST(TextScene, PointMassesGiveTheRunPAndLAsTheBuiltInParticlesDo) {
  expect_same_momenta("two_body", "[model.parameters]\nm1 = 1.0\nm2 = 2.0\nk = 1.5\n",
                      "q = [0.0, 0.0, 1.0, 0.2]\nqd = [0.1, -0.3, 0.0, 0.7]\n", R"toml(
coordinates = ["x1", "y1", "x2", "y2"]
kinetic = "0.5*m1*(x1_dot^2 + y1_dot^2) + 0.5*m2*(x2_dot^2 + y2_dot^2)"
potential = "-k/sqrt((x2 - x1)^2 + (y2 - y1)^2)"
STATE
[[model.points]]
name = "one"
mass = 1.0
x = "x1"
y = "y1"
[[model.points]]
name = "two"
mass = 2.0
x = "x2"
y = "y2"
)toml");
  // A plane tilted about y: its impulses have a part along x (P_x is not
  // conserved although gravity is along −z); P_y is.
  const RunResult tilted = run_model_text("name = \"ball_and_plane\"\nq = [0.0, 0.0, 1.0]\nqd = [0.3, 0.2, 0.0]\n"
                                          "[model.parameters]\nnx = 0.6\nnz = 0.8\n",
                                          1.0);
  EXPECT_FALSE(tilted.report.linear_momentum_conserved[0]);
  EXPECT_TRUE(tilted.report.linear_momentum_conserved[1]);
  expect_same_momenta("ball_and_plane",
                      "[model.parameters]\nm = 1.0\nR = 0.1\ng = 9.81\nnx = 0.6\nny = 0.0\nnz = 0.8\noffset = 0.0\n",
                      "q = [0.0, 0.0, 1.0]\nqd = [0.3, 0.2, 0.0]\n", R"toml(
coordinates = ["x", "y", "z"]
kinetic = "0.5*m*(x_dot^2 + y_dot^2 + z_dot^2)"
potential = "m*g*z"
STATE
[[model.contacts]]
gap = "nx*x + ny*y + nz*z - offset - R"
restitution = 0.5
[[model.points]]
name = "ball"
mass = 1.0
x = "x"
y = "y"
z = "z"
)toml");
}

// The double pendulum's bobs (1 kg, 2 kg on 1 m, 0.5 m rods): P and L from
// r(q) by the chain rule, P = Σ m (∂r/∂θ) θ̇, against the closed form; the
// pivot and gravity change P_x, P_y and L_z, and the run says so.
TEST(TextScene, PointsOfAPendulumReportPAndLWithTheirVerdicts) {
  const RunResult r = run_model_text(R"toml(
coordinates = ["a", "b"]
kinetic = "0.5*(m1 + m2)*l1^2*a_dot^2 + 0.5*m2*l2^2*b_dot^2 + m2*l1*l2*a_dot*b_dot*cos(a - b)"
potential = "-(m1 + m2)*g*l1*cos(a) - m2*g*l2*cos(b)"
q = [0.7, -0.4]
qd = [1.1, 0.3]
[[model.points]]
name = "one"
mass = 1.0
x = "l1*sin(a)"
y = "-l1*cos(a)"
[[model.points]]
name = "two"
mass = 2.0
x = "l1*sin(a) + l2*sin(b)"
y = "-l1*cos(a) - l2*cos(b)"
[model.parameters]
m1 = 1.0
m2 = 2.0
l1 = 1.0
l2 = 0.5
g = 9.81
)toml",
                                     1.0);
  ASSERT_TRUE(r.report.has_particles);
  const double a = 0.7, b = -0.4, ad = 1.1, bd = 0.3, l1 = 1.0, l2 = 0.5, m1 = 1.0, m2 = 2.0;
  const double x1 = l1 * std::sin(a), y1 = -l1 * std::cos(a), x2 = x1 + l2 * std::sin(b), y2 = y1 - l2 * std::cos(b);
  const double vx1 = l1 * std::cos(a) * ad, vy1 = l1 * std::sin(a) * ad;
  const double vx2 = vx1 + l2 * std::cos(b) * bd, vy2 = vy1 + l2 * std::sin(b) * bd;
  EXPECT_NEAR(r.report.linear_momentum_initial[0], m1 * vx1 + m2 * vx2, 1e-14);
  EXPECT_NEAR(r.report.linear_momentum_initial[1], m1 * vy1 + m2 * vy2, 1e-14);
  EXPECT_NEAR(r.report.angular_momentum_initial[2], m1 * (x1 * vy1 - y1 * vx1) + m2 * (x2 * vy2 - y2 * vx2), 1e-14);
  EXPECT_FALSE(r.report.linear_momentum_conserved[0]);
  EXPECT_FALSE(r.report.linear_momentum_conserved[1]);
  EXPECT_TRUE(r.report.linear_momentum_conserved[2]);  // a plane motion: P_z = 0 throughout
  EXPECT_FALSE(r.report.angular_momentum_conserved[2]);
  EXPECT_FALSE(r.report.linear_momentum_reason[0].empty());
}

// A bead on the wire y = 0 and a wall x + y = 1 across it: the wall's
// impulse is along its normal (1, 1)/√2, but the wire takes up its y part,
// so the bead's P_y stays 0: the contact changes P_x only.
TEST(TextScene, AContactsImpulseOnPointsHoldsTheConstraints) {
  const RunResult r = run_model_text(R"toml(
coordinates = ["x", "y"]
kinetic = "0.5*m*(x_dot^2 + y_dot^2)"
potential = "0"
holonomic = ["y"]
q = [0.2, 0.0]
qd = [1.0, 0.0]
[[model.contacts]]
gap = "1 - x - y"
restitution = 1.0
[[model.points]]
name = "bead"
mass = 2.0
x = "x"
y = "y"
[model.parameters]
m = 2.0
)toml",
                                     2.0);
  ASSERT_TRUE(r.report.has_particles);
  EXPECT_FALSE(r.report.linear_momentum_conserved[0]) << r.report.linear_momentum_reason[0];
  EXPECT_TRUE(r.report.linear_momentum_conserved[1]) << r.report.linear_momentum_reason[1];
  EXPECT_LE(r.report.linear_momentum_drift_max, 1e-12);
  EXPECT_EQ(r.report.impacts, 1u);
}

}  // namespace
