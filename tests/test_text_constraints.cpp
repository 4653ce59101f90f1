// Constraints of models stated as text (text/text_model.hpp): holonomic and
// Pfaffian rows counted at run time, against closed forms and against the
// built-in C++ models with the same constraints.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/text/text_model.hpp"

namespace {

using namespace lagrangian;
using text::Definition;

State<Dynamic> state(std::initializer_list<double> q, std::initializer_list<double> qd) {
  State<Dynamic> s(static_cast<int>(q.size()));
  int i = 0;
  for (double v : q) s.q[i++] = v;
  i = 0;
  for (double v : qd) s.qd[i++] = v;
  return s;
}

/// The samples and the columns of a run.
struct Recording : Recorder<Dynamic> {
  Columns columns;
  void begin(const Columns& c) { columns = c; }
};

SimulationOptions tight(double t_end, double interval) {
  SimulationOptions o;
  o.t_end = t_end;
  o.rtol = 1e-12;
  o.atol = 1e-12;
  o.output_interval = interval;
  return o;
}

Definition atwood(double m1, double m2, double g, double c) {
  Definition d;
  d.coordinates = {"y1", "y2"};
  d.units = {"m", "m"};
  d.kinetic = "0.5*m1*y1_dot^2 + 0.5*m2*y2_dot^2";
  d.potential = "m1*g*y1 + m2*g*y2";
  d.holonomic = {"y1 + y2 - c"};
  d.constraint_names = {"string"};
  d.constraint_units = {"m"};
  d.parameters = {{"m1", m1}, {"m2", m2}, {"g", g}, {"c", c}};
  return d;
}

// Atwood machine by a holonomic constraint: heights y1, y2 (up) with
// y1 + y2 = c. Newton for each mass, m_i ÿ_i = −m_i g + τ, with ÿ2 = −ÿ1,
// gives ÿ1 = −g (m1 − m2)/(m1 + m2) and the tension τ = 2 m1 m2 g/(m1 + m2),
// the multiplier of g = y1 + y2 − c (the force along +∇g on each mass).
TEST(TextConstraints, AtwoodMachineFollowsTheClosedFormWithItsTension) {
  const double m1 = 3.0, m2 = 1.0, g = 9.81, c = 1.0;
  const text::TextModel model(atwood(m1, m2, g, c));
  EXPECT_EQ(model.holonomic_count(), 1);
  EXPECT_EQ(model.pfaffian_count(), 0);
  const State<Dynamic> x0 = state({0.8, 0.2}, {0.1, -0.1});
  const DofReport dof = dof_report(model, x0);
  EXPECT_EQ(dof.holonomic, 1);
  EXPECT_EQ(dof.holonomic_rank, 1);
  EXPECT_EQ(dof.degrees_of_freedom, 1);

  const double a = -g * (m1 - m2) / (m1 + m2), tension = 2 * m1 * m2 * g / (m1 + m2);
  Recording rec;
  const RunReport r = simulate(model, x0, tight(0.3, 0.05), rec);
  ASSERT_EQ(rec.samples.size(), 7u);
  EXPECT_EQ(rec.columns.constraints, std::vector<std::string>{"string"});
  EXPECT_EQ(rec.columns.constraint_units, std::vector<std::string>{"N"});
  for (const auto& s : rec.samples) {
    EXPECT_NEAR(s.q[0], 0.8 + 0.1 * s.t + 0.5 * a * s.t * s.t, 1e-11) << "t = " << s.t;
    EXPECT_NEAR(s.q[1], 0.2 - 0.1 * s.t - 0.5 * a * s.t * s.t, 1e-11) << "t = " << s.t;
    ASSERT_EQ(s.multipliers.size(), 1);
    EXPECT_NEAR(s.multipliers[0], tension, 1e-9) << "t = " << s.t;
  }
  EXPECT_TRUE(r.constrained);
  EXPECT_LE(r.constraints.max_position_residual, 1e-12);
  EXPECT_LE(r.energy_drift_max, 1e-10);
}

/// A particle (x, y) of mass m under gravity g, held on the circle of
/// radius l about the origin by the holonomic constraint `rod`.
Definition cartesian_pendulum(const std::string& rod, double m, double l, double g) {
  Definition d;
  d.coordinates = {"x", "y"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2)";
  d.potential = "m*g*y";
  d.holonomic = {rod};
  d.parameters = {{"m", m}, {"l", l}, {"g", g}};
  return d;
}

// A plane pendulum as a particle (x, y) on a rod, g = √(x² + y²) − l: a
// constraint whose γ is not zero, against the built-in CartesianPendulum.
TEST(TextConstraints, CartesianPendulumAgreesWithTheBuiltInModel) {
  const double m = 1.5, l = 0.7, g = 9.81;
  const text::TextModel text_model(cartesian_pendulum("sqrt(x^2 + y^2) - l", m, l, g));
  const models::CartesianPendulum built_in(m, l, g);
  const double th = 1.1, w = 0.4;
  State<2> s0;
  s0.q << l * std::sin(th), -l * std::cos(th);
  s0.qd << l * std::cos(th) * w, l * std::sin(th) * w;
  State<Dynamic> x0(2);
  x0.q = s0.q;
  x0.qd = s0.qd;
  Recorder<2> ra;
  Recording rb;
  const RunReport a = simulate(built_in, s0, tight(5.0, 0.25), ra);
  const RunReport b = simulate(text_model, x0, tight(5.0, 0.25), rb);
  ASSERT_EQ(ra.samples.size(), rb.samples.size());
  for (std::size_t k = 0; k < ra.samples.size(); ++k) {
    EXPECT_LE((ra.samples[k].q - rb.samples[k].q).lpNorm<Eigen::Infinity>(), 1e-10) << ra.samples[k].t;
    EXPECT_LE((ra.samples[k].qd - rb.samples[k].qd).lpNorm<Eigen::Infinity>(), 1e-9) << ra.samples[k].t;
    EXPECT_NEAR(ra.samples[k].multipliers[0], rb.samples[k].multipliers[0], 1e-8) << ra.samples[k].t;
  }
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(rb.columns.constraints, std::vector<std::string>{"g0"});
  EXPECT_LE(b.constraints.max_position_residual, 1e-11);

  // Its equilibria on the circle: the bottom (stable) and the top.
  EquilibriumOptions eo;
  eo.starts = {Eigen::Vector2d(0.3, -0.6), Eigen::Vector2d(0.2, 0.65)};
  const auto eq = find_equilibria(text_model, eo);
  ASSERT_EQ(eq.size(), 2u);
  EXPECT_NEAR(eq[0].q[1], -l, 1e-9);
  EXPECT_TRUE(eq[0].stable);
  EXPECT_NEAR(eq[0].multipliers[0], -m * g, 1e-8);  // the rod pulls the bob up: λ along +∇g = −ŷ
  EXPECT_NEAR(eq[1].q[1], l, 1e-9);
  EXPECT_FALSE(eq[1].stable);
}

// consistent_initial_state() on a model whose constraints are counted at
// run time: from a guess off the pendulum's circle, the nearest point of
// the circle is l r/|r| (the closed form) and the velocity is projected
// onto its tangent; the built-in CartesianPendulum gives the same state.
TEST(TextConstraints, ConsistentInitialStateFindsTheNearestPointOfTheCircle) {
  const double m = 1.5, l = 0.7, g = 9.81;
  const text::TextModel text_model(cartesian_pendulum("x^2 + y^2 - l^2", m, l, g));
  State<Dynamic> guess = state({0.9, -0.5}, {0.3, 0.8});
  ConsistentStateReport rep;
  const State<Dynamic> s = consistent_initial_state(text_model, guess, 0.0, 1e-12, &rep);
  const double r = std::hypot(0.9, -0.5);
  EXPECT_NEAR(s.q[0], l * 0.9 / r, 1e-14);
  EXPECT_NEAR(s.q[1], l * -0.5 / r, 1e-14);
  EXPECT_NEAR(s.q.dot(s.qd), 0.0, 1e-13);  // tangent to the circle
  EXPECT_NEAR(rep.distance, r - l, 1e-14);
  EXPECT_TRUE(rep.local_minimum);
  EXPECT_LE(rep.position_residual, 1e-14);
  EXPECT_LE(rep.velocity_residual, 1e-13);
  State<2> guess2;
  guess2.q << 0.9, -0.5;
  guess2.qd << 0.3, 0.8;
  const State<2> b = consistent_initial_state(models::CartesianPendulum(m, l, g), guess2, 0.0, 1e-12);
  EXPECT_LE((b.q - s.q).lpNorm<Eigen::Infinity>(), 1e-14);
  EXPECT_LE((b.qd - s.qd).lpNorm<Eigen::Infinity>(), 1e-13);
}

// The knife edge (a Pfaffian constraint, no side slip), against the
// built-in KnifeEdge: the same motion and side force, DOF 3, velocity DOF 2.
TEST(TextConstraints, KnifeEdgeAgreesWithTheBuiltInModel) {
  const double m = 2.0, I = 0.3;
  Definition d;
  d.coordinates = {"x", "y", "phi"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2) + 0.5*I*phi_dot^2";
  d.pfaffian = {"x_dot*sin(phi) - y_dot*cos(phi)"};
  d.constraint_names = {"no_sideslip"};
  d.parameters = {{"m", m}, {"I", I}};
  const text::TextModel text_model(d);
  const models::KnifeEdge built_in(m, I);
  const double phi0 = 0.3, v = 1.2, w = 0.8;
  State<3> s0;
  s0.q << 0.0, 0.0, phi0;
  s0.qd << v * std::cos(phi0), v * std::sin(phi0), w;
  State<Dynamic> x0(3);
  x0.q = s0.q;
  x0.qd = s0.qd;
  const DofReport dof = dof_report(text_model, x0);
  EXPECT_EQ(dof.degrees_of_freedom, 3);
  EXPECT_EQ(dof.velocity_degrees_of_freedom, 2);
  Recorder<3> ra;
  Recording rb;
  simulate(built_in, s0, tight(4.0, 0.5), ra);
  const RunReport b = simulate(text_model, x0, tight(4.0, 0.5), rb);
  ASSERT_EQ(ra.samples.size(), rb.samples.size());
  for (std::size_t k = 0; k < ra.samples.size(); ++k) {
    const auto& s = rb.samples[k];
    EXPECT_LE((ra.samples[k].q - s.q).lpNorm<Eigen::Infinity>(), 1e-10) << s.t;
    EXPECT_NEAR(ra.samples[k].multipliers[0], s.multipliers[0], 1e-9) << s.t;
    // The closed form: the edge runs on a circle of radius v/ω at constant speed.
    const double phi = phi0 + w * s.t;
    EXPECT_NEAR(s.q[0], v / w * (std::sin(phi) - std::sin(phi0)), 1e-9) << s.t;
    EXPECT_NEAR(s.q[1], -v / w * (std::cos(phi) - std::cos(phi0)), 1e-9) << s.t;
    // The side force keeps it on the circle: m v²/R = m v ω along the normal.
    EXPECT_NEAR(std::abs(s.multipliers[0]), m * v * w, 1e-9) << s.t;
  }
  EXPECT_LE(b.constraints.max_velocity_residual, 1e-10);
}

// A ball bouncing on a tilted plane (a contact with restitution, then
// sliding at rest on it), against the built-in BallAndPlane: the same
// impacts at the same times with the same impulses, the same rest.
TEST(TextConstraints, ContactsAgreeWithTheBuiltInBallAndPlane) {
  const double m = 0.7, R = 0.1, e = 0.6, g = 9.81;
  const models::BallAndPlane built_in(m, R, e, g, {0.3, 0.0, 1.0}, -0.2);
  Definition d;
  d.coordinates = {"x", "y", "z"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2 + z_dot^2)";
  d.potential = "m*g*z";
  d.contacts = {{"ball-plane", "nx*x + nz*z - d - R", e, "m"}};
  d.parameters = {{"m", m},   {"g", g}, {"R", R}, {"nx", built_in.normal()[0]}, {"nz", built_in.normal()[2]},
                  {"d", -0.2}};
  const text::TextModel text_model(d);
  State<3> s0;
  s0.q << 0.0, 0.0, 1.0;
  s0.qd << 0.5, 0.2, 0.0;
  State<Dynamic> x0(3);
  x0.q = s0.q;
  x0.qd = s0.qd;
  SimulationOptions o = tight(3.0, 0.5);
  o.rtol = o.atol = 1e-11;
  Recorder<3> ra;
  Recording rb;
  const RunReport a = simulate(built_in, s0, o, ra);
  const RunReport b = simulate(text_model, x0, o, rb);
  EXPECT_EQ(rb.columns.constraints, std::vector<std::string>{"ball-plane"});
  EXPECT_EQ(rb.columns.constraint_units, std::vector<std::string>{"N"});
  ASSERT_GE(a.impacts, 5u);
  EXPECT_EQ(a.impacts, b.impacts);
  ASSERT_EQ(a.events.size(), b.events.size());
  for (std::size_t k = 0; k < a.events.size(); ++k) {
    EXPECT_EQ(a.events[k].kind, b.events[k].kind) << k;
    EXPECT_NEAR(a.events[k].t, b.events[k].t, 1e-9) << k;
    EXPECT_NEAR(a.events[k].impulse, b.events[k].impulse, 1e-9) << k;
  }
  EXPECT_EQ(b.events.back().kind, EventKind::rest);
  ASSERT_EQ(ra.samples.size(), rb.samples.size());
  EXPECT_LE((ra.samples.back().q - rb.samples.back().q).lpNorm<Eigen::Infinity>(), 1e-8);
  // Resting on the plane at the end, pressed by m g n_z (N).
  EXPECT_NEAR(rb.samples.back().multipliers[0], m * g * built_in.normal()[2], 1e-8);
}

TEST(TextConstraints, MistakesNameTheField) {
  auto message = [](const Definition& d) {
    try {
      text::TextModel model(d);
    } catch (const text::ExpressionError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Definition d = atwood(3, 1, 9.81, 1);
  d.holonomic = {"y1 + y2_dot"};
  EXPECT_NE(message(d).find("holonomic[0]"), std::string::npos) << message(d);
  EXPECT_NE(message(d).find("a velocity appears"), std::string::npos) << message(d);
  d = atwood(3, 1, 9.81, 1);
  d.constraint_names.clear();
  d.constraint_units.clear();
  d.pfaffian = {"y1_dot + y2", "y1_dot*y2_dot"};
  EXPECT_NE(message(d).find("pfaffian[1]"), std::string::npos) << message(d);
  EXPECT_NE(message(d).find("linear in the velocities"), std::string::npos) << message(d);
  d.pfaffian = {"y1_dot + sin(y2)*y2_dot + t"};  // affine: accepted
  EXPECT_EQ(message(d), "no error");
  d.constraint_names = {"string"};
  EXPECT_NE(message(d).find("constraint_names"), std::string::npos) << message(d);
  EXPECT_NE(message(d).find("1 for 2 constraints"), std::string::npos) << message(d);
  d = atwood(3, 1, 9.81, 1);
  d.holonomic = {"y1 + y2 - c +"};
  EXPECT_NE(message(d).find("holonomic[0]"), std::string::npos) << message(d);
  d = atwood(3, 1, 9.81, 1);
  d.contacts = {{"floor", "y1", std::nan(""), ""}};
  EXPECT_NE(message(d).find("contacts[0].restitution"), std::string::npos) << message(d);
  d.contacts = {{"floor", "y1", 1.5, ""}};
  EXPECT_NE(message(d).find("must be in [0, 1], got 1.5"), std::string::npos) << message(d);
  d.contacts = {{"floor", "y1_dot", 0.5, ""}};
  EXPECT_NE(message(d).find("contacts[0].gap"), std::string::npos) << message(d);
  d.contacts = {{"string", "y1", 0.5, ""}};  // the holonomic constraint's name
  EXPECT_NE(message(d).find("constraint_names"), std::string::npos) << message(d);
}

// A model without constraints keeps the unconstrained path: no constraint
// columns, no multipliers.
TEST(TextConstraints, AModelWithoutConstraintsRunsUnconstrained) {
  Definition d;
  d.coordinates = {"x"};
  d.kinetic = "0.5*x_dot^2";
  d.potential = "0.5*x^2";
  const text::TextModel model(d);
  Recording rec;
  const RunReport r = simulate(model, state({1.0}, {0.0}), tight(1.0, 0.5), rec);
  EXPECT_FALSE(r.constrained);
  EXPECT_TRUE(rec.columns.constraints.empty());
  EXPECT_EQ(rec.samples.back().multipliers.size(), 0);
  EXPECT_NEAR(rec.samples.back().q[0], std::cos(1.0), 1e-10);
}

}  // namespace
