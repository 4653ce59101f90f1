// Built against the installed package: a pendulum's small-angle period.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <lagrangian/lagrangian.hpp>
#include <lagrangian/models/pendulums.hpp>

int main() {
  const lagrangian::models::SimplePendulum p(1.0, 1.0, 9.81);
  lagrangian::State<1> s;
  s.q[0] = 1e-4;
  lagrangian::SimulationOptions o;
  o.t_end = 2 * std::numbers::pi * std::sqrt(p.l / p.g);  // one small-angle period
  o.output_interval = -1;
  lagrangian::Recorder<1> rec;
  const auto report = lagrangian::simulate(p, s, o, rec);
  const double back = rec.samples.back().q[0];
  std::printf("%s", report.summary().c_str());
  std::printf("theta after one period: %.12g (started at 1e-4)\n", back);
  return std::abs(back - 1e-4) < 1e-9 ? 0 : 1;
}
