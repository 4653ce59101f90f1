// What located events and impacts cost: a ball bouncing to rest (21 events)
// and three perfectly elastic spheres in a box (about 1 000 impacts per
// 100 s), both with dopri5 at rtol 1e-10, atol 1e-12. The `_GeneralMass`
// rows run the same models with their constant_mass_matrix declaration
// withdrawn (M from the AD pass at every evaluation), for the ratio.
#include <benchmark/benchmark.h>

#include <type_traits>
#include <utility>

#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/models/impacts.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

/// The model with its constant_mass_matrix declaration withdrawn.
template <class M>
struct GeneralMass : M {
  static constexpr bool constant_mass_matrix = false;
  explicit GeneralMass(M m) : M(std::move(m)) {}
};

/// M itself, or M with the declaration withdrawn.
template <class M, bool Withdrawn>
using Declared = std::conditional_t<Withdrawn, GeneralMass<M>, M>;

template <bool Withdrawn>
void bouncing_ball(benchmark::State& st) {
  const Declared<BallAndPlane, Withdrawn> ball(BallAndPlane(1.0, 0.1, 0.5, 9.81));
  State<3> s;
  s.q << 0.0, 0.0, 1.1;
  SimulationOptions o;
  o.t_end = 10.0;
  o.output_interval = -1;
  RunReport r;
  for (auto _ : st) {
    r = simulate(ball, s, o);
    benchmark::DoNotOptimize(r.steps);
  }
  st.counters["events"] = static_cast<double>(r.events.size());
  st.counters["steps"] = static_cast<double>(r.steps);
}

template <bool Withdrawn>
void three_spheres(benchmark::State& st) {
  const Declared<SpheresInBox<3>, Withdrawn> box(
      SpheresInBox<3>({1.0, 2.0, 0.5}, {0.1, 0.15, 0.08}, 2.0, 1.5, 1.0, 1.0));
  State<6> s;
  s.q << 0.3, 0.4, 1.0, 1.0, 1.6, 0.5;
  s.qd << 3.1, 1.7, -2.2, 0.9, 1.3, -2.9;
  SimulationOptions o;
  o.t_end = 100.0;
  o.output_interval = -1;
  RunReport r;
  for (auto _ : st) {
    r = simulate(box, s, o);
    benchmark::DoNotOptimize(r.steps);
  }
  st.counters["impacts"] = static_cast<double>(r.impacts);
  st.counters["steps"] = static_cast<double>(r.steps);
  st.counters["rhs"] = static_cast<double>(r.rhs_evaluations);
  st.counters["impacts_per_s"] = benchmark::Counter(static_cast<double>(r.impacts), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_BouncingBallToRest(benchmark::State& st) { bouncing_ball<false>(st); }
void BM_BouncingBallToRest_GeneralMass(benchmark::State& st) { bouncing_ball<true>(st); }
void BM_ThreeSpheresInABox(benchmark::State& st) { three_spheres<false>(st); }
void BM_ThreeSpheresInABox_GeneralMass(benchmark::State& st) { three_spheres<true>(st); }
BENCHMARK(BM_BouncingBallToRest)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BouncingBallToRest_GeneralMass)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ThreeSpheresInABox)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ThreeSpheresInABox_GeneralMass)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
