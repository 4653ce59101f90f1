#pragma once
// Shared by the tangent-flow tests: dopri5 runs for Lyapunov exponents (to
// t_end at rtol, atol 1e-13) and for Floquet multipliers (one period at
// rtol 1e-12, atol 1e-14).

#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"

namespace lagrangian_test {

inline lagrangian::LyapunovOptions lyapunov_options(double t_end, double rtol = 1e-11) {
  lagrangian::LyapunovOptions o;
  o.run.t_end = t_end;
  o.run.rtol = rtol;
  o.run.atol = 1e-13;
  return o;
}

inline lagrangian::FloquetOptions floquet_options(double period) {
  lagrangian::FloquetOptions o;
  o.period = period;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  return o;
}

}  // namespace lagrangian_test
