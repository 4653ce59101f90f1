// One pendulum, two formulations: the angle θ (one coordinate, no
// constraint) and a Cartesian particle (x, y) held by a rod constraint
// √(x² + y²) = l. The motions agree, and the rod's multiplier is the tension
// T = m (g cos θ + l θ̇²).
#include <algorithm>
#include <cmath>
#include <iostream>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/pendulums.hpp"

int main() try {
  const double m = 1.0, l = 1.0, g = 9.81, theta0 = 1.0;
  const lagrangian::models::SimplePendulum angle(m, l, g);
  const lagrangian::models::CartesianPendulum cartesian(m, l, g);
  lagrangian::State<1> a0;
  a0.q[0] = theta0;
  lagrangian::State<2> c0;
  c0.q << l * std::sin(theta0), -l * std::cos(theta0);
  lagrangian::SimulationOptions opt;
  opt.t_end = 20.0;
  opt.rtol = 1e-11;
  opt.atol = 1e-13;
  opt.output_interval = 0.05;
  lagrangian::Recorder<1> ra;
  lagrangian::Recorder<2> rc;
  lagrangian::simulate(angle, a0, opt, ra);
  const auto report = lagrangian::simulate(cartesian, c0, opt, rc);
  double worst_angle = 0, worst_tension = 0;
  for (std::size_t k = 0; k < ra.samples.size(); ++k) {
    const auto& s = rc.samples[k];
    worst_angle = std::max(worst_angle, std::abs(std::atan2(s.q[0], -s.q[1]) - ra.samples[k].q[0]));
    const double theta = ra.samples[k].q[0], theta_dot = ra.samples[k].qd[0];
    const double tension = m * (g * std::cos(theta) + l * theta_dot * theta_dot);
    worst_tension = std::max(worst_tension, std::abs(-s.multipliers[0] - tension));  // λ = −T along +∇g
  }
  std::cout << report.summary() << "max |θ_cartesian − θ| = " << worst_angle
            << " rad, max |tension − m(g cos θ + l θ̇²)| = " << worst_tension << " N\n";
  return worst_angle < 1e-8 && worst_tension < 1e-7 ? 0 : 1;
} catch (const std::exception& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 2;
}
