// What a hard-sphere gas's Lyapunov exponents cost against a plain run of
// the same event-driven motion (scene/hard_spheres_tangent.hpp), timed in
// one process: N spheres of radius 1 cm in a box of side N^(1/3)/10 m (the
// density of examples/scenes/gas_in_container.toml), started on a grid with
// 515 m/s in directions from a fixed sequence, elastic; the largest
// exponent (k = 1), the six largest and, for N ≤ 100, the whole spectrum.
// Usage: bench_gas_tangent [REPEATS] (default 3)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/scene/hard_spheres.hpp"
#include "lagrangian/scene/hard_spheres_tangent.hpp"

namespace {

lagrangian::HardSphereSystem gas(int side) {
  lagrangian::HardSphereSystem s;
  const double spacing = 0.1;
  s.box_max = Eigen::Vector3d::Constant(side * spacing);
  std::uint64_t state = 2024;
  auto next = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;
  };
  for (int i = 0; i < side * side * side; ++i) {
    lagrangian::HardSphere h;
    h.mass = 4.65e-26;
    h.radius = 0.01;
    h.position = spacing * (Eigen::Vector3d(i % side, (i / side) % side, i / (side * side)) +
                            Eigen::Vector3d::Constant(0.5));
    Eigen::Vector3d d(next(), next(), next());
    h.velocity = 515.0 * d.normalized();
    s.spheres.push_back(h);
  }
  return s;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 3;
  for (int side : {4, 10}) {
    const lagrangian::HardSphereSystem s = gas(side);
    const int n = static_cast<int>(s.spheres.size());
    lagrangian::HardSphereOptions o;
    o.t_end = 0.02;
    o.max_recorded_events = 0;
    for (int r = 0; r < repeats; ++r) {
      double plain = 1e300;
      std::uint64_t events = 0, impacts = 0;
      for (int i = 0; i < 3; ++i) {  // the fastest of three: a plain run takes milliseconds
        const auto start = std::chrono::steady_clock::now();
        const lagrangian::RunReport rep = lagrangian::run_hard_spheres(s, o);
        plain = std::min(plain, seconds_since(start));
        events = rep.steps;
        impacts = rep.impacts;
      }
      std::printf("%d spheres over %g s: plain run %.4f s (%llu events, %llu impacts)\n", n, o.t_end, plain,
                  static_cast<unsigned long long>(events), static_cast<unsigned long long>(impacts));
      for (int k : {1, 6, 6 * n}) {
        if (k > lagrangian::scene::kMaxHardSphereExponents) continue;
        const auto start = std::chrono::steady_clock::now();
        const lagrangian::LyapunovResult l = lagrangian::scene::lyapunov_hard_spheres(s, o, k);
        const double t = seconds_since(start);
        std::printf("  k = %d: %.4f s (%.1fx the plain run), %d renormalisations, largest exponent %.1f 1/s, "
                    "sum %.3g 1/s\n",
                    k, t, t / plain, l.renormalisations, l.spectrum[0], l.sum);
      }
    }
  }
  return 0;
}
