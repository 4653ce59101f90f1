// A user's own translation unit, timed by scripts/time-user-tu: the
// 40-coordinate pendulum chain (one derivative pass of 40 directions) and
// one simulate() call.
#include <cstdio>

#include <lagrangian/lagrangian.hpp>
#include <lagrangian/models/pendulums.hpp>

int main() {
  const lagrangian::models::PendulumChain<40> chain;
  lagrangian::State<40> s;
  s.q.setConstant(0.3);
  lagrangian::SimulationOptions o;
  o.t_end = 0.5;
  const auto report = lagrangian::simulate(chain, s, o);
  std::printf("%s", report.summary().c_str());
  return report.energy_drift_max < 1e-6 ? 0 : 1;
}
