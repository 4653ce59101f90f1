// The simulate() driver against raw Boost.Odeint with the same hand-coded
// right-hand side, stepper and tolerances; and the full AD-derived run.
// Double pendulum from θ1 = θ2 = 2 rad at rest, t ∈ [0, 20] s, with dopri5
// and fehlberg78 (rtol 1e-10, atol 1e-12) and rk4 (dt = 1 ms): the same
// steps in both loops (counted), so the ratio is the driver's overhead. For
// the double pendulum also raw Odeint with q̈ out of line (not inlined into
// the stages), which is how the compiled-once driver reaches every q̈.
// simulate() runs the hand-coded models twice: through the loops compiled
// once in the library, and wrapped by lagrangian::inlined() (the loops
// compiled here with q̈ inlined). And the harmonic oscillator, whose
// right-hand side is one multiply: there the driver's per-step work is the
// largest share it can be.
#include <benchmark/benchmark.h>

#include <array>

#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/integrate/integrate_n_steps.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include "hand_coded.hpp"
#include "lagrangian/integrate/inlined.hpp"
#include "lagrangian/integrate/simulate.hpp"

namespace {

namespace odeint = boost::numeric::odeint;
constexpr double kRtol = 1e-10, kAtol = 1e-12, kTEnd = 20.0, kDt = 1e-3;

using X = std::array<double, 4>;   // double pendulum: [θ1, θ2, θ̇1, θ̇2]
using X1 = std::array<double, 2>;  // oscillator: [x, ẋ]

/// ẋ = [q̇; q̈] with the hand-coded q̈.
struct HandRhs {
  const bench::HandDoublePendulum* p;
  void operator()(const X& x, X& dxdt, double) const {
    dxdt[0] = x[2];
    dxdt[1] = x[3];
    bench::double_pendulum_qdd(*p, x.data(), x.data() + 2, dxdt.data() + 2);
  }
};

/// The same with q̈ compiled out of line, as simulate() reaches it: raw
/// Odeint's loop without the inlining of q̈ into its stages. The difference
/// to HandRhs is what inlining is worth; the difference to simulate() is
/// the driver's own cost.
[[gnu::noinline]] void double_pendulum_xdot(const bench::HandDoublePendulum& p, const double* x, double* dxdt) {
  dxdt[0] = x[2];
  dxdt[1] = x[3];
  bench::double_pendulum_qdd(p, x, x + 2, dxdt + 2);
}
struct OutOfLineRhs {
  const bench::HandDoublePendulum* p;
  void operator()(const X& x, X& dxdt, double) const { double_pendulum_xdot(*p, x.data(), dxdt.data()); }
};

// The worst case for the driver: a right-hand side of one multiply. The
// harmonic oscillator m ẍ = −k x (m = 0.5 kg, k = 2 N/m) from x = 0.7 m,
// ẋ = −0.3 m/s over t ∈ [0, 20] s, the same steppers and tolerances.

/// The oscillator with its q̈ = −(k/m) x supplied by the model.
struct HandOscillator : lagrangian::models::HarmonicOscillator {
  using lagrangian::models::HarmonicOscillator::BasicHarmonicOscillator;
  void accelerations(const lagrangian::Vec<double, 1>& q, const lagrangian::Vec<double, 1>&, double,
                     lagrangian::Vec<double, 1>& qdd) const {
    qdd[0] = -(k / m) * q[0];
  }
};

struct OscillatorRhs {
  const HandOscillator* p;
  void operator()(const X1& x, X1& dxdt, double) const {
    dxdt[0] = x[1];
    dxdt[1] = -(p->k / p->m) * x[0];
  }
};

/// The two systems: the hand-coded model and Odeint system, the AD model,
/// and the initial state as Odeint's x and as simulate()'s State.
struct DoublePendulumCase {
  using Hand = bench::HandDoublePendulum;
  using Rhs = HandRhs;
  static Hand hand() { return Hand(); }
  static lagrangian::models::DoublePendulum ad() { return lagrangian::models::DoublePendulum{}; }
  static X x0() { return {2.0, 2.0, 0.0, 0.0}; }
};

struct OutOfLineCase : DoublePendulumCase {
  using Rhs = OutOfLineRhs;
};

struct OscillatorCase {
  using Hand = HandOscillator;
  using Rhs = OscillatorRhs;
  static Hand hand() { return Hand(0.5, 2.0); }
  static lagrangian::models::HarmonicOscillator ad() { return lagrangian::models::HarmonicOscillator(0.5, 2.0); }
  static X1 x0() { return {0.7, -0.3}; }
};

/// Raw Odeint: integrate_adaptive with the controlled Stepper, or rk4's
/// integrate_n_steps, on the hand-coded system.
template <class Case, class Stepper>
void raw_adaptive(benchmark::State& st) {
  auto p = Case::hand();
  benchmark::DoNotOptimize(p);  // parameters from memory, as in simulate(): not compile-time constants
  std::size_t steps = 0;
  for (auto _ : st) {
    auto x = Case::x0();
    using Controlled = odeint::controlled_runge_kutta<Stepper>;
    Controlled stepper{typename Controlled::error_checker_type(kAtol, kRtol)};
    steps = odeint::integrate_adaptive(stepper, typename Case::Rhs{&p}, x, 0.0, kTEnd, kDt);
    benchmark::DoNotOptimize(x);
  }
  st.counters["steps"] = static_cast<double>(steps);
}

template <class Case>
void raw_rk4(benchmark::State& st) {
  auto p = Case::hand();
  benchmark::DoNotOptimize(p);  // parameters from memory, as in simulate(): not compile-time constants
  using XC = decltype(Case::x0());
  const auto n = static_cast<std::size_t>(kTEnd / kDt + 0.5);
  for (auto _ : st) {
    XC x = Case::x0();
    odeint::integrate_n_steps(odeint::runge_kutta4<XC>{}, typename Case::Rhs{&p}, x, 0.0, kDt, n);
    benchmark::DoNotOptimize(x);
  }
  st.counters["steps"] = static_cast<double>(n);
}

/// simulate() from the same initial state, samples only at the two ends.
template <class Case, class Model>
void run_simulate(benchmark::State& st, const Model& model, const char* method) {
  lagrangian::SimulationOptions o;
  o.method = lagrangian::parse_method(method, "method");
  o.t_end = kTEnd;
  o.rtol = kRtol;
  o.atol = kAtol;
  o.dt = kDt;
  o.output_interval = -1;  // first and last state only, as the raw loop
  constexpr int n = lagrangian::coordinate_count_v<Model>;
  const auto x0 = Case::x0();
  lagrangian::State<n> s;
  for (int i = 0; i < n; ++i) {
    s.q[i] = x0[static_cast<std::size_t>(i)];
    s.qd[i] = x0[static_cast<std::size_t>(n + i)];
  }
  lagrangian::RunReport r;
  for (auto _ : st) {
    r = lagrangian::simulate(model, s, o);
    benchmark::DoNotOptimize(r.steps);
  }
  st.counters["steps"] = static_cast<double>(r.steps);
  st.counters["rejected"] = static_cast<double>(r.rejected_steps);
}

template <class Case>
void hand_simulate(benchmark::State& st, const char* method) {
  run_simulate<Case>(st, Case::hand(), method);
}

template <class Case>
void inlined_simulate(benchmark::State& st, const char* method) {
  run_simulate<Case>(st, lagrangian::inlined(Case::hand()), method);
}

template <class Case>
void ad_simulate(benchmark::State& st, const char* method) {
  run_simulate<Case>(st, Case::ad(), method);
}

// Benchmark names: BM_{RawOdeint,Simulate_HandRHS,Simulate_HandRHSInlined,Simulate_AD}_{Dopri5,Fehlberg78,Rk4}_{DoublePendulum,Oscillator}
// (scripts/count-instructions and bench/peers/run_peers.sh select them by name).
#define LAGRANGIAN_DRIVER_BENCHMARKS(System, Case, Xs)                                                      \
  void BM_RawOdeint_Dopri5_##System(benchmark::State& st) {                                                \
    raw_adaptive<Case, odeint::runge_kutta_dopri5<Xs>>(st);                                               \
  }                                                                                                         \
  void BM_RawOdeint_Fehlberg78_##System(benchmark::State& st) {                                            \
    raw_adaptive<Case, odeint::runge_kutta_fehlberg78<Xs>>(st);                                           \
  }                                                                                                         \
  void BM_RawOdeint_Rk4_##System(benchmark::State& st) { raw_rk4<Case>(st); }                               \
  void BM_Simulate_HandRHS_Dopri5_##System(benchmark::State& st) { hand_simulate<Case>(st, "dopri5"); }      \
  void BM_Simulate_HandRHSInlined_Dopri5_##System(benchmark::State& st) {                                 \
    inlined_simulate<Case>(st, "dopri5");                                                                  \
  }                                                                                                         \
  void BM_Simulate_HandRHSInlined_Fehlberg78_##System(benchmark::State& st) {                             \
    inlined_simulate<Case>(st, "fehlberg78");                                                              \
  }                                                                                                         \
  void BM_Simulate_HandRHSInlined_Rk4_##System(benchmark::State& st) { inlined_simulate<Case>(st, "rk4"); } \
  void BM_Simulate_AD_Dopri5_##System(benchmark::State& st) { ad_simulate<Case>(st, "dopri5"); }            \
  void BM_Simulate_HandRHS_Fehlberg78_##System(benchmark::State& st) { hand_simulate<Case>(st, "fehlberg78"); } \
  void BM_Simulate_AD_Fehlberg78_##System(benchmark::State& st) { ad_simulate<Case>(st, "fehlberg78"); }    \
  void BM_Simulate_HandRHS_Rk4_##System(benchmark::State& st) { hand_simulate<Case>(st, "rk4"); }            \
  void BM_Simulate_AD_Rk4_##System(benchmark::State& st) { ad_simulate<Case>(st, "rk4"); }                  \
  BENCHMARK(BM_RawOdeint_Dopri5_##System)->Unit(benchmark::kMillisecond);                                  \
  BENCHMARK(BM_RawOdeint_Fehlberg78_##System)->Unit(benchmark::kMillisecond);                              \
  BENCHMARK(BM_RawOdeint_Rk4_##System)->Unit(benchmark::kMillisecond);                                     \
  BENCHMARK(BM_Simulate_HandRHS_Dopri5_##System)->Unit(benchmark::kMillisecond);                           \
  BENCHMARK(BM_Simulate_HandRHSInlined_Dopri5_##System)->Unit(benchmark::kMillisecond);                    \
  BENCHMARK(BM_Simulate_HandRHSInlined_Fehlberg78_##System)->Unit(benchmark::kMillisecond);                \
  BENCHMARK(BM_Simulate_HandRHSInlined_Rk4_##System)->Unit(benchmark::kMillisecond);                       \
  BENCHMARK(BM_Simulate_AD_Dopri5_##System)->Unit(benchmark::kMillisecond);                                \
  BENCHMARK(BM_Simulate_HandRHS_Fehlberg78_##System)->Unit(benchmark::kMillisecond);                       \
  BENCHMARK(BM_Simulate_AD_Fehlberg78_##System)->Unit(benchmark::kMillisecond);                            \
  BENCHMARK(BM_Simulate_HandRHS_Rk4_##System)->Unit(benchmark::kMillisecond);                              \
  BENCHMARK(BM_Simulate_AD_Rk4_##System)->Unit(benchmark::kMillisecond)

LAGRANGIAN_DRIVER_BENCHMARKS(DoublePendulum, DoublePendulumCase, X);
void BM_RawOdeintOutOfLine_Dopri5_DoublePendulum(benchmark::State& st) {
  raw_adaptive<OutOfLineCase, odeint::runge_kutta_dopri5<X>>(st);
}
void BM_RawOdeintOutOfLine_Fehlberg78_DoublePendulum(benchmark::State& st) {
  raw_adaptive<OutOfLineCase, odeint::runge_kutta_fehlberg78<X>>(st);
}
void BM_RawOdeintOutOfLine_Rk4_DoublePendulum(benchmark::State& st) { raw_rk4<OutOfLineCase>(st); }
BENCHMARK(BM_RawOdeintOutOfLine_Dopri5_DoublePendulum)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RawOdeintOutOfLine_Fehlberg78_DoublePendulum)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RawOdeintOutOfLine_Rk4_DoublePendulum)->Unit(benchmark::kMillisecond);
LAGRANGIAN_DRIVER_BENCHMARKS(Oscillator, OscillatorCase, X1);

}  // namespace

BENCHMARK_MAIN();
