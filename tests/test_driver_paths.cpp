// The driver's two ways through a run must agree to the last bit: steps
// with per-step bookkeeping (every step sampled) against steps taken in a
// row between samples (quiet_steps in integrate/detail/controlled_loop.hpp), and the
// explicit loops compiled once, reaching q̈ through the System's vtable,
// against the same loops compiled here with q̈ inlined (lagrangian::inlined,
// for a hand-coded and an AD q̈). Each pair does the same arithmetic, so each gives the
// same steps, the same evaluations and the same end state; and a run that
// fails fails at the same time with the same message either way.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "lagrangian/integrate/inlined.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

using namespace lagrangian;

const Method kExplicitMethods[] = {Method::dopri5, Method::rk4, Method::cash_karp54, Method::fehlberg78,
                                   Method::bulirsch_stoer};

/// The double pendulum with q̈ written out. With c = cos(θ1 − θ2),
/// s = sin(θ1 − θ2), Lagrange's equations of T and V of models::DoublePendulum are
///   (m1 + m2) l1² θ̈1 + m2 l1 l2 c θ̈2 = −m2 l1 l2 s θ̇2² − (m1 + m2) g l1 sin θ1,
///   m2 l1 l2 c θ̈1 + m2 l2² θ̈2       =  m2 l1 l2 s θ̇1² − m2 g l2 sin θ2,
/// solved here by Cramer's rule (rad/s²).
struct HandDoublePendulum : models::DoublePendulum {
  void accelerations(const Vec<double, 2>& q, const Vec<double, 2>& qd, double, Vec<double, 2>& qdd) const {
    const double c = std::cos(q[0] - q[1]), s = std::sin(q[0] - q[1]);
    const double a11 = (m1 + m2) * l1 * l1, a12 = m2 * l1 * l2 * c, a22 = m2 * l2 * l2;
    const double b1 = -m2 * l1 * l2 * s * qd[1] * qd[1] - (m1 + m2) * g * l1 * std::sin(q[0]);
    const double b2 = m2 * l1 * l2 * s * qd[0] * qd[0] - m2 * g * l2 * std::sin(q[1]);
    const double det = a11 * a22 - a12 * a12;
    qdd[0] = (b1 * a22 - a12 * b2) / det;
    qdd[1] = (a11 * b2 - a12 * b1) / det;
  }
};
static_assert(!inline_rhs_v<HandDoublePendulum>, "simulate() runs the library's loops unless asked");
static_assert(inline_rhs_v<Inlined<HandDoublePendulum>>);

/// V = −½ q⁴, T = ½ q̇²: q̈ = 2 q³, and from q = q̇ = 1 the motion
/// q = 1 / (1 − t) leaves every bound at t = 1 s. q̈ is hand-coded: the
/// stops under test do not depend on how q̈ is reached.
struct BlowUp {
  void accelerations(const Vec<double, 1>& q, const Vec<double, 1>&, double, Vec<double, 1>& qdd) const {
    qdd[0] = 2 * q[0] * q[0] * q[0];
  }
  static constexpr int coordinate_count = 1;
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    return -0.5 * q[0] * q[0] * q[0] * q[0];
  }
};

SimulationOptions options(Method method, double output_interval) {
  SimulationOptions o;
  o.method = method;
  o.t_end = 5.0;
  o.dt = 1e-3;
  o.output_interval = output_interval;
  return o;
}

State<2> start() {
  State<2> s;
  s.q << 0.5, -0.3;
  s.qd << 0.2, 0.0;
  return s;
}

struct Outcome {
  RunReport report;
  Sample<2> end;
};

template <class M>
Outcome run(const M& model, const SimulationOptions& o) {
  Recorder<2> rec;
  Outcome out{simulate(model, start(), o, rec), {}};
  out.end = rec.samples.back();
  return out;
}

void expect_same_run(const Outcome& a, const Outcome& b) {
  EXPECT_EQ(a.report.steps, b.report.steps);
  EXPECT_EQ(a.report.rejected_steps, b.report.rejected_steps);
  EXPECT_EQ(a.report.rhs_evaluations, b.report.rhs_evaluations);
  EXPECT_EQ(a.end.t, b.end.t);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(a.end.q[i], b.end.q[i]) << "q[" << i << "]";
    EXPECT_EQ(a.end.qd[i], b.end.qd[i]) << "qd[" << i << "]";
  }
}

TEST(DriverPaths, StepsInARowMatchStepsSampledOneByOne) {
  for (const Method method : kExplicitMethods) {
    SCOPED_TRACE(method);
    const Outcome every_step = run(models::DoublePendulum(), options(method, 0.0));
    const Outcome ends_only = run(models::DoublePendulum(), options(method, -1.0));
    EXPECT_GT(every_step.report.steps, 20u);
    expect_same_run(every_step, ends_only);
  }
}

TEST(DriverPaths, DenseSamplesDoNotChangeTheSteps) {
  // dopri5 samples from its dense output and rk4 from a sub-step, so
  // samples every 0.25 s leave the steps as they are.
  for (const Method method : {Method::dopri5, Method::rk4}) {
    SCOPED_TRACE(method);
    const Outcome sampled = run(models::DoublePendulum(), options(method, 0.25));
    const Outcome ends_only = run(models::DoublePendulum(), options(method, -1.0));
    expect_same_run(sampled, ends_only);
  }
}

TEST(DriverPaths, InlinedAccelerationsMatchTheLibraryLoops) {
  for (const Method method : kExplicitMethods) {
    for (const double interval : {0.0, -1.0}) {
      SCOPED_TRACE(std::string(to_string(method)) + ", output_interval " + std::to_string(interval));
      expect_same_run(run(inlined(HandDoublePendulum()), options(method, interval)),
                      run(HandDoublePendulum(), options(method, interval)));
      // An AD q̈ inlined (DirectRhs): the oscillator, whose AD pass is cheap to compile.
      const models::HarmonicOscillator oscillator(0.5, 2.0);
      State<1> s;
      s.q << 0.7;
      s.qd << -0.3;
      Recorder<1> a, b;
      const RunReport ra = simulate(inlined(oscillator), s, options(method, interval), a);
      const RunReport rb = simulate(oscillator, s, options(method, interval), b);
      EXPECT_EQ(ra.steps, rb.steps);
      EXPECT_EQ(ra.rhs_evaluations, rb.rhs_evaluations);
      EXPECT_EQ(a.samples.back().q[0], b.samples.back().q[0]);
      EXPECT_EQ(a.samples.back().qd[0], b.samples.back().qd[0]);
    }
  }
}

TEST(DriverPaths, HandCodedAccelerationsAgreeWithTheLagrangian) {
  // An independent derivation: the Cramer's-rule q̈ against automatic
  // differentiation of T − V, at rtol 1e-10 over 5 s of regular motion.
  const Outcome hand = run(HandDoublePendulum(), options(Method::dopri5, -1.0));
  const Outcome ad = run(models::DoublePendulum(), options(Method::dopri5, -1.0));
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(hand.end.q[i], ad.end.q[i], 1e-8);
    EXPECT_NEAR(hand.end.qd[i], ad.end.qd[i], 1e-8);
  }
}

/// The SimulationError of a run of `model` (BlowUp) from q = q̇ = 1.
template <class M = BlowUp>
SimulationError failure(const SimulationOptions& o, const M& model = {}) {
  State<1> s;
  s.q << 1.0;
  s.qd << 1.0;
  try {
    simulate(model, s, o);
  } catch (const SimulationError& e) {
    return e;
  }
  ADD_FAILURE() << o.method << ": the run did not fail";
  return SimulationError("", 0.0);
}

TEST(DriverPaths, ABlowUpStopsAtTheSameStepEitherWay) {
  for (const Method method : kExplicitMethods) {
    SCOPED_TRACE(method);
    SimulationOptions o = options(method, 0.0);
    o.t_end = 2.0;
    const SimulationError every_step = failure(o);
    o.output_interval = -1.0;
    const SimulationError ends_only = failure(o);
    const SimulationError ends_only_inlined = failure(o, inlined(BlowUp{}));
    EXPECT_EQ(std::string(every_step.what()), std::string(ends_only.what()));
    EXPECT_EQ(every_step.time(), ends_only.time());
    EXPECT_EQ(std::string(every_step.what()), std::string(ends_only_inlined.what()));
    EXPECT_EQ(every_step.time(), ends_only_inlined.time());
    // q = 1/(1 − t) leaves double precision just after t = 1 s (rk4 at
    // dt = 1 ms runs past the pole before its values overflow).
    EXPECT_GT(every_step.time(), 0.99);
    EXPECT_LT(every_step.time(), 1.1);
  }
}

TEST(DriverPaths, MaxStepsStopsAtTheSameStepEitherWay) {
  // rk4 with dt = 1 ms and max_steps = 100 fails on its 101st step, which ends at 0.101 s.
  for (const double interval : {0.0, -1.0}) {
    SimulationOptions o = options(Method::rk4, interval);
    o.max_steps = 100;
    for (const SimulationError& e : {failure(o), failure(o, inlined(BlowUp{}))}) {
      EXPECT_NE(std::string(e.what()).find("max_steps = 100"), std::string::npos) << e.what();
      EXPECT_NEAR(e.time(), 0.101, 1e-15);
    }
  }
}

}  // namespace
