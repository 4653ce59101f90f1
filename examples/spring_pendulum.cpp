// The elastic (spring) pendulum: energy exchange between the radial and the
// swinging motion, with the total energy T + V conserved.
#include <algorithm>
#include <cmath>
#include <iostream>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"

int main() try {
  const lagrangian::models::ElasticPendulum pendulum(1.0, 40.0, 1.0, 9.81);  // m, k, l0, g
  lagrangian::State<2> x0;
  x0.q << 1.3, 0.4;  // r (m), θ (rad)
  lagrangian::SimulationOptions opt;
  opt.method = lagrangian::Method::fehlberg78;
  opt.t_end = 30.0;
  opt.output_interval = 0.05;
  double r_min = 1e300, r_max = 0;
  const auto report = lagrangian::simulate(pendulum, x0, opt, [&](const lagrangian::Sample<2>& s) {
    r_min = std::min(r_min, s.q[0]);
    r_max = std::max(r_max, s.q[0]);
  });
  std::cout << report.summary() << "spring length ranged over [" << r_min << ", " << r_max << "] m\n";
  return report.total_energy_drift_max < 1e-8 && r_min > 0 ? 0 : 1;
} catch (const std::exception& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 2;
}
