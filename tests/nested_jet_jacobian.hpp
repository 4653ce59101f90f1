#pragma once
// An independent derivation of the tangent flow for tests and benchmarks:
// J V = (∂q̈/∂(q, q̇)) V from the third derivatives of L, with L evaluated
// once on a second-order ad::Jet over (q, q̇, t) whose entries are
// first-order ad::Jets along the K directions V. Differentiating
// M q̈ = r along a direction gives M (J V)_c = (∂r V)_c − (∂M V)_c q̈ with
//   M = ∂²L/∂q̇²,  r = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q − ∂D/∂q̇.
// The library's state_jvp() takes another route (ad::EomJet numbers
// differentiated along V), so agreement checks both.

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian::testing {

template <int K, class M>
void nested_jet_jvp(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                    const Vec<double, coordinate_count_v<M>>& qd, double t,
                    const Eigen::Matrix<double, 2 * coordinate_count_v<M>, K>& v, Vec<double, coordinate_count_v<M>>& qdd,
                    Eigen::Matrix<double, coordinate_count_v<M>, K>& jv) {
  constexpr int n = coordinate_count_v<M>;
  using I = ad::Jet<double, K, 1>;     // a value and its derivatives along the K directions
  using O = ad::Jet<I, 2 * n + 1, 2>;  // second order in (q, q̇, t), each entry an I
  Vec<I, n> qi, qdi;
  detail::along_directions(q, qd, v, qi, qdi);
  Vec<O, n> qo, qdo;
  for (int k = 0; k < n; ++k) {
    qo[k] = O::variable(qi[k], k);
    qdo[k] = O::variable(qdi[k], n + k);
  }
  const I ti(t);
  const O l = detail::lagrangian_of(model, qo, qdo, O::variable(ti, 2 * n));
  Mat<double, n> mass;
  Eigen::Matrix<double, n, K> dmass[n];  // dmass[i](j, c): the derivative of M_ij along V_c
  Vec<I, n> r;
  for (int i = 0; i < n; ++i) {
    I ri = l.g[i] - l.hess(n + i, 2 * n);
    for (int j = 0; j < n; ++j) {
      ri -= l.hess(n + i, j) * qdi[j];
      const I& mij = l.hess(n + i, n + j);
      mass(i, j) = mij.v;
      for (int c = 0; c < K; ++c) dmass[i](j, c) = mij.g[c];
    }
    r[i] = ri;
  }
  if constexpr (has_generalized_forces_v<M>) {
    if (uses_generalized_forces(model)) {
      const Vec<I, n> f = model.generalized_forces(qi, qdi, ti);
      for (int i = 0; i < n; ++i) r[i] += f[i];
    }
  }
  if constexpr (has_dissipation_v<M>) {
    if (uses_dissipation(model)) {
      using D = ad::Jet<I, n, 1>;  // first order in q̇, each entry an I
      Vec<D, n> qD, qdD;
      for (int k = 0; k < n; ++k) {
        qD[k] = D(qi[k]);
        qdD[k] = D::variable(qdi[k], k);
      }
      const D d = D(model.dissipation(qD, qdD));
      for (int i = 0; i < n; ++i) r[i] -= d.g[i];
    }
  }
  const Eigen::LLT<Mat<double, n>> llt(mass);
  Vec<double, n> rv;
  for (int i = 0; i < n; ++i) rv[i] = r[i].v;
  qdd = llt.solve(rv);
  Eigen::Matrix<double, n, K> rhs;
  for (int c = 0; c < K; ++c)
    for (int i = 0; i < n; ++i) rhs(i, c) = r[i].g[c] - dmass[i].col(c).dot(qdd);
  jv = llt.solve(rhs);
}

}  // namespace lagrangian::testing
