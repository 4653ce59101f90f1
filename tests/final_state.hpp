#pragma once
// x(T) = (q, q̇) of a plain simulate() run at tight tolerances: what the
// tangent-flow tests take central differences of.

#include <Eigen/Core>

#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/integrate/simulate.hpp"

namespace lagrangian::testing {

/// The state (q, q̇) (2n values) of `model` at t = T from `s` at t = 0
/// (dopri5, rtol 1e-13, atol 1e-15).
template <class M>
Eigen::VectorXd final_state(const M& model, const State<coordinate_count_v<M>>& s, double T) {
  constexpr int n = coordinate_count_v<M>;
  SimulationOptions o;
  o.t_end = T;
  o.rtol = 1e-13;
  o.atol = 1e-15;
  o.output_interval = -1;  // the initial and the final state only
  Recorder<n> rec;
  simulate(model, s, o, rec);
  const auto& last = rec.samples.back();
  Eigen::VectorXd x(2 * n);
  x << last.q, last.qd;
  return x;
}

}  // namespace lagrangian::testing
