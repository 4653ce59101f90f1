// What the Lyapunov exponents cost against a plain run of the same motion:
// the chaotic double pendulum (θ1 = θ2 = 2 rad from rest, 100 s, dopri5 at
// rtol 1e-10, atol 1e-12), the largest exponent (one tangent vector) and the
// whole spectrum (four), each timed against simulate() in the same process,
// and the largest exponent again through the whole Jacobian (J δx with J
// from state_jacobian(), as k > 1 takes it) instead of its one direction
// (state_jvp()); then the same motion in Cartesian coordinates with two rod
// constraints (CartesianDoublePendulum, over 20 s: the tangent flow on the
// constraint manifold), against its own plain run (docs/performance.md).
// Usage: bench_lyapunov [REPEATS] (default 3)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

/// A plain run of `model` from `s` and its exponents with k = 1 and k = 4,
/// in this process; with `whole`, k = 1 again through the whole J.
template <class M>
void measure(const M& model, const lagrangian::State<M::coordinate_count>& s, double t_end, bool whole) {
  lagrangian::SimulationOptions run;
  run.t_end = t_end;
  run.rtol = 1e-10;
  run.atol = 1e-12;
  run.output_interval = -1;
  const auto start = std::chrono::steady_clock::now();
  const lagrangian::RunReport plain = lagrangian::simulate(model, s, run);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s, plain run over %g s: %.4f s, %llu steps, %llu evaluations of q̈\n", model.name().c_str(), t_end,
              seconds, static_cast<unsigned long long>(plain.steps),
              static_cast<unsigned long long>(plain.rhs_evaluations));
  for (int k : {1, 4}) {
    lagrangian::LyapunovOptions o;
    o.run = run;
    o.exponents = k;
    const lagrangian::LyapunovResult l = lagrangian::lyapunov_spectrum(model, s, o);
    std::printf("  k = %d: %.4f s (%.1fx the plain run), %llu steps, %llu evaluations of q̈ with its derivatives, "
                "%d renormalisations, largest exponent %.4f 1/s, sum %.1e 1/s\n",
                k, l.seconds, l.seconds / seconds, static_cast<unsigned long long>(l.steps),
                static_cast<unsigned long long>(l.rhs_evaluations), l.renormalisations, l.spectrum[0], l.sum);
  }
  if (!whole) return;
  lagrangian::LyapunovOptions o;
  o.run = run;
  o.exponents = 1;
  lagrangian::detail::TangentModel tm = lagrangian::detail::tangent_model_of(model, "bench: ");
  tm.evaluate_direction = nullptr;  // J δx from the whole J
  const lagrangian::LyapunovResult l = lagrangian::detail::lyapunov_spectrum(tm, s.q.data(), s.qd.data(), o);
  std::printf("  k = 1 through the whole J: %.4f s (%.1fx the plain run), %llu steps, largest exponent %.4f 1/s\n",
              l.seconds, l.seconds / seconds, static_cast<unsigned long long>(l.steps), l.spectrum[0]);
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 3;
  const lagrangian::models::DoublePendulum dp;
  lagrangian::State<2> s;
  s.q << 2.0, 2.0;
  // The same start in Cartesian coordinates (unit rods, bobs at rest).
  const lagrangian::models::CartesianDoublePendulum cartesian;
  lagrangian::State<4> c;
  c.q << std::sin(2.0), -std::cos(2.0), 2 * std::sin(2.0), -2 * std::cos(2.0);
  c.qd.setZero();
  for (int r = 0; r < repeats; ++r) {
    measure(dp, s, 100, true);
    measure(cartesian, c, 20, false);
  }
}
