// The simulate() driver against raw Boost.Odeint with the same hand-coded
// right-hand side, stepper and tolerances; and the full AD-derived run.
// Double pendulum from θ1 = θ2 = 2 rad at rest, t ∈ [0, 20] s, with dopri5
// and fehlberg78 (rtol 1e-10, atol 1e-12) and rk4 (dt = 1 ms): the same
// steps in both loops (counted), so the ratio is the driver's overhead.
// And the harmonic oscillator, whose right-hand side is one multiply: there
// the driver's per-step work is the largest share it can be.
#include <benchmark/benchmark.h>

#include <array>

#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/integrate/integrate_n_steps.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

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

using X = std::array<double, 4>;

/// ẋ = [q̇; q̈] with the hand-coded q̈.
struct HandRhs {
  const bench::HandDoublePendulum* p;
  void operator()(const X& x, X& dxdt, double) const {
    dxdt[0] = x[2];
    dxdt[1] = x[3];
    bench::double_pendulum_qdd(*p, x.data(), x.data() + 2, dxdt.data() + 2);
  }
};

template <class Stepper>
void raw_adaptive(benchmark::State& st) {
  bench::HandDoublePendulum p;
  benchmark::DoNotOptimize(p);  // parameters from memory, as in simulate(): not compile-time constants
  std::size_t steps = 0;
  for (auto _ : st) {
    X x = {2.0, 2.0, 0.0, 0.0};
    using Controlled = odeint::controlled_runge_kutta<Stepper>;
    Controlled stepper{typename Controlled::error_checker_type(kAtol, kRtol)};
    steps = odeint::integrate_adaptive(stepper, HandRhs{&p}, x, 0.0, kTEnd, kDt);
    benchmark::DoNotOptimize(x);
  }
  st.counters["steps"] = static_cast<double>(steps);
}

void BM_RawOdeint_Dopri5_DoublePendulum(benchmark::State& st) { raw_adaptive<odeint::runge_kutta_dopri5<X>>(st); }
BENCHMARK(BM_RawOdeint_Dopri5_DoublePendulum)->Unit(benchmark::kMillisecond);

void BM_RawOdeint_Fehlberg78_DoublePendulum(benchmark::State& st) {
  raw_adaptive<odeint::runge_kutta_fehlberg78<X>>(st);
}
BENCHMARK(BM_RawOdeint_Fehlberg78_DoublePendulum)->Unit(benchmark::kMillisecond);

void BM_RawOdeint_Rk4_DoublePendulum(benchmark::State& st) {
  bench::HandDoublePendulum p;
  benchmark::DoNotOptimize(p);  // parameters from memory, as in simulate(): not compile-time constants
  const auto n = static_cast<std::size_t>(kTEnd / kDt + 0.5);
  for (auto _ : st) {
    X x = {2.0, 2.0, 0.0, 0.0};
    odeint::integrate_n_steps(odeint::runge_kutta4<X>{}, HandRhs{&p}, x, 0.0, kDt, n);
    benchmark::DoNotOptimize(x);
  }
  st.counters["steps"] = static_cast<double>(n);
}
BENCHMARK(BM_RawOdeint_Rk4_DoublePendulum)->Unit(benchmark::kMillisecond);

template <class Model>
void run_simulate(benchmark::State& st, const Model& p, const char* method) {
  lagrangian::SimulationOptions o;
  o.method = method;
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
  run_simulate(st, model, "dopri5");
}
BENCHMARK(BM_Simulate_HandRHS_Dopri5_DoublePendulum)->Unit(benchmark::kMillisecond);

void BM_Simulate_AD_Dopri5_DoublePendulum(benchmark::State& st) {
  run_simulate(st, lagrangian::models::DoublePendulum{}, "dopri5");
}
BENCHMARK(BM_Simulate_AD_Dopri5_DoublePendulum)->Unit(benchmark::kMillisecond);

void BM_Simulate_HandRHS_Fehlberg78_DoublePendulum(benchmark::State& st) {
  const bench::HandDoublePendulum model;
  run_simulate(st, model, "fehlberg78");
}
BENCHMARK(BM_Simulate_HandRHS_Fehlberg78_DoublePendulum)->Unit(benchmark::kMillisecond);

void BM_Simulate_AD_Fehlberg78_DoublePendulum(benchmark::State& st) {
  run_simulate(st, lagrangian::models::DoublePendulum{}, "fehlberg78");
}
BENCHMARK(BM_Simulate_AD_Fehlberg78_DoublePendulum)->Unit(benchmark::kMillisecond);

void BM_Simulate_HandRHS_Rk4_DoublePendulum(benchmark::State& st) {
  const bench::HandDoublePendulum model;
  run_simulate(st, model, "rk4");
}
BENCHMARK(BM_Simulate_HandRHS_Rk4_DoublePendulum)->Unit(benchmark::kMillisecond);

void BM_Simulate_AD_Rk4_DoublePendulum(benchmark::State& st) {
  run_simulate(st, lagrangian::models::DoublePendulum{}, "rk4");
}
BENCHMARK(BM_Simulate_AD_Rk4_DoublePendulum)->Unit(benchmark::kMillisecond);

// The worst case for the driver: a right-hand side of one multiply. The
// harmonic oscillator m ẍ = −k x (m = 0.5 kg, k = 2 N/m) from x = 0.7 m,
// ẋ = −0.3 m/s over t ∈ [0, 20] s, the same steppers and tolerances.

/// The oscillator with its q̈ = −(k/m) x supplied by the model.
struct HandOscillator : lagrangian::models::HarmonicOscillator {
  using HarmonicOscillator::HarmonicOscillator;
  void accelerations(const lagrangian::Vec<double, 1>& q, const lagrangian::Vec<double, 1>&, double,
                     lagrangian::Vec<double, 1>& qdd) const {
    qdd[0] = -(k / m) * q[0];
  }
};

using X1 = std::array<double, 2>;

struct OscillatorRhs {
  const HandOscillator* p;
  void operator()(const X1& x, X1& dxdt, double) const {
    dxdt[0] = x[1];
    dxdt[1] = -(p->k / p->m) * x[0];
  }
};

template <class Stepper>
void raw_oscillator(benchmark::State& st) {
  HandOscillator p(0.5, 2.0);
  benchmark::DoNotOptimize(p);
  std::size_t steps = 0;
  for (auto _ : st) {
    X1 x = {0.7, -0.3};
    using Controlled = odeint::controlled_runge_kutta<Stepper>;
    Controlled stepper{typename Controlled::error_checker_type(kAtol, kRtol)};
    steps = odeint::integrate_adaptive(stepper, OscillatorRhs{&p}, x, 0.0, kTEnd, kDt);
    benchmark::DoNotOptimize(x);
  }
  st.counters["steps"] = static_cast<double>(steps);
}

void BM_RawOdeint_Dopri5_Oscillator(benchmark::State& st) { raw_oscillator<odeint::runge_kutta_dopri5<X1>>(st); }
BENCHMARK(BM_RawOdeint_Dopri5_Oscillator)->Unit(benchmark::kMillisecond);

void BM_RawOdeint_Fehlberg78_Oscillator(benchmark::State& st) {
  raw_oscillator<odeint::runge_kutta_fehlberg78<X1>>(st);
}
BENCHMARK(BM_RawOdeint_Fehlberg78_Oscillator)->Unit(benchmark::kMillisecond);

void BM_RawOdeint_Rk4_Oscillator(benchmark::State& st) {
  HandOscillator p(0.5, 2.0);
  benchmark::DoNotOptimize(p);
  const auto n = static_cast<std::size_t>(kTEnd / kDt + 0.5);
  for (auto _ : st) {
    X1 x = {0.7, -0.3};
    odeint::integrate_n_steps(odeint::runge_kutta4<X1>{}, OscillatorRhs{&p}, x, 0.0, kDt, n);
    benchmark::DoNotOptimize(x);
  }
  st.counters["steps"] = static_cast<double>(n);
}
BENCHMARK(BM_RawOdeint_Rk4_Oscillator)->Unit(benchmark::kMillisecond);

template <class Model>
void simulate_oscillator(benchmark::State& st, const Model& p, const char* method) {
  lagrangian::SimulationOptions o;
  o.method = method;
  o.t_end = kTEnd;
  o.rtol = kRtol;
  o.atol = kAtol;
  o.dt = kDt;
  o.output_interval = -1;
  lagrangian::State<1> s;
  s.q[0] = 0.7;
  s.qd[0] = -0.3;
  lagrangian::RunReport r;
  for (auto _ : st) {
    r = lagrangian::simulate(p, s, o);
    benchmark::DoNotOptimize(r.steps);
  }
  st.counters["steps"] = static_cast<double>(r.steps);
  st.counters["rejected"] = static_cast<double>(r.rejected_steps);
}

void BM_Simulate_HandRHS_Dopri5_Oscillator(benchmark::State& st) {
  simulate_oscillator(st, HandOscillator(0.5, 2.0), "dopri5");
}
BENCHMARK(BM_Simulate_HandRHS_Dopri5_Oscillator)->Unit(benchmark::kMillisecond);

void BM_Simulate_AD_Dopri5_Oscillator(benchmark::State& st) {
  simulate_oscillator(st, lagrangian::models::HarmonicOscillator(0.5, 2.0), "dopri5");
}
BENCHMARK(BM_Simulate_AD_Dopri5_Oscillator)->Unit(benchmark::kMillisecond);

void BM_Simulate_HandRHS_Fehlberg78_Oscillator(benchmark::State& st) {
  simulate_oscillator(st, HandOscillator(0.5, 2.0), "fehlberg78");
}
BENCHMARK(BM_Simulate_HandRHS_Fehlberg78_Oscillator)->Unit(benchmark::kMillisecond);

void BM_Simulate_AD_Fehlberg78_Oscillator(benchmark::State& st) {
  simulate_oscillator(st, lagrangian::models::HarmonicOscillator(0.5, 2.0), "fehlberg78");
}
BENCHMARK(BM_Simulate_AD_Fehlberg78_Oscillator)->Unit(benchmark::kMillisecond);

void BM_Simulate_HandRHS_Rk4_Oscillator(benchmark::State& st) {
  simulate_oscillator(st, HandOscillator(0.5, 2.0), "rk4");
}
BENCHMARK(BM_Simulate_HandRHS_Rk4_Oscillator)->Unit(benchmark::kMillisecond);

void BM_Simulate_AD_Rk4_Oscillator(benchmark::State& st) {
  simulate_oscillator(st, lagrangian::models::HarmonicOscillator(0.5, 2.0), "rk4");
}
BENCHMARK(BM_Simulate_AD_Rk4_Oscillator)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
