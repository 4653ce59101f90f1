// What the event-driven hard-sphere engine costs as the gas grows: N equal
// spheres (R = 5 cm, 1 kg) at packing fraction 10 %, e = 1, Maxwellian
// velocities (1 m/s per component), run for the time in which each sphere
// has about 10 collisions with other spheres. The cell grid should cost
// O(log N) per collision; the all-pairs broad phase O(N).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <string>

#include "lagrangian/scene/hard_spheres.hpp"

namespace {

using namespace lagrangian;

constexpr double kPhi = 0.10;  // packing fraction
constexpr double kR = 0.05;    // radius (m)
constexpr double kCollisionsPerSphere = 10.0;
const double kPi = std::acos(-1.0);

double box_side(int n) { return std::cbrt(n * 4.0 / 3.0 * kPi * kR * kR * kR / kPhi); }

// Simulated time for ~kCollisionsPerSphere sphere–sphere collisions per
// sphere: the Enskog collision frequency ν = 4 n σ² χ √(π kT/m) with
// σ = 2R, kT/m = 1 m²/s² and the Carnahan–Starling contact value
// χ = (1 − φ/2)/(1 − φ)³.
double run_time(int n) {
  const double L = box_side(n), sigma = 2 * kR;
  const double density = n / (L * L * L);
  const double chi = (1 - kPhi / 2) / std::pow(1 - kPhi, 3);
  const double nu = 4 * density * sigma * sigma * chi * std::sqrt(kPi);
  return kCollisionsPerSphere / nu;
}

HardSphereSystem gas(int n) {
  std::mt19937_64 rng(20261201);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::normal_distribution<double> maxwell(0.0, 1.0);
  const double L = box_side(n);
  const int m = static_cast<int>(std::ceil(std::cbrt(static_cast<double>(n))));
  const double a = L / m, room = 0.5 * a - kR;  // lattice spacing, jitter that keeps spheres apart
  HardSphereSystem sys;
  sys.box_min = Eigen::Vector3d::Zero();
  sys.box_max = Eigen::Vector3d::Constant(L);
  for (int i = 0; i < n; ++i) {
    HardSphere s;
    s.name = "s" + std::to_string(i + 1);
    s.mass = 1.0;
    s.radius = kR;
    s.position = Eigen::Vector3d(a * (i % m + 0.5), a * ((i / m) % m + 0.5), a * (i / (m * m) + 0.5));
    for (int d = 0; d < 3; ++d) s.position[d] += 0.999 * room * uni(rng);
    s.velocity = Eigen::Vector3d(maxwell(rng), maxwell(rng), maxwell(rng));
    sys.spheres.push_back(s);
  }
  return sys;
}

void BM_Gas(benchmark::State& st, BroadPhase broad_phase) {
  const int n = static_cast<int>(st.range(0));
  const HardSphereSystem sys = gas(n);
  HardSphereOptions opt;
  opt.t_end = run_time(n);
  opt.max_recorded_events = 0;
  opt.broad_phase = broad_phase;
  RunReport r;
  for (auto _ : st) {
    r = run_hard_spheres(sys, opt);
    benchmark::DoNotOptimize(r.impacts);
  }
  // Split the impacts into pair and wall impacts with one logged run (after
  // the timed loop, so not timed).
  opt.max_recorded_events = r.impacts;
  const RunReport logged = run_hard_spheres(sys, opt);
  double walls = 0;
  for (const auto& e : logged.events) walls += e.name.find("wall:") != std::string::npos ? 1 : 0;
  const double pairs = static_cast<double>(logged.impacts) - walls;
  using C = benchmark::Counter;
  st.counters["sim_s"] = opt.t_end;
  st.counters["pair_coll/sphere"] = 2 * pairs / n;
  st.counters["wall_hits/sphere"] = walls / n;
  st.counters["events/impact"] = static_cast<double>(r.steps) / static_cast<double>(r.impacts);
  st.counters["impacts/s"] = C(static_cast<double>(r.impacts), C::kIsIterationInvariantRate);
  st.counters["s/impact"] = C(static_cast<double>(r.impacts), C::kIsIterationInvariantRate | C::kInvert);
  // Wall time per sphere per simulated second.
  st.counters["s/(sphere*sim_s)"] = C(n * opt.t_end, C::kIsIterationInvariantRate | C::kInvert);
}
BENCHMARK_CAPTURE(BM_Gas, cell_grid, BroadPhase::cell_grid)
    ->Arg(10)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Gas, all_pairs, BroadPhase::all_pairs)
    ->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
