// A user's own translation unit, timed by scripts/time-user-tu: the
// 10-coordinate pendulum chain (a model template the library does not
// compile for this size) and one simulate() call.
#include <cstdio>

#include <lagrangian/lagrangian.hpp>
#include <lagrangian/models/pendulums.hpp>

int main() {
  const lagrangian::models::PendulumChain<10> chain;
  lagrangian::State<10> s;
  s.q.setConstant(0.3);
  lagrangian::SimulationOptions o;
  o.t_end = 2.0;
  const auto report = lagrangian::simulate(chain, s, o);
  std::printf("%s", report.summary().c_str());
  return report.energy_drift_max < 1e-6 ? 0 : 1;
}
