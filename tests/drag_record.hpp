#pragma once
// The drag record the identification test and bench_sensitivity fit: a
// projectile's path under linear drag b = 0.035 kg/s (0.145 kg, 30 m/s at
// 0.7 rad from the origin), 3 s at 50 Hz, with seeded Gaussian noise of
// σ = 1 mm on x and y.

#include <random>
#include <vector>

#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/models/projectile.hpp"

namespace lagrangian::testing {

struct DragRecord {
  static constexpr double b_true = 0.035;     ///< kg/s
  static constexpr double interval = 0.02;    ///< s
  static constexpr double noise = 1e-3;       ///< m, standard deviation
  State<2> x0;
  std::vector<double> xs, ys;  ///< m
  DragRecord() {
    const models::Projectile<models::Drag::linear> truth(0.145, 9.81, 0.0, b_true);
    x0 = truth.launch(30.0, 0.7);
    SimulationOptions o;
    o.t_end = 3.0;
    o.output_interval = interval;
    Recorder<2> rec;
    simulate(truth, x0, o, rec);
    std::mt19937_64 rng(7);
    std::normal_distribution<double> gauss(0.0, noise);
    for (const auto& s : rec.samples) {
      xs.push_back(s.q[0] + gauss(rng));
      ys.push_back(s.q[1] + gauss(rng));
    }
  }
};

}  // namespace lagrangian::testing
