// The parameter columns ∂x(t)/∂p of particle scenes (src/scene/
// particle_parameters.cpp, particle_tangent.cpp), named by their scene
// keys: against closed forms differentiated by central differences (a
// projectile under linear drag, a body on a spring, a ball that bounces to
// rest on a tilted plane and slides, two spheres in a direct impact), and
// against central differences of plain runs (a double pendulum on links);
// the refusals name the parameter.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/scene/io.hpp"
#include "lagrangian/scene/run.hpp"
#include "particle_scenes.hpp"
#include "plane_slide.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::scene;

/// The columns of `names` at t_end (2n × names), without the initial state's.
Eigen::MatrixXd parameter_columns(const Scene& scene, const std::vector<std::string>& names,
                                  Eigen::VectorXd* state = nullptr) {
  SensitivityRequest request;
  request.parameters = names;
  request.initial_state = false;
  const SensitivityRun r = sensitivity(scene, request);
  EXPECT_EQ(r.model, "particles");
  EXPECT_EQ(r.result.parameters, names);
  if (state != nullptr) *state = r.result.states.back();
  return r.result.sensitivities.back();
}

/// The largest entry of |a − b| over the largest of |b| (or 1 when b is 0).
double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

// A 0.4 kg projectile under gravity G and linear drag b: with k = b/m,
//   v(t) = v0 e^(−kt) + (G/k)(1 − e^(−kt)),
//   r(t) = r0 + (v0 − G/k)(1 − e^(−kt))/k + G t/k,
// differentiated in (G_x, G_z, b, m) by central differences, at 1.5 s.
TEST(ParticleSensitivity, ProjectileUnderLinearDragHasTheClosedFormColumns) {
  const Scene scene = parse_scene(lagrangian_test::precise_scene("projectile with drag", 1.5, R"([[bodies]]
name = "ball"
mass = 0.4
position = [0.0, 0.5, 1.0]
velocity = [6.0, -1.0, 8.0]
[gravity]
g = [0.7, 0.0, -9.81]
[[linear_drag]]
coefficient = 0.12
)"));
  const double t = 1.5;
  const Eigen::Vector3d r0(0.0, 0.5, 1.0), v0(6.0, -1.0, 8.0);
  const auto closed_form = [&](const std::array<double, 4>& p) {
    const Eigen::Vector3d g(p[0], 0.0, p[1]);
    const double k = p[2] / p[3], decay = std::exp(-k * t);
    Eigen::VectorXd x(6);
    x << r0 + (v0 - g / k) * (1.0 - decay) / k + g * t / k, v0 * decay + (g / k) * (1.0 - decay);
    return x;
  };
  const Eigen::MatrixXd expected = lagrangian_test::central_differences(closed_form, std::array{0.7, -9.81, 0.12, 0.4});
  Eigen::VectorXd state;
  const Eigen::MatrixXd columns = parameter_columns(
      scene, {"gravity.g[0]", "gravity.g[2]", "linear_drag[0].coefficient", "bodies[0].mass"}, &state);
  EXPECT_LT((state - closed_form({0.7, -9.81, 0.12, 0.4})).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT(relative_error(columns, expected), 1e-8) << columns << "\n\n" << expected;
  EXPECT_GT(expected.col(2).cwiseAbs().maxCoeff(), 1.0);  // the drag moves the end by metres per kg/s
}

// A 0.5 kg body on a spring (k = 8 N/m, rest length L0 = 1 m) from an
// anchor at the origin, moving along the spring's line:
//   z(t) = L0 + (z0 − L0) cos ωt + (ż0/ω) sin ωt,  ω = √(k/m),
// differentiated in (k, L0, m), at 2 s; the columns of the other body of the
// scene (far away, on its own spring) are 0.
TEST(ParticleSensitivity, BodyOnASpringHasTheClosedFormColumns) {
  const Scene scene = parse_scene(lagrangian_test::precise_scene("springs", 2.0, R"([[bodies]]
name = "bob"
mass = 0.5
position = [0.0, 0.0, 1.3]
velocity = [0.0, 0.0, 0.4]
[[bodies]]
name = "other"
mass = 2.0
position = [5.0, 0.0, 0.0]
velocity = [0.0, 0.3, 0.0]
[[springs]]
a = "bob"
anchor = [0.0, 0.0, 0.0]
stiffness = 8.0
rest_length = 1.0
[[springs]]
a = "other"
anchor = [4.0, 0.0, 0.0]
stiffness = 3.0
rest_length = 0.0
)"));
  const double t = 2.0, z0 = 1.3, w0 = 0.4;
  const auto closed_form = [&](const std::array<double, 3>& p) {
    const double w = std::sqrt(p[0] / p[2]);
    Eigen::VectorXd x(2);
    x << p[1] + (z0 - p[1]) * std::cos(w * t) + w0 / w * std::sin(w * t),
        -(z0 - p[1]) * w * std::sin(w * t) + w0 * std::cos(w * t);
    return x;
  };
  const Eigen::MatrixXd expected = lagrangian_test::central_differences(closed_form, std::array{8.0, 1.0, 0.5});
  const Eigen::MatrixXd columns =
      parameter_columns(scene, {"springs[0].stiffness", "springs[0].rest_length", "bodies[0].mass"});
  ASSERT_EQ(columns.rows(), 12);
  Eigen::MatrixXd along_z(2, 3);
  along_z << columns.row(2), columns.row(8);  // z and ż of the bob
  EXPECT_LT(relative_error(along_z, expected), 1e-8) << along_z << "\n\n" << expected;
  Eigen::MatrixXd rest = columns;
  rest.row(2).setZero();
  rest.row(8).setZero();
  EXPECT_EQ(rest.cwiseAbs().maxCoeff(), 0.0) << columns;
}

// The ball on an incline (particle_scenes.hpp: 0.3 kg, R = 0.05 m, e = 0.5)
// bounces, comes to rest by the Zeno rule at about 1.05 s and slides: at
// 1.6 s its state is that of free fall projected on the plane,
//   r = P (r0 + v0 t + ½ G t²) + (n̂·p + R) n̂,  v = P (v0 + G t),
// P = I − n̂n̂ᵀ, whatever e and m. The columns of G, the plane's point p,
// R, e and m against it, through more than ten impacts and the rest.
TEST(ParticleSensitivity, BallRestingOnATiltedPlaneHasTheClosedFormColumns) {
  const Scene scene =
      parse_scene(lagrangian_test::precise_scene("ball on an incline", 1.6, lagrangian_test::kBallOnAnIncline));
  const double t = 1.6;
  const Eigen::Vector3d n(std::sin(0.3), 0.0, std::cos(0.3)), r0(0.2, 0.1, 0.6), v0(0.4, -0.3, 0.0);
  const auto closed_form = [&](const std::array<double, 9>& q) {
    const Eigen::Vector3d g(q[0], q[1], q[2]), p(q[3], q[4], q[5]);
    const Eigen::Matrix3d project = Eigen::Matrix3d::Identity() - n * n.transpose();
    Eigen::VectorXd x(6);
    x << project * (r0 + v0 * t + 0.5 * g * t * t) + (n.dot(p) + q[6]) * n, project * (v0 + g * t);
    return x;  // (q[7], q[8]: e and m, which it does not depend on)
  };
  const std::array<double, 9> at{0.0, 0.0, -9.81, 0.1, -0.2, 0.03, 0.05, 0.5, 0.3};
  const Eigen::MatrixXd expected = lagrangian_test::central_differences(closed_form, at);
  SensitivityRequest request;
  request.parameters = {"gravity.g[0]",
                        "gravity.g[1]",
                        "gravity.g[2]",
                        "contacts.planes[0].point[0]",
                        "contacts.planes[0].point[1]",
                        "contacts.planes[0].point[2]",
                        "bodies[0].radius",
                        "contacts.planes[0].restitution",
                        "bodies[0].mass"};
  request.initial_state = false;
  const SensitivityRun r = sensitivity(scene, request);
  EXPECT_GT(r.result.impacts, 10);
  EXPECT_LT((r.result.states.back() - closed_form(at)).cwiseAbs().maxCoeff(), 1e-9);
  const Eigen::MatrixXd& columns = r.result.sensitivities.back();
  EXPECT_LT((columns - expected).cwiseAbs().maxCoeff(), 1e-8) << columns << "\n\n" << expected;
  EXPECT_GT(expected.cwiseAbs().maxCoeff(), 1.0);  // ∂r/∂G = ½ t² P
}

// Spheres of 1 and 2 kg, radii 0.1 and 0.15 m, on the x axis at 0 and
// 0.9 m moving at 1 and −0.5 m/s meet at t_c = (0.9 − R1 − R2)/1.5 and
// leave with Newton's law, e = 0.6:
//   v1⁺ = v1 − m2 (1 + e)(v1 − v2)/(m1 + m2),  v2⁺ = v2 + m1 (1 + e)(v1 − v2)/(m1 + m2),
// x_i(t) = x_i0 + v_i t_c + v_i⁺ (t − t_c); the columns of e, m1, m2, R1
// at 1 s against that, differentiated by central differences.
TEST(ParticleSensitivity, TwoSpheresInADirectImpactHaveTheClosedFormColumns) {
  const Scene scene = parse_scene(lagrangian_test::precise_scene("direct impact", 1.0, R"([[bodies]]
name = "a"
mass = 1.0
radius = 0.1
position = [0.0, 0.0, 0.0]
velocity = [1.0, 0.0, 0.0]
[[bodies]]
name = "b"
mass = 2.0
radius = 0.15
position = [0.9, 0.0, 0.0]
velocity = [-0.5, 0.0, 0.0]
[contacts.spheres]
restitution = 0.6
)"));
  const double t = 1.0;
  const auto closed_form = [&](const std::array<double, 4>& p) {
    const double e = p[0], m1 = p[1], m2 = p[2], tc = (0.9 - p[3] - 0.15) / 1.5;
    const double v1 = 1.0 - m2 * (1 + e) * 1.5 / (m1 + m2), v2 = -0.5 + m1 * (1 + e) * 1.5 / (m1 + m2);
    Eigen::VectorXd x(4);
    x << tc + v1 * (t - tc), 0.9 - 0.5 * tc + v2 * (t - tc), v1, v2;
    return x;
  };
  const Eigen::MatrixXd expected = lagrangian_test::central_differences(closed_form, std::array{0.6, 1.0, 2.0, 0.1});
  const Eigen::MatrixXd columns = parameter_columns(
      scene, {"contacts.spheres.restitution", "bodies[0].mass", "bodies[1].mass", "bodies[0].radius"});
  Eigen::MatrixXd along_x(4, 4);
  along_x << columns.row(0), columns.row(3), columns.row(6), columns.row(9);
  EXPECT_LT(relative_error(along_x, expected), 1e-9) << along_x << "\n\n" << expected;
  EXPECT_GT(expected.cwiseAbs().maxCoeff(), 0.5);
}

// The double pendulum on links (examples/scenes/double_pendulum_links.toml
// with bobs of 1 and 0.6 kg) at 1 s: the columns of g_z and of both masses
// against central differences of plain runs (each moved by ±1e-5 of
// itself). Scaling both masses together changes nothing (their inertia and
// weight scale alike): m1 ∂x/∂m1 + m2 ∂x/∂m2 = 0. The rods' lengths move
// the constraints past the start: refused, naming the first; so is a name
// the scene does not declare, with the list of those it does.
TEST(ParticleSensitivity, DoublePendulumOnLinksMatchesPlainRuns) {
  Scene scene = load_scene(std::string(LAGRANGIAN_SOURCE_DIR) + "/examples/scenes/double_pendulum_links.toml");
  scene.run.t_end = 1.0;
  scene.run.rtol = 1e-12;
  scene.run.atol = 1e-14;
  scene.bodies[1].mass = 0.6;
  const Eigen::MatrixXd columns = parameter_columns(scene, {"gravity.g[2]", "bodies[0].mass", "bodies[1].mass"});
  const auto end_state = [&](const std::array<double, 3>& p) {
    Scene s = scene;
    s.gravity->g[2] = p[0];
    s.bodies[0].mass = p[1];
    s.bodies[1].mass = p[2];
    return lagrangian_test::plain_end_state(s);
  };
  const Eigen::MatrixXd expected =
      lagrangian_test::central_differences(end_state, std::array{-9.81, 1.0, 0.6}, 1e-5, 0.0);
  for (int j = 0; j < 3; ++j)
    EXPECT_LT((columns.col(j) - expected.col(j)).cwiseAbs().maxCoeff(), 1e-6 * expected.col(j).cwiseAbs().maxCoeff())
        << j << "\n" << columns << "\n\n" << expected;
  EXPECT_GT(expected.col(1).cwiseAbs().maxCoeff(), 0.1);  // the masses' ratio matters
  EXPECT_LT((1.0 * columns.col(1) + 0.6 * columns.col(2)).cwiseAbs().maxCoeff(), 1e-9) << columns;

  SensitivityRequest length;
  length.parameters = {"links[1].length"};
  try {
    sensitivity(scene, length);
    ADD_FAILURE() << "a rod's length was taken as a parameter that keeps the start";
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("parameter 'links[1].length' moves the constraint manifold past the start"),
              std::string::npos)
        << e.what();
  }
  SensitivityRequest unknown;
  unknown.parameters = {"m"};
  try {
    sensitivity(scene, unknown);
    ADD_FAILURE() << "an unknown parameter was accepted";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("'m' is not a parameter of the model (bodies[0].mass, bodies[1].mass, "
                                         "gravity.g[0], gravity.g[1], gravity.g[2], links[0].length, "
                                         "links[1].length)"),
              std::string::npos)
        << e.what();
  }
}

// A gas's tangent flow is the event-driven engine's, which carries the
// initial state's columns only: a parameter is refused, naming it.
TEST(ParticleSensitivity, AGasRefusesParameters) {
  const Scene scene = load_scene(std::string(LAGRANGIAN_SOURCE_DIR) + "/examples/scenes/gas_in_container.toml");
  SensitivityRequest request;
  request.parameters = {"bodies[0].mass"};
  try {
    sensitivity(scene, request);
    ADD_FAILURE() << "a gas's parameter column was computed";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("--parameter bodies[0].mass: a gas's sensitivities are those of its initial "
                                         "state"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
