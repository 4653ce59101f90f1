// A user's own translation unit, timed by scripts/time-user-tu: the largest
// Lyapunov exponent of a built-in model (the double pendulum from rest at
// θ1 = θ2 = 2 rad over 10 s), whose tangent flow the library has compiled
// (analysis/detail/compiled_tangent_flow.hpp).
#include <cstdio>

#include <lagrangian/analysis/lyapunov.hpp>
#include <lagrangian/models/pendulums.hpp>

int main() {
  const lagrangian::models::DoublePendulum pendulum;
  lagrangian::State<2> start;
  start.q << 2.0, 2.0;
  start.qd << 0.0, 0.0;
  lagrangian::LyapunovOptions options;
  options.run.t_end = 10.0;
  options.exponents = 1;
  const lagrangian::LyapunovResult r = lagrangian::lyapunov_spectrum(pendulum, start, options);
  std::printf("largest exponent %.4f 1/s over %.0f s\n", r.spectrum[0], options.run.t_end);
  return r.spectrum[0] > 0 ? 0 : 1;
}
