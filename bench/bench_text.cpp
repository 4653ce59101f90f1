// Whole runs of models stated as text against the same models compiled:
// simulate() with the same method, tolerances and output grid, the
// observer doing nothing. The double pendulum (T and V as the README's
// C++ model writes them) and a 10-link chain (T written as the chain's
// PendulumChain<10> computes it: running sums of the link velocities).
// Run: scripts/bench (docs/performance.md, "Models stated as text").
#include <benchmark/benchmark.h>

#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/text/text_model.hpp"
#include "text_double_pendulum.hpp"

namespace {

using namespace lagrangian;

SimulationOptions options() {
  SimulationOptions o;
  o.method = Method::dopri5;
  o.t_end = 10.0;
  o.rtol = 1e-10;
  o.atol = 1e-12;
  o.output_interval = 0.01;
  return o;
}

struct Nothing {
  template <class Sample>
  void operator()(const Sample&) {}
};

/// x_k = Σ_{i≤k} l sin θ_i, y_k = −Σ_{i≤k} l cos θ_i: T = Σ_k ½ m (ẋ_k² + ẏ_k²),
/// V = Σ_k m g y_k, each running sum written out (equal prefixes are
/// stored once when read).
text::Definition chain_text(int n) {
  text::Definition d;
  std::string vx, vy, y, kinetic, potential;
  for (int k = 1; k <= n; ++k) {
    const std::string th = "th" + std::to_string(k);
    d.coordinates.push_back(th);
    vx += (k > 1 ? " + " : "") + std::string("l*cos(") + th + ")*" + th + "_dot";
    vy += (k > 1 ? " + " : "") + std::string("l*sin(") + th + ")*" + th + "_dot";
    y += " - l*cos(" + th + ")";
    kinetic += (k > 1 ? " + " : "") + std::string("0.5*m*((") + vx + ")^2 + (" + vy + ")^2)";
    potential += (k > 1 ? " + " : "") + std::string("m*g*(") + y + ")";
  }
  d.kinetic = kinetic;
  d.potential = potential;
  d.parameters = {{"m", 1.0}, {"l", 1.0}, {"g", 9.81}};
  return d;
}

template <class M, class X>
void run(benchmark::State& st, const M& model, const X& x0) {
  std::uint64_t steps = 0;
  for (auto _ : st) {
    const RunReport r = simulate(model, x0, options(), Nothing{});
    steps = r.steps;
    benchmark::DoNotOptimize(r.rhs_evaluations);
  }
  st.counters["steps"] = static_cast<double>(steps);
}

template <int N>
State<N> start() {
  State<N> s;
  for (int i = 0; i < N; ++i) s.q[i] = 0.5 + 0.05 * i;
  s.qd.setZero();
  return s;
}
State<Dynamic> start_dynamic(int n) {
  State<Dynamic> s(n);
  for (int i = 0; i < n; ++i) s.q[i] = 0.5 + 0.05 * i;
  s.qd.setZero();
  return s;
}

void BM_Run_DoublePendulum_Compiled(benchmark::State& st) { run(st, models::DoublePendulum(), start<2>()); }
void BM_Run_DoublePendulum_Text(benchmark::State& st) {
  run(st, text::TextModel(bench::double_pendulum_text()), start_dynamic(2));
}
void BM_Run_Chain10_Compiled(benchmark::State& st) { run(st, models::PendulumChain<10>(), start<10>()); }
void BM_Run_Chain10_Text(benchmark::State& st) { run(st, text::TextModel(chain_text(10)), start_dynamic(10)); }

BENCHMARK(BM_Run_DoublePendulum_Compiled)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Run_DoublePendulum_Text)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Run_Chain10_Compiled)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Run_Chain10_Text)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
