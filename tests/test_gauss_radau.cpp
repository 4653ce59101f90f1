// The 15th-order Gauss–Radau integrator (method "gauss_radau15"): its nodes,
// its order at fixed steps, exactness on polynomial motion, reversibility,
// located events, velocity-dependent forces, constraints, and conservation
// in adaptive runs, each against a closed form or an independent derivation.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "lagrangian/integrate/detail/gauss_radau.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/kepler.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/models/two_body.hpp"

namespace {

using namespace lagrangian;
using lagrangian::detail::GaussRadau15;
namespace lm = lagrangian::models;

// -- the stepper at fixed steps ------------------------------------------------------

/// Kepler's problem q̈ = −GM q/|q|³ in the plane, x = [q; q̇].
struct KeplerRhs {
  double gm = 1.0;
  void operator()(const double* x, double* dxdt, double) const {
    const double r2 = x[0] * x[0] + x[1] * x[1];
    const double k = gm / (r2 * std::sqrt(r2));
    dxdt[0] = x[2];
    dxdt[1] = x[3];
    dxdt[2] = -k * x[0];
    dxdt[3] = -k * x[1];
  }
};

/// `steps` fixed steps of size dt from x (every step's iteration converged).
template <class F>
std::array<double, 4> fixed_steps(const F& f, std::array<double, 4> x, double t0, double dt, int steps) {
  GaussRadau15<2> gr;
  gr.start(x.data());
  const auto rhs = lagrangian::detail::function_ref<void(const double*, double*, double)>(f);
  double t = t0;
  for (int k = 0; k < steps; ++k) {
    const GaussRadau15<2>::Attempt a = gr.attempt(rhs, t, dt);
    EXPECT_LT(a.corrector_change, 1e-8) << "step " << k;
    gr.accept(dt);
    t += dt;
  }
  gr.state(x.data());
  return x;
}

double distance(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  double d = 0;
  for (int i = 0; i < 4; ++i) d = std::max(d, std::abs(a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]));
  return d;
}

TEST(GaussRadau, NodesAreTheRadauNodesOfEverhartAndReinSpiegel) {
  // The spacings as published (Everhart 1985; Rein & Spiegel 2015, IAS15),
  // against the roots the stepper finds for itself.
  const std::array<double, 8> published{0.0,
                                        0.0562625605369221464656521910318,
                                        0.180240691736892364987579942780,
                                        0.352624717113169637373907769648,
                                        0.547153626330555383001448554766,
                                        0.734210177215410531523210605558,
                                        0.885320946839095768090359771030,
                                        0.977520613561287501891174488626};
  const auto& h = GaussRadau15<>::nodes();
  for (std::size_t k = 0; k < 8; ++k) EXPECT_NEAR(h[k], published[k], 2e-16) << k;
  // The 8-point Radau rule on them integrates s^m exactly for m ≤ 14: its
  // weights w (from the moments m = 0 … 7) also give the moments 8 … 14.
  std::array<std::array<long double, 9>, 8> a{};
  for (int m = 0; m < 8; ++m) {
    for (int k = 0; k < 8; ++k) a[static_cast<std::size_t>(m)][static_cast<std::size_t>(k)] = std::pow(static_cast<long double>(h[static_cast<std::size_t>(k)]), m);
    a[static_cast<std::size_t>(m)][8] = 1.0L / (m + 1);
  }
  for (int c = 0; c < 8; ++c) {  // Gauss–Jordan, partial pivoting
    int p = c;
    for (int r = c + 1; r < 8; ++r)
      if (std::abs(a[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)]) > std::abs(a[static_cast<std::size_t>(p)][static_cast<std::size_t>(c)])) p = r;
    std::swap(a[static_cast<std::size_t>(c)], a[static_cast<std::size_t>(p)]);
    for (int r = 0; r < 8; ++r) {
      if (r == c) continue;
      const long double f = a[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] / a[static_cast<std::size_t>(c)][static_cast<std::size_t>(c)];
      for (int k = c; k < 9; ++k) a[static_cast<std::size_t>(r)][static_cast<std::size_t>(k)] -= f * a[static_cast<std::size_t>(c)][static_cast<std::size_t>(k)];
    }
  }
  std::array<long double, 8> w{};
  for (int k = 0; k < 8; ++k) w[static_cast<std::size_t>(k)] = a[static_cast<std::size_t>(k)][8] / a[static_cast<std::size_t>(k)][static_cast<std::size_t>(k)];
  for (int m = 8; m <= 15; ++m) {
    long double sum = 0;
    for (int k = 0; k < 8; ++k) sum += w[static_cast<std::size_t>(k)] * std::pow(static_cast<long double>(h[static_cast<std::size_t>(k)]), m);
    if (m <= 14) {
      EXPECT_NEAR(static_cast<double>(sum), 1.0 / (m + 1), 1e-14) << "moment " << m;
    } else {
      EXPECT_GT(std::abs(static_cast<double>(sum) - 1.0 / (m + 1)), 1e-10) << "degree 15 is not exact";
    }
  }
}

TEST(GaussRadau, FifteenthOrderAtFixedSteps) {
  // Two oscillators q̈ = −ω² q (ω = 1 and 1/2) over t = 768 s from q = 1:
  // q = cos ωt. The global error falls as h^15 between h = 2 s and 1.5 s,
  // where it is still far above round-off (a step of 1 s is at round-off
  // already, and one of 3 s is too long for the iteration to converge).
  const auto f = [](const double* x, double* dxdt, double) {
    dxdt[0] = x[2];
    dxdt[1] = x[3];
    dxdt[2] = -x[0];
    dxdt[3] = -0.25 * x[1];
  };
  const double T = 768.0;
  std::vector<double> errors;
  const std::array<double, 2> h{2.0, 1.5};
  for (double step : h) {
    const int n = static_cast<int>(std::lround(T / step));
    const std::array<double, 4> x = fixed_steps(f, {1.0, 1.0, 0.0, 0.0}, 0.0, T / n, n);
    // The distance in the phase plane (q, q̇/ω): the phase error, whatever the phase.
    const auto off = [&](int i, double w) {
      return std::hypot(x[static_cast<std::size_t>(i)] - std::cos(w * T),
                        (x[static_cast<std::size_t>(i + 2)] + w * std::sin(w * T)) / w);
    };
    errors.push_back(std::max(off(0, 1.0), off(1, 0.5)));
    std::printf("  h = %.2f s: error %.3e\n", step, errors.back());
  }
  const double order = std::log(errors[0] / errors[1]) / std::log(h[0] / h[1]);
  std::printf("  observed order %.2f\n", order);
  EXPECT_GT(errors[1], 1e-13);  // above round-off: the ratio is the method's
  EXPECT_GT(order, 14.0);
  EXPECT_LT(order, 16.5);
}

TEST(GaussRadau, FreeFlightUnderConstantForceIsExact) {
  // q̈ = const: the acceleration's polynomial is exact (every b is 0), so
  // any step gives q₀ + v₀ t + ½ a t² to round-off.
  const auto f = [](const double* x, double* dxdt, double) {
    dxdt[0] = x[2];
    dxdt[1] = x[3];
    dxdt[2] = 0.5;
    dxdt[3] = -9.81;
  };
  const std::array<double, 4> x0{1.0, 2.0, 3.0, 40.0};
  const double T = 7.3;
  const std::array<double, 4> x = fixed_steps(f, x0, 0.0, T / 5, 5);
  const std::array<double, 4> exact{1.0 + 3.0 * T + 0.25 * T * T, 2.0 + 40.0 * T - 0.5 * 9.81 * T * T, 3.0 + 0.5 * T,
                                    40.0 - 9.81 * T};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(x[i], exact[i], 4e-15 * std::abs(exact[i])) << i;
  // A force polynomial in time of degree 6, q̈ = t⁶: exact too (degree ≤ 7).
  const auto g = [](const double* x, double* dxdt, double t) {
    dxdt[0] = x[2];
    dxdt[1] = x[3];
    dxdt[2] = std::pow(t, 6);
    dxdt[3] = 0.0;
  };
  const std::array<double, 4> y = fixed_steps(g, {0.0, 0.0, 0.0, 0.0}, 0.0, 0.5, 4);
  EXPECT_NEAR(y[0], std::pow(2.0, 8) / 56.0, 1e-14 * std::pow(2.0, 8) / 56.0);
  EXPECT_NEAR(y[2], std::pow(2.0, 7) / 7.0, 1e-14 * std::pow(2.0, 7) / 7.0);
}

TEST(GaussRadau, ReversibleToRoundOff) {
  // Forward one orbit of e = 0.5, then back with the velocities reversed:
  // the start is recovered to round-off, not to the (far larger) truncation error.
  const lm::KeplerOrbit orbit(1.0, 0.5, 1.0);
  const std::array<double, 4> x0 = orbit.state(0.0);
  const int steps = 200;
  const double dt = orbit.period() / steps;
  std::array<double, 4> x = fixed_steps(KeplerRhs{}, x0, 0.0, dt, steps);
  x[2] = -x[2];
  x[3] = -x[3];
  std::array<double, 4> back = fixed_steps(KeplerRhs{}, x, 0.0, dt, steps);
  back[2] = -back[2];
  back[3] = -back[3];
  const double err = distance(back, x0);
  std::printf("  back at the start to %.3e\n", err);
  EXPECT_LT(err, 2e-14);
}

// -- in runs (simulate) ------------------------------------------------------------

/// Kepler's problem as the relative motion of two bodies, μ = k = 1 (GM = 1).
const lm::RelativeMotion<2> kKepler(1.0, lm::NewtonianGravity{1.0});

/// The state of `orbit` at time t: position (m) and velocity (m/s).
State<2> orbit_state(const lm::KeplerOrbit& orbit, double t) {
  const auto x = orbit.state(t);
  State<2> s;
  s.q << x[0], x[1];
  s.qd << x[2], x[3];
  return s;
}

/// max_i |q_i − the orbit's position at t| (m).
double position_error(const Sample<2>& x, const lm::KeplerOrbit& orbit, double t) {
  const auto exact = orbit.state(t);
  return std::max(std::abs(x.q[0] - exact[0]), std::abs(x.q[1] - exact[1]));
}

SimulationOptions radau(double t_end, double rtol = 1e-10) {
  SimulationOptions o;
  o.method = Method::gauss_radau15;
  o.t_end = t_end;
  o.rtol = rtol;
  o.output_interval = -1;
  return o;
}

TEST(GaussRadau, ProjectileEventsToTheClosedForm) {
  // Launched at 20 m/s, 60° over flat ground: apex at u sin α / g, landing at
  // twice that; the motion is a parabola, which the method integrates exactly.
  const double u = 20.0, alpha = std::acos(-1.0) / 3, g = 9.81;
  State<2> s;
  s.q << 0.0, 0.0;
  s.qd << u * std::cos(alpha), u * std::sin(alpha);
  const RunReport r = simulate(lm::Projectile<>(1.0, g), s, radau(10.0));
  ASSERT_EQ(r.events.size(), 3u);  // apex, landing, stop
  ASSERT_EQ(r.events[0].name, "apex");
  const double apex = u * std::sin(alpha) / g;
  EXPECT_NEAR(r.events[0].t, apex, 1e-14);
  EXPECT_EQ(r.stopped_by, "landing");
  EXPECT_NEAR(r.stopped_at, 2 * apex, 1e-14);
  std::printf("  apex %.3e s, landing %.3e s off the closed form\n", r.events[0].t - apex, r.stopped_at - 2 * apex);
}

TEST(GaussRadau, BouncingBallImpactsToTheClosedForm) {
  // Dropped from rest with its centre at h + R: the k-th impact at
  // t_k = t₁ (1 + 2e + 2e² + … + 2e^{k−1}), t₁ = √(2h/g).
  const double m = 1.0, R = 0.1, e = 0.5, g = 9.81, h = 1.0;
  State<3> s;
  s.q << 0.0, 0.0, h + R;
  s.qd.setZero();
  const RunReport r = simulate(lm::BallAndPlane(m, R, e, g), s, radau(1.5));
  const double t1 = std::sqrt(2 * h / g);
  int checked = 0;
  double worst = 0, tk = t1, gap = 2 * e * t1;
  for (const EventRecord& ev : r.events) {
    if (ev.kind != EventKind::impact || checked == 5) continue;
    EXPECT_NEAR(ev.t, tk, 1e-14) << "impact " << checked + 1;
    worst = std::max(worst, std::abs(ev.t - tk));
    tk += gap;
    gap *= e;
    ++checked;
  }
  EXPECT_EQ(checked, 5);
  std::printf("  first 5 impacts within %.3e s of the closed form\n", worst);
}

TEST(GaussRadau, BouncingComesToRestAsWithDopri5) {
  // The Zeno accumulation of a bouncing ball (e = 0.5) ends in a resting
  // contact: the same impacts as dopri5, the bounce whose approach speed
  // has fallen by e^20 < 1e-6 (zeno_speed_ratio) ending it. It comes at
  // t₁ (1 + 2 Σ_{j=1}^{20} e^j), t₁ = √(2h/g); each impact is located to
  // event_time_tolerance (1e-12 s).
  const double e = 0.5, g = 9.81, h = 1.0;
  State<3> s;
  s.q << 0.0, 0.0, h + 0.1;
  s.qd.setZero();
  const auto rest_time = [&](Method method, std::uint64_t& impacts) {
    SimulationOptions o = radau(4.0);
    o.method = method;
    const RunReport r = simulate(lm::BallAndPlane(1.0, 0.1, e, g), s, o);
    impacts = r.impacts;
    for (const EventRecord& ev : r.events)
      if (ev.kind == EventKind::rest) return ev.t;
    return -1.0;
  };
  std::uint64_t impacts_radau = 0, impacts_dopri = 0;
  const double t_radau = rest_time(Method::gauss_radau15, impacts_radau);
  const double t_dopri = rest_time(Method::dopri5, impacts_dopri);
  double t_rest = 1, ej = 1;
  for (int j = 1; j <= 20; ++j) t_rest += 2 * (ej *= e);
  t_rest *= std::sqrt(2 * h / g);
  std::printf("  rest at %.15f s (dopri5 %.15f s, closed form %.15f s), %llu impacts\n", t_radau, t_dopri, t_rest,
              static_cast<unsigned long long>(impacts_radau));
  EXPECT_EQ(impacts_radau, 20u);
  EXPECT_EQ(impacts_dopri, 20u);
  EXPECT_NEAR(t_radau, t_rest, 20 * 1e-12);
}

TEST(GaussRadau, LinearDragIteratesTheVelocityDependentForce) {
  // m ẍ = −b ẋ, m ÿ = −m g − b ẏ with τ = m/b:
  //   x = u_x τ (1 − e^{−t/τ}),  y = τ (u_y + g τ)(1 − e^{−t/τ}) − g τ t.
  const double m = 2.0, b = 0.7, g = 9.81, tau = m / b, ux = 12.0, uy = 30.0;
  State<2> s;
  s.q << 0.0, 0.0;
  s.qd << ux, uy;
  Recorder<2> rec;
  SimulationOptions o = radau(4.0);
  const RunReport r = simulate(lm::Projectile<lm::Drag::linear>(m, g, 0.0, b), s, o, rec);
  const double t = rec.samples.back().t;
  const double decay = 1 - std::exp(-t / tau);
  EXPECT_NEAR(rec.samples.back().q[0], ux * tau * decay, 1e-12 * ux * tau);
  EXPECT_NEAR(rec.samples.back().q[1], tau * (uy + g * tau) * decay - g * tau * t, 1e-12 * uy * tau);
  EXPECT_NEAR(rec.samples.back().qd[0], ux * std::exp(-t / tau), 1e-12 * ux);
  std::printf("  %llu steps, %llu evaluations\n", static_cast<unsigned long long>(r.steps),
              static_cast<unsigned long long>(r.rhs_evaluations));
}

TEST(GaussRadau, KeplerOrbitsKeepEnergyAndFollowTheClosedForm) {
  // Ten orbits of e = 0.9 in Cartesian coordinates (the relative motion of
  // two bodies, μ = 1, k = 1): the energy to round-off and the position to
  // Kepler's equation.
  const lm::KeplerOrbit orbit(1.0, 0.9, 1.0);
  const double T = 10 * orbit.period();
  Recorder<2> rec;
  const RunReport r = simulate(kKepler, orbit_state(orbit, 0.0), radau(T, 1e-9), rec);
  // The energy ½|q̇|² − 1/|q| in long double: in double its own round-off at
  // periapsis (|V| = 20 |E|) would be as large as what is measured.
  const auto energy = [](const Sample<2>& x) {
    using L = long double;
    return L(0.5) * (L(x.qd[0]) * x.qd[0] + L(x.qd[1]) * x.qd[1]) - 1 / std::sqrt(L(x.q[0]) * x.q[0] + L(x.q[1]) * x.q[1]);
  };
  const long double E0 = energy(rec.samples.front()), E1 = energy(rec.samples.back());
  const double dE = static_cast<double>(std::abs((E1 - E0) / E0));
  const double dq = position_error(rec.samples.back(), orbit, T);
  std::printf("  10 orbits e = 0.9: |dE/E| %.2e, position %.2e, %llu steps, %llu evaluations\n", dE, dq,
              static_cast<unsigned long long>(r.steps), static_cast<unsigned long long>(r.rhs_evaluations));
  // Round-off: about 1e-15 of |E| per step near periapsis, a random walk over
  // the 2 360 steps.
  EXPECT_LT(dE, 3e-14);
  EXPECT_LT(dq, 1e-11);
}

TEST(GaussRadau, ALooserToleranceTakesLongerStepsForALargerError) {
  // Three orbits of e = 0.9 against Kepler's equation: rtol loosens the
  // method (its default keeps the error near round-off).
  const lm::KeplerOrbit orbit(1.0, 0.9, 1.0);
  const double T = 3 * orbit.period();
  double prev_error = 0;
  std::uint64_t prev_evaluations = ~std::uint64_t{0};
  // (Beyond 1e-5 the longer steps need more iterations: no cheaper.)
  for (double tol : {1e-9, 1e-7, 1e-5}) {
    Recorder<2> rec;
    const RunReport r = simulate(kKepler, orbit_state(orbit, 0.0), radau(T, tol), rec);
    const double error = position_error(rec.samples.back(), orbit, T);
    std::printf("  rtol %.0e: error %.2e, %llu evaluations\n", tol, error,
                static_cast<unsigned long long>(r.rhs_evaluations));
    if (tol > 1e-9) {
      EXPECT_GT(error, prev_error) << tol;
      EXPECT_LT(r.rhs_evaluations, prev_evaluations) << tol;
    }
    prev_error = error;
    prev_evaluations = r.rhs_evaluations;
  }
}

TEST(GaussRadau, ChaoticDoublePendulumMatchesAnIndependentReference) {
  // θ₁ = θ₂ = 2 rad from rest (m = l = 1, g = 9.81) to t = 5 s: the model's
  // equations (automatic differentiation of T and V) against the state from
  // hand-written equations integrated at 70 digits by Gragg–Bulirsch–Stoer
  // extrapolation in mpmath (bench/reference/double_pendulum.txt).
  State<2> s;
  s.q << 2.0, 2.0;
  s.qd << 0.0, 0.0;
  Recorder<2> rec;
  simulate(lm::DoublePendulum(1, 1, 1, 1, 9.81), s, radau(5.0, 1e-9), rec);
  const auto& end = rec.samples.back();
  const std::array<double, 4> reference{-1.410706688941584255, -4.041716878877189688, -1.984147306034064826,
                                        -5.429525625408064226};
  double error = 0;
  for (int i = 0; i < 2; ++i)
    error = std::max({error, std::abs(end.q[i] - reference[static_cast<std::size_t>(i)]),
                      std::abs(end.qd[i] - reference[static_cast<std::size_t>(2 + i)])});
  std::printf("  t = 5 s: max error %.2e\n", error);
  EXPECT_LT(error, 1e-12);
}

TEST(GaussRadau, SamplesBetweenStepsFollowTheClosedForm) {
  // Samples every 0.01 s come from the steps' polynomials, through the
  // periapsis events the model watches (each retakes its step to the
  // event, and the samples before it come from that shorter step): every
  // sample of three orbits of e = 0.5 against Kepler's equation.
  const lm::KeplerOrbit orbit(1.0, 0.5, 1.0);
  SimulationOptions o = radau(3 * orbit.period(), 1e-10);
  o.output_interval = 0.01;
  Recorder<2> rec;
  const RunReport r = simulate(kKepler, orbit_state(orbit, 0.3), o, rec);
  EXPECT_EQ(r.events.size(), 3u);  // three periapses
  double worst = 0;
  for (const auto& x : rec.samples) {
    const auto exact = orbit.state(x.t + 0.3);
    for (int i = 0; i < 2; ++i)
      worst = std::max({worst, std::abs(x.q[i] - exact[static_cast<std::size_t>(i)]),
                        std::abs(x.qd[i] - exact[static_cast<std::size_t>(2 + i)])});
  }
  std::printf("  %zu samples, worst %.2e\n", rec.samples.size(), worst);
  EXPECT_GT(rec.samples.size(), 1800u);
  EXPECT_LT(worst, 1e-11);
}

TEST(GaussRadau, ConstrainedPendulumAgreesWithTheAngle) {
  // The pendulum as a constrained point (x, y, |r| = l) and as an angle θ,
  // both with this method: the same bob position after 5 s.
  const double theta0 = 1.2;
  State<1> a;
  a.q << theta0;
  a.qd << 0.0;
  Recorder<1> angle;
  simulate(lm::SimplePendulum(1.0, 1.0, 9.81), a, radau(5.0, 1e-12), angle);
  State<2> c;
  c.q << std::sin(theta0), -std::cos(theta0);
  c.qd << 0.0, 0.0;
  Recorder<2> cart;
  const RunReport r = simulate(lm::CartesianPendulum(1.0, 1.0, 9.81), c, radau(5.0, 1e-12), cart);
  const double th = angle.samples.back().q[0];
  EXPECT_NEAR(cart.samples.back().q[0], std::sin(th), 1e-10);
  EXPECT_NEAR(cart.samples.back().q[1], -std::cos(th), 1e-10);
  EXPECT_LT(r.constraints.max_position_residual, 1e-12);
}

}  // namespace
