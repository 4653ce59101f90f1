// The simulate() driver against raw Boost.Odeint with the same hand-coded
// right-hand side, stepper and tolerances; and the full AD-derived run.
#include <benchmark/benchmark.h>

#include <array>

#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>

#include "hand_coded.hpp"
#include "lagrangian/simulate.hpp"

namespace {

namespace odeint = boost::numeric::odeint;
constexpr double kRtol = 1e-10, kAtol = 1e-12, kTEnd = 20.0, kDt = 1e-3;

lagrangian::State<2> initial() {
  lagrangian::State<2> s;
  s.q << 2.0, 2.0;
  return s;
}

void BM_RawOdeint_Dopri5_DoublePendulum(benchmark::State& st) {
  const bench::HandDoublePendulum p;
  using X = std::array<double, 4>;
  std::size_t steps = 0;
  for (auto _ : st) {
    X x = {2.0, 2.0, 0.0, 0.0};
    using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<X>>;
    Controlled stepper{Controlled::error_checker_type(kAtol, kRtol)};
    steps = odeint::integrate_adaptive(
        stepper,
        [&p](const X& x, X& dxdt, double) {
          dxdt[0] = x[2];
          dxdt[1] = x[3];
          bench::double_pendulum_qdd(p, x.data(), x.data() + 2, dxdt.data() + 2);
        },
        x, 0.0, kTEnd, kDt);
    benchmark::DoNotOptimize(x);
  }
  st.counters["steps"] = static_cast<double>(steps);
}
BENCHMARK(BM_RawOdeint_Dopri5_DoublePendulum)->Unit(benchmark::kMillisecond);

template <class Model>
void run_simulate(benchmark::State& st, const Model& p) {
  lagrangian::SimulationOptions o;
  o.method = "dopri5";
  o.t_end = kTEnd;
  o.rtol = kRtol;
  o.atol = kAtol;
  o.dt = kDt;
  o.output_interval = -1;  // first and last state only, as the raw loop
  lagrangian::RunReport r;
  for (auto _ : st) {
    r = lagrangian::simulate(p, initial(), o);
    benchmark::DoNotOptimize(r.steps);
  }
  st.counters["steps"] = static_cast<double>(r.steps);
  st.counters["rejected"] = static_cast<double>(r.rejected_steps);
}

void BM_Simulate_HandRHS_Dopri5_DoublePendulum(benchmark::State& st) {
  const bench::HandDoublePendulum model;
  run_simulate(st, model);
}
BENCHMARK(BM_Simulate_HandRHS_Dopri5_DoublePendulum)->Unit(benchmark::kMillisecond);

void BM_Simulate_AD_Dopri5_DoublePendulum(benchmark::State& st) {
  run_simulate(st, lagrangian::models::DoublePendulum{});
}
BENCHMARK(BM_Simulate_AD_Dopri5_DoublePendulum)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
