#pragma once
// The bounce record the identification test and bench_sensitivity fit: the
// heights of a ball (0.3 kg, R = 0.05 m, e = 0.72) dropped from rest at
// 1.05 m onto a floor, 2.5 s at 100 Hz, with seeded Gaussian noise of
// σ = 1 mm, and without it.

#include <random>
#include <vector>

#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/models/impacts.hpp"

namespace lagrangian::testing {

struct BounceRecord {
  static constexpr double e_true = 0.72;    ///< 1
  static constexpr double interval = 0.01;  ///< s
  static constexpr double noise = 1e-3;     ///< m, standard deviation
  State<3> x0;
  std::vector<double> heights, clean;  ///< m, with and without the noise
  BounceRecord() {
    x0.q << 0.0, 0.0, 1.05;
    x0.qd << 0.0, 0.0, 0.0;
    SimulationOptions o;
    o.t_end = 2.5;
    o.output_interval = interval;
    Recorder<3> rec;
    simulate(models::BallAndPlane(0.3, 0.05, e_true, 9.81), x0, o, rec);
    std::mt19937_64 rng(42);
    std::normal_distribution<double> gauss(0.0, noise);
    for (const auto& s : rec.samples) {
      clean.push_back(s.q[2]);
      heights.push_back(s.q[2] + gauss(rng));
    }
  }
};

}  // namespace lagrangian::testing
