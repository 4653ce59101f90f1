#pragma once
// Shared by the Lyapunov tests: a run of dopri5 to t_end at rtol (atol 1e-13).

#include "lagrangian/analysis/lyapunov.hpp"

namespace lagrangian_test {

inline lagrangian::LyapunovOptions lyapunov_options(double t_end, double rtol = 1e-11) {
  lagrangian::LyapunovOptions o;
  o.run.t_end = t_end;
  o.run.rtol = rtol;
  o.run.atol = 1e-13;
  return o;
}

}  // namespace lagrangian_test
