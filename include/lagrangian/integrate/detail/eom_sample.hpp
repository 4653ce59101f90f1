#pragma once
// eom_sample(): the equations of motion of a model at one state, as plain
// numbers (declared in compiled_models.hpp, compiled once in the library for
// the built-in and text models). Two statements of one system must agree in
// them: tests/test_text_catalog.cpp checks every built-in model against its
// text twin. It evaluates q̈ with the functions a run calls, so it adds
// little to what a model's simulate() compiles.
#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/integrate/detail/compiled_models.hpp"
#include "lagrangian/mechanics/dynamics.hpp"

namespace lagrangian::detail {

template <class M>
EomSample eom_sample(const M& model, const double* q_in, const double* qd_in, double t) {
  constexpr int N = coordinate_count_v<M>;
  const int n = model_size(model);
  Vec<double, N> q(n), qd(n), qdd(n);
  for (int i = 0; i < n; ++i) {
    q[i] = q_in[i];
    qd[i] = qd_in[i];
  }
  Workspace<N> ws(n);
  bool constrained = false;  // (contacts stay open: no unilateral row is active)
  if constexpr (has_constraints_v<M>) {
    constrained = has_constraints(model);
    if (constrained) {
      ConstraintWorkspaceFor<M> cw = constraint_workspace(model);
      constrained_accelerations(model, ws, cw, q, qd, t, qdd, 0.0, ActiveSet{});
    }
  }
  if (!constrained) free_accelerations(model, ws, q, qd, t, qdd);
  // (Both paths leave M and p of the state in ws; L is evaluated here.)
  EomSample s;
  s.qdd.assign(qdd.data(), qdd.data() + n);
  s.p.assign(ws.momenta.data(), ws.momenta.data() + n);
  s.mass.reserve(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) s.mass.push_back(ws.mass(i, j));
  s.h = ws.momenta.dot(qd) - lagrangian_of(model, q, qd, t);
  return s;
}

}  // namespace lagrangian::detail

#define LAGRANGIAN_INSTANTIATE_EOM_SAMPLE(...) template LAGRANGIAN_EOM_SAMPLE_SIGNATURE(__VA_ARGS__);
