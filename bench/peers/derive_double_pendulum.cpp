// What lagrangian's "derivation" of the double pendulum costs: nothing at run
// time — q̈ comes from automatic differentiation of T and V at each call, so
// the cost is paid once by the compiler (bench/peers/run_peers.sh times the
// compilation of this file) and then per evaluation. Prints q̈ at the peers'
// initial state and at a second state, checked against the hand-coded form,
// and the time of the first and of the median evaluation.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/models/pendulums.hpp"

int main() {
  using Clock = std::chrono::steady_clock;
  const lagrangian::models::DoublePendulum p;  // m1 = m2 = 1 kg, l1 = l2 = 1 m, g = 9.81 m/s²
  lagrangian::Workspace<2> ws;
  lagrangian::Vec<double, 2> q(2.0, 2.0), qd(0.0, 0.0), out;
  const auto t0 = Clock::now();
  lagrangian::accelerations(p, ws, q, qd, 0.0, out);
  const double first = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("qdd(2, 2, 0, 0) = [%.17g, %.17g]\n", out[0], out[1]);

  // Hand-coded q̈ at a second state (Cramer's rule on M q̈ = f).
  q << 0.3, -1.1;
  qd << 0.7, 2.5;
  lagrangian::accelerations(p, ws, q, qd, 0.0, out);
  const double d = q[0] - q[1], c = std::cos(d), s = std::sin(d);
  const double m11 = 2.0, m12 = c, m22 = 1.0, det = m11 * m22 - m12 * m12;
  const double f1 = -qd[1] * qd[1] * s - 2 * 9.81 * std::sin(q[0]), f2 = qd[0] * qd[0] * s - 9.81 * std::sin(q[1]);
  const double h0 = (f1 * m22 - m12 * f2) / det, h1 = (m11 * f2 - m12 * f1) / det;
  if (std::abs(out[0] - h0) > 1e-12 * (1 + std::abs(h0)) || std::abs(out[1] - h1) > 1e-12 * (1 + std::abs(h1))) {
    std::printf("derive: AD q'' [%g, %g] differs from the hand-coded [%g, %g]\n", out[0], out[1], h0, h1);
    return 1;
  }
  std::vector<double> times;
  for (int k = 0; k < 101; ++k) {
    qd[0] += 1e-9;  // a new input every time
    const auto a = Clock::now();
    for (int i = 0; i < 1000; ++i) lagrangian::accelerations(p, ws, q, qd, 0.0, out);
    times.push_back(std::chrono::duration<double>(Clock::now() - a).count() / 1000);
  }
  std::nth_element(times.begin(), times.begin() + 50, times.end());
  std::printf("first evaluation %.3g s; median evaluation %.3g s; agrees with the hand-coded q'' to 1e-12\n", first,
              times[50]);
  return 0;
}
