// What a scene costs: a gravity-only scene against a hand-coded projectile
// right-hand side in the same Odeint stepper and loop, and the cost per
// right-hand side as effects are added one by one.
//
//   build/bench/bench_scenes --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>

#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/run.hpp"
#include "../src/scene/particle_engine.hpp"

namespace {

using namespace lagrangian::scene;
using X = std::vector<double>;

constexpr double kTEnd = 20.0, kInterval = 0.01, kRtol = 1e-10, kAtol = 1e-12;

Scene projectile_scene(lagrangian::Method method) {
  Scene s;
  s.name = "projectile";
  s.bodies.push_back({.name = "ball", .mass = 0.2, .position = {0, 0, 1}, .velocity = {10, 0, 10}});
  s.gravity = UniformGravity{{0, 0, -9.81}};
  s.run.method = method;
  s.run.t_end = kTEnd;
  s.run.rtol = kRtol;
  s.run.atol = kAtol;
  s.run.dt = 1e-3;
  s.run.output_interval = kInterval;
  return s;
}

/// The hand-coded projectile: ẋ = [v; g].
struct HandProjectile {
  void operator()(const X& x, X& dx, double) const {
    dx[0] = x[3];
    dx[1] = x[4];
    dx[2] = x[5];
    dx[3] = 0.0;
    dx[4] = 0.0;
    dx[5] = -9.81;
  }
};

/// The driver's loop (integrate.hpp) with the hand-coded right-hand side:
/// dopri5 steps freely, the samples every kInterval come from its dense
/// output, T + V and the momentum are evaluated at each.
double hand_dopri5() {
  namespace odeint = boost::numeric::odeint;
  using C = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<X>>;
  C stepper{C::error_checker_type(kAtol, kRtol)};
  const HandProjectile f;
  X x{0, 0, 1, 10, 0, 10}, dxdt(6), x_old(6), dxdt_old(6), buf(6);
  f(x, dxdt, 0.0);
  double t = 0, dt = 1e-3, next = kInterval, acc = 0;
  std::size_t steps = 0;
  auto sample = [&acc](const X& s) {
    acc += 0.5 * 0.2 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]) + 0.2 * 9.81 * s[2] + 0.2 * (s[3] + s[4] + s[5]);
  };
  while (kTEnd - t > 1e-12) {
    const bool clamped = t + dt > kTEnd;
    double d = clamped ? kTEnd - t : dt;
    x_old = x;
    dxdt_old = dxdt;
    const double t_old = t;
    if (stepper.try_step(f, x, dxdt, t, d) == odeint::success) {
      ++steps;
      if (clamped) t = kTEnd;
      for (double v : x)
        if (!std::isfinite(v)) return -1;
      for (; next <= t + 1e-12; next += kInterval) {
        if (std::abs(next - t) <= 1e-12) {
          sample(x);
        } else {
          stepper.stepper().calc_state(next, buf, x_old, dxdt_old, t_old, x, dxdt, t);
          sample(buf);
        }
      }
      dt = clamped ? std::max(dt, d) : d;
    } else {
      dt = d;
    }
  }
  return acc + x[2] + static_cast<double>(steps);
}

double hand_rk4() {
  namespace odeint = boost::numeric::odeint;
  odeint::runge_kutta4<X> stepper;
  X x{0, 0, 1, 10, 0, 10};
  double t = 0, acc = 0;
  const double dt = 1e-3;
  const auto n = static_cast<std::size_t>(std::llround(kTEnd / dt));
  for (std::size_t k = 1; k <= n; ++k) {
    stepper.do_step(HandProjectile{}, x, t, dt);
    t = static_cast<double>(k) * dt;
    for (double v : x)
      if (!std::isfinite(v)) return -1;
    if (k % 10 == 0)
      acc += 0.5 * 0.2 * (x[3] * x[3] + x[4] * x[4] + x[5] * x[5]) + 0.2 * 9.81 * x[2] + 0.2 * (x[3] + x[4] + x[5]);
  }
  return acc + x[2];
}

void BM_HandProjectile_dopri5(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(hand_dopri5());
}
BENCHMARK(BM_HandProjectile_dopri5)->Unit(benchmark::kMicrosecond);

void BM_SceneProjectile_dopri5(benchmark::State& state) {
  const Scene s = projectile_scene(lagrangian::Method::dopri5);
  RunControls c;
  c.write_outputs = false;
  for (auto _ : state) benchmark::DoNotOptimize(run(s, c).report.steps);
}
BENCHMARK(BM_SceneProjectile_dopri5)->Unit(benchmark::kMicrosecond);

void BM_HandProjectile_rk4(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(hand_rk4());
}
BENCHMARK(BM_HandProjectile_rk4)->Unit(benchmark::kMicrosecond);

void BM_SceneProjectile_rk4(benchmark::State& state) {
  const Scene s = projectile_scene(lagrangian::Method::rk4);
  RunControls c;
  c.write_outputs = false;
  for (auto _ : state) benchmark::DoNotOptimize(run(s, c).report.steps);
}
BENCHMARK(BM_SceneProjectile_rk4)->Unit(benchmark::kMicrosecond);

/// One right-hand side of N projectiles: hand-coded (ẋ = [v; g], inlined)
/// against the scene's composed one (one indirect call, then the declared
/// kernels only).
Scene projectiles(int n) {
  Scene s;
  for (int i = 0; i < n; ++i)
    s.bodies.push_back({.name = "p" + std::to_string(i), .mass = 0.2, .position = {0.0 + i, 0, 1}, .velocity = {10, 0, 10}});
  s.gravity = UniformGravity{{0, 0, -9.81}};
  return s;
}

void BM_HandRhs(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), dim = 3 * n;
  X x(static_cast<std::size_t>(2 * dim), 1.0), dx(x.size());
  for (auto _ : state) {
    benchmark::DoNotOptimize(x.data());
    for (int i = 0; i < dim; ++i) dx[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(dim + i)];
    for (int i = 0; i < n; ++i) {
      dx[static_cast<std::size_t>(dim + 3 * i)] = 0.0;
      dx[static_cast<std::size_t>(dim + 3 * i + 1)] = 0.0;
      dx[static_cast<std::size_t>(dim + 3 * i + 2)] = -9.81;
    }
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_HandRhs)->Arg(1)->Arg(10)->Arg(1000);

void BM_SceneRhs(benchmark::State& state) {
  lagrangian::scene::detail::ComposedRhs rhs(projectiles(static_cast<int>(state.range(0))));
  X x(static_cast<std::size_t>(rhs.size()), 1.0), dx(x.size());
  for (auto _ : state) {
    benchmark::DoNotOptimize(x.data());
    rhs(x.data(), dx.data(), 0.0);
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_SceneRhs)->Arg(1)->Arg(10)->Arg(1000);

/// Two bodies with effects added one at a time (rk4, dt = 1 ms, 2 s): the
/// counter ns_per_rhs is the wall time per right-hand side evaluation.
Scene with_effects(int k) {
  Scene s;
  s.name = "effects";
  s.bodies.push_back({.name = "a", .mass = 1.0, .radius = 0.05, .position = {0, 0, 2}, .velocity = {0.5, 0, 0}});
  s.bodies.push_back({.name = "b", .mass = 2.0, .radius = 0.05, .position = {1, 0, 2}, .velocity = {0, 0.5, 0}});
  s.run.method = lagrangian::Method::rk4;
  s.run.dt = 1e-3;
  s.run.t_end = 2.0;
  s.run.output_interval = 0.1;
  if (k >= 0) s.gravity = UniformGravity{};
  if (k >= 1) s.linear_drag.push_back({.coefficient = 0.01});
  if (k >= 2) s.quadratic_drag.push_back({.coefficient = 0.01});
  if (k >= 3) s.springs.push_back({.a = "a", .b = "b", .stiffness = 50, .rest_length = 1});
  if (k >= 4) s.newtonian_gravity = NewtonianGravity{};
  if (k >= 5) s.links.push_back({.a = "a", .anchor = {0, 0, 3}});
  if (k >= 6) s.planes.push_back({.name = "floor", .point = {0, 0, 0}, .normal = {0, 0, 1}, .restitution = 0.9});
  if (k >= 7) s.sphere_contacts = SphereContacts{0.9, {}};
  return s;
}

void BM_SceneEffects(benchmark::State& state) {
  const Scene s = with_effects(static_cast<int>(state.range(0)));
  RunControls c;
  c.write_outputs = false;
  std::uint64_t rhs = 0;
  for (auto _ : state) {
    const RunResult r = run(s, c);
    rhs = r.report.rhs_evaluations;
    benchmark::DoNotOptimize(r.report.steps);
  }
  state.counters["rhs_per_run"] = static_cast<double>(rhs);
  state.counters["ns_per_rhs"] = benchmark::Counter(static_cast<double>(rhs) * 1e-9,
                                                    benchmark::Counter::kIsIterationInvariantRate |
                                                        benchmark::Counter::kInvert);
}
BENCHMARK(BM_SceneEffects)->DenseRange(0, 7)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
