// Brouwer's law for gauss_radau15: over 10⁵ orbits the energy error of an
// integrator whose only error is round-off grows as a random walk, ∝ t^½
// (Brouwer 1937, AJ 46, 149). An ensemble of Kepler orbits (reduced-mass
// model, e = 0.5, GM = a = 1, each from its own mean anomaly) is integrated
// at rtol 1e-9; the RMS relative energy error (long double evaluation) at
// the first step ends past 1, 2, 5, 10, … orbits is printed, with the exponent fitted to it from 100
// orbits on (docs/accuracy.md, "Brouwer's law").
//
// Usage: bench_brouwer [ORBITS=1e5] [RUNS=8] [E=0.5]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/models/kepler.hpp"
#include "lagrangian/models/two_body.hpp"

namespace {

using namespace lagrangian;
namespace lm = lagrangian::models;

/// Checkpoints 1, 2, 5, 10, 20, 50, … up to `orbits`.
std::vector<double> checkpoints(double orbits) {
  std::vector<double> c;
  for (double decade = 1; decade <= orbits; decade *= 10)
    for (double m : {1.0, 2.0, 5.0})
      if (m * decade <= orbits) c.push_back(m * decade);
  return c;
}

/// Relative energy error ½|q̇|² − 1/|q| against E₀, in long double.
struct EnergyAtCheckpoints {
  long double e0 = 0;
  double period = 0;
  const std::vector<double>* marks = nullptr;
  std::vector<double>* sum_squares = nullptr;
  std::size_t next = 0;
  bool started = false;
  void operator()(const Sample<2>& s) {
    using L = long double;
    const L e = L(0.5) * (L(s.qd[0]) * s.qd[0] + L(s.qd[1]) * s.qd[1]) -
                1 / std::sqrt(L(s.q[0]) * s.q[0] + L(s.q[1]) * s.q[1]);
    if (!started) {
      e0 = e;
      started = true;
      return;
    }
    // The first step end at or past the checkpoint: a step's end has the
    // method's accuracy, a sample inside a step only its polynomial's.
    if (next < marks->size() && s.t >= (*marks)[next] * period) {
      const double rel = static_cast<double>((e - e0) / e0);
      (*sum_squares)[next] += rel * rel;
      ++next;
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  const double orbits = argc > 1 ? std::atof(argv[1]) : 1e5;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 8;
  const double ecc = argc > 3 ? std::atof(argv[3]) : 0.5;
  const lm::KeplerOrbit orbit(1.0, ecc, 1.0);
  const double period = orbit.period();
  const std::vector<double> marks = checkpoints(orbits);
  std::vector<double> sum_squares(marks.size(), 0.0);
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t steps = 0;
  for (int r = 0; r < runs; ++r) {
    const auto x0 = orbit.state(period * r / runs);  // its own mean anomaly
    State<2> s;
    s.q << x0[0], x0[1];
    s.qd << x0[2], x0[3];
    SimulationOptions o;
    o.method = Method::gauss_radau15;
    o.rtol = 1e-9;
    o.t0 = 0;
    o.t_end = orbits * period;
    o.output_interval = 0;  // every step's end
    o.max_steps = 2'000'000'000;
    EnergyAtCheckpoints obs{0, period, &marks, &sum_squares};
    const RunReport rep = simulate(lm::RelativeMotion<2>(1.0, lm::NewtonianGravity{1.0}), s, o, std::ref(obs));
    steps += rep.steps;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("# Brouwer's law: gauss_radau15 at rtol 1e-9, Kepler e = %g, %d runs of %g orbits (%.3g steps in all, "
              "%.1f s)\n# orbits  rms_relative_energy_error\n",
              ecc, runs, orbits, static_cast<double>(steps), wall);
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int count = 0;
  for (std::size_t k = 0; k < marks.size(); ++k) {
    const double rms = std::sqrt(sum_squares[k] / runs);
    std::printf("%g %.4e\n", marks[k], rms);
    if (marks[k] >= 100 && rms > 0) {
      const double x = std::log(marks[k]), y = std::log(rms);
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
      ++count;
    }
  }
  if (count >= 2)
    std::printf("# fitted exponent from 100 orbits on: %.3f (Brouwer: 0.5)\n",
                (count * sxy - sx * sy) / (count * sxx - sx * sx));
  return 0;
}
