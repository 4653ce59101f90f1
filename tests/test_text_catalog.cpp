// Every built-in generalized-coordinate model restated as text: the
// catalog is walked, so a new built-in model fails here until its text twin
// is written. Each twin states T, V, the forces and constraints of the
// course's formulation with the catalog's parameter names and defaults, and
// must agree with the compiled model in q̈, p, M and h at 100 random states
// to 1e-13 relative (two statements of one system, derived by the same AD
// from different code).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/models.hpp"

namespace {

using namespace lagrangian::scene;
using lagrangian::text::Contact;

/// A text twin and the state its random states are drawn around.
struct Twin {
  TextModelSpec text;
  std::vector<double> centre;  ///< q around which states are drawn (q̇ in [−1, 1])
  bool time_dependent = false;  ///< draw t too
};

TextModelSpec spec(std::vector<std::string> coordinates, std::string kinetic, std::string potential) {
  TextModelSpec s;
  s.coordinates = std::move(coordinates);
  s.kinetic = std::move(kinetic);
  s.potential = std::move(potential);
  return s;
}

std::string planar_chain_kinetic(int n) {
  std::string vx, vy, t;
  for (int k = 1; k <= n; ++k) {
    const std::string th = "theta" + std::to_string(k);
    vx += (k > 1 ? " + " : "") + std::string("l*cos(") + th + ")*" + th + "_dot";
    vy += (k > 1 ? " + " : "") + std::string("l*sin(") + th + ")*" + th + "_dot";
    t += (k > 1 ? " + " : "") + std::string("0.5*m*((") + vx + ")^2 + (" + vy + ")^2)";
  }
  return t;
}

std::map<std::string, Twin> twins() {
  std::map<std::string, Twin> w;
  {
    TextModelSpec s = spec({"y1", "y2"}, "0.5*m1*y1_dot^2 + 0.5*m2*y2_dot^2", "m1*g*y1 + m2*g*y2");
    s.holonomic = {"y1 + y2 - c"};
    w["atwood_machine"] = {s, {0.3, -0.3}};
  }
  {
    TextModelSpec s = spec({"x", "y", "z"}, "0.5*m*(x_dot^2 + y_dot^2 + z_dot^2)", "m*g*z");
    s.contacts = {Contact{"floor", "nx*x + ny*y + nz*z - offset - R", 0.5, "m"}};
    w["ball_and_plane"] = {s, {0.2, -0.1, 1.0}};
  }
  w["bead_on_rotating_hoop"] = {
      spec({"theta"}, "0.5*m*R^2*(theta_dot^2 + omega^2*sin(theta)^2)", "-m*g*R*cos(theta)"), {0.5}};
  {
    TextModelSpec s = spec({"x", "y"}, "0.5*m*(x_dot^2 + y_dot^2)", "0");
    s.holonomic = {"x*sin(omega*t) - y*cos(omega*t)"};
    w["bead_on_rotating_wire"] = {s, {1.0, 0.5}, true};
  }
  w["cart_pendulum"] = {spec({"x", "theta"},
                             "0.5*(M + m)*x_dot^2 + m*l*x_dot*theta_dot*cos(theta) + 0.5*m*l^2*theta_dot^2",
                             "0.5*k*x^2 - m*g*l*cos(theta)"),
                        {0.1, 0.7}};
  {
    TextModelSpec s = spec({"x1", "y1", "x2", "y2"}, "0.5*m1*(x1_dot^2 + y1_dot^2) + 0.5*m2*(x2_dot^2 + y2_dot^2)",
                           "m1*g*y1 + m2*g*y2");
    s.holonomic = {"sqrt(x1^2 + y1^2) - l1", "sqrt((x2 - x1)^2 + (y2 - y1)^2) - l2"};
    w["cartesian_double_pendulum"] = {s, {0.6, -0.8, 1.4, -1.4}};
  }
  {
    TextModelSpec s = spec({"x1", "x2"}, "0.5*m1*x1_dot^2 + 0.5*m2*x2_dot^2", "0");
    s.contacts = {Contact{"", "x2 - x1 - (r1 + r2)", 0.8, "m"}};
    w["direct_impact"] = {s, {0.0, 0.5}};
  }
  w["double_pendulum"] = {
      spec({"theta1", "theta2"},
           "0.5*(m1 + m2)*l1^2*theta1_dot^2 + 0.5*m2*l2^2*theta2_dot^2 + "
           "m2*l1*l2*theta1_dot*theta2_dot*cos(theta1 - theta2)",
           "-(m1 + m2)*g*l1*cos(theta1) - m2*g*l2*cos(theta2)"),
      {1.0, 0.5}};
  // The bob at (l sin θ, y_p − l cos θ), y_p = a cos Ωt: T from its velocity.
  w["driven_pendulum"] = {spec({"theta"},
                               "0.5*m*((l*cos(theta)*theta_dot)^2 + (-a*Omega*sin(Omega*t) + l*sin(theta)*theta_dot)^2)",
                               "m*g*(a*cos(Omega*t) - l*cos(theta))"),
                          {2.0},
                          true};
  w["elastic_pendulum"] = {spec({"r", "theta"}, "0.5*m*(r_dot^2 + r^2*theta_dot^2)",
                                "-m*g*r*cos(theta) + 0.5*k*(r - l0)^2"),
                           {1.2, 0.4}};
  w["harmonic_oscillator"] = {spec({"x"}, "0.5*m*x_dot^2", "0.5*k*x^2"), {0.3}};
  w["kepler"] = {spec({"x", "y"}, "0.5*mu*(x_dot^2 + y_dot^2)", "-k/sqrt(x^2 + y^2)"), {1.0, 0.3}};
  w["kepler_polar"] = {spec({"r", "phi"}, "0.5*m*(r_dot^2 + r^2*phi_dot^2)", "-k/r"), {1.0, 0.3}};
  {
    TextModelSpec s = spec({"x", "y", "phi"}, "0.5*m*(x_dot^2 + y_dot^2) + 0.5*I*phi_dot^2", "0");
    s.pfaffian = {"x_dot*sin(phi) - y_dot*cos(phi)"};
    w["knife_edge"] = {s, {0.2, 0.1, 0.6}};
  }
  {
    TextModelSpec s = spec({"x1", "x2", "x3", "x4", "x5"},
                           "0.5*m*(x1_dot^2 + x2_dot^2 + x3_dot^2 + x4_dot^2 + x5_dot^2)", "0");
    for (int i = 1; i < 5; ++i)
      s.contacts.push_back(Contact{"", "x" + std::to_string(i + 1) + " - x" + std::to_string(i) + " - 2*r", 1.0, "m"});
    w["newtons_cradle"] = {s, {0.0, 0.1, 0.2, 0.3, 0.4}};
  }
  {
    TextModelSpec s = spec({"x1", "y1", "x2", "y2"}, "0.5*m1*(x1_dot^2 + y1_dot^2) + 0.5*m2*(x2_dot^2 + y2_dot^2)",
                           "0");
    s.contacts = {Contact{"", "sqrt((x2 - x1)^2 + (y2 - y1)^2) - (r1 + r2)", 0.9, "m"}};
    w["oblique_impact"] = {s, {0.0, 0.0, 0.5, 0.1}};
  }
  {
    TextModelSpec s = spec({"x", "y", "z"}, "0.5*m*(x_dot^2 + y_dot^2 + z_dot^2)", "m*g*z");
    s.holonomic = {"sqrt(x^2 + y^2 + z^2) - R"};
    w["particle_on_sphere"] = {s, {0.5, 0.3, -0.8}};
  }
  w["pendulum_chain_3"] = {spec({"theta1", "theta2", "theta3"}, planar_chain_kinetic(3),
                                "m*g*(-l*cos(theta1)) + m*g*(-l*cos(theta1) - l*cos(theta2)) + "
                                "m*g*(-l*cos(theta1) - l*cos(theta2) - l*cos(theta3))"),
                           {0.5, 0.6, 0.7}};
  w["projectile"] = {spec({"x", "y"}, "0.5*m*(x_dot^2 + y_dot^2)", "m*g*y"), {2.0, 1.0}};
  {
    TextModelSpec s = spec({"x", "y"}, "0.5*m*(x_dot^2 + y_dot^2)", "m*g*y");
    s.dissipation = "0.5*b*(x_dot^2 + y_dot^2)";
    w["projectile_linear_drag"] = {s, {2.0, 1.0}};
    s.dissipation = "c/3*(x_dot^2 + y_dot^2)^1.5";
    w["projectile_quadratic_drag"] = {s, {2.0, 1.0}};
  }
  w["simple_pendulum"] = {spec({"theta"}, "0.5*m*l^2*theta_dot^2", "-m*g*l*cos(theta)"), {0.8}};
  {
    TextModelSpec s = spec({"x1", "y1", "x2", "y2", "x3", "y3"},
                           "0.5*m*(x1_dot^2 + y1_dot^2 + x2_dot^2 + y2_dot^2 + x3_dot^2 + y3_dot^2)",
                           "m*g*(y1 + y2 + y3)");
    for (int i = 1; i <= 3; ++i) {
      const std::string x = "x" + std::to_string(i), y = "y" + std::to_string(i);
      for (const std::string& gap : {x + " - r", "W - " + x + " - r", y + " - r", "H - " + y + " - r"})
        s.contacts.push_back(Contact{"", gap, 1.0, "m"});
    }
    for (int i = 1; i <= 3; ++i)
      for (int j = i + 1; j <= 3; ++j) {
        const std::string a = std::to_string(i), b = std::to_string(j);
        s.contacts.push_back(
            Contact{"", "sqrt((x" + b + " - x" + a + ")^2 + (y" + b + " - y" + a + ")^2) - 2*r", 1.0, "m"});
      }
    w["spheres_in_box"] = {s, {0.4, 0.3, 1.0, 0.5, 1.6, 0.7}};
  }
  w["spherical_pendulum"] = {spec({"theta", "phi"}, "0.5*m*l^2*(theta_dot^2 + sin(theta)^2*phi_dot^2)",
                                  "-m*g*l*cos(theta)"),
                             {1.0, 0.3}};
  w["two_body"] = {spec({"x1", "y1", "x2", "y2"}, "0.5*m1*(x1_dot^2 + y1_dot^2) + 0.5*m2*(x2_dot^2 + y2_dot^2)",
                        "-k/sqrt((x2 - x1)^2 + (y2 - y1)^2)"),
                   {0.0, 0.0, 1.0, 0.4}};
  return w;
}

/// max |a − b| / max(max |a|, tiny).
double relative(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0, scale = 1e-300;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(a[i]));
  }
  return diff / scale;
}

TEST(TextCatalog, EveryBuiltInModelAgreesWithItsTextTwin) {
  const auto all = twins();
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const ModelInfo& info : builtin_models()) {
    SCOPED_TRACE(info.name);
    const auto it = all.find(info.name);
    ASSERT_NE(it, all.end()) << "built-in model '" << info.name << "' has no text twin in this test";
    const Twin& twin = it->second;
    ModelSpec built_in;
    built_in.name = info.name;
    ModelSpec text;
    text.text = twin.text;
    for (const ParameterInfo& p : info.parameters) text.parameters[p.name] = p.default_value;
    const auto& a = detail::entry_for(built_in);
    const auto& b = detail::entry_for(text);
    const std::size_t n = info.coordinates.size();
    ASSERT_EQ(twin.text.coordinates.size(), n);
    ASSERT_EQ(twin.centre.size(), n);
    double worst_qdd = 0, worst_p = 0, worst_m = 0, worst_h = 0;
    for (int k = 0; k < 100; ++k) {
      std::vector<double> q(n), qd(n);
      for (std::size_t i = 0; i < n; ++i) {
        q[i] = twin.centre[i] + 0.1 * unit(rng);
        qd[i] = unit(rng);
      }
      const double t = twin.time_dependent ? 1.0 + unit(rng) : 0.0;
      const lagrangian::detail::EomSample x = a->eom(built_in, q.data(), qd.data(), t);
      const lagrangian::detail::EomSample y = b->eom(text, q.data(), qd.data(), t);
      worst_qdd = std::max(worst_qdd, relative(x.qdd, y.qdd));
      worst_p = std::max(worst_p, relative(x.p, y.p));
      worst_m = std::max(worst_m, relative(x.mass, y.mass));
      worst_h = std::max(worst_h, std::abs(x.h - y.h) / std::max(std::abs(x.h), 1e-300));
    }
    EXPECT_LE(worst_qdd, 1e-13) << "q̈";
    EXPECT_LE(worst_p, 1e-13) << "p";
    EXPECT_LE(worst_m, 1e-13) << "M";
    EXPECT_LE(worst_h, 1e-13) << "h";
    std::printf("%-28s q̈ %.1e  p %.1e  M %.1e  h %.1e\n", info.name.c_str(), worst_qdd, worst_p, worst_m, worst_h);
  }
}

// The test can fail: a twin with a wrong sign in V disagrees in q̈.
TEST(TextCatalog, AWrongTwinDisagrees) {
  const ModelInfo* info = find_model("simple_pendulum");
  ASSERT_NE(info, nullptr);
  ModelSpec built_in;
  built_in.name = "simple_pendulum";
  ModelSpec text;
  text.text = spec({"theta"}, "0.5*m*l^2*theta_dot^2", "m*g*l*cos(theta)");
  for (const ParameterInfo& p : info->parameters) text.parameters[p.name] = p.default_value;
  const double q = 0.8, qd = 0.1;
  const auto x = detail::entry_for(built_in)->eom(built_in, &q, &qd, 0.0);
  const auto y = detail::entry_for(text)->eom(text, &q, &qd, 0.0);
  EXPECT_GT(relative(x.qdd, y.qdd), 1.0);
}

}  // namespace
