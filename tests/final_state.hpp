#pragma once
// x(T) = (q, q̇) of a plain simulate() run: what the tangent-flow tests
// and bench_sensitivity take central differences of.

#include <Eigen/Core>

#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/integrate/simulate.hpp"

namespace lagrangian::testing {

/// The state (q, q̇) (2n values) of `model` at o.t_end from `s` at o.t0
/// (n fixed or counted at run time, as a text model's).
template <class M>
Eigen::VectorXd final_state(const M& model, const State<coordinate_count_v<M>>& s, SimulationOptions o) {
  o.output_interval = -1;  // the initial and the final state only
  Recorder<coordinate_count_v<M>> rec;
  simulate(model, s, o, rec);
  const auto& last = rec.samples.back();
  Eigen::VectorXd x(last.q.size() + last.qd.size());
  x << last.q, last.qd;
  return x;
}

/// The same at t = T from t = 0 with dopri5 at rtol 1e-13, atol 1e-15.
template <class M>
Eigen::VectorXd final_state(const M& model, const State<coordinate_count_v<M>>& s, double T) {
  SimulationOptions o;
  o.t_end = T;
  o.rtol = 1e-13;
  o.atol = 1e-15;
  return final_state(model, s, o);
}

}  // namespace lagrangian::testing
