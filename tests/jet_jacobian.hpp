#pragma once
// Shared by the tests that compare a model with the same system in other
// coordinates, X = ψ(x): ψ(x) and its Jacobian Dψ(x) by a first-order Jet.

#include <utility>

#include <Eigen/Core>

#include "lagrangian/ad/jet.hpp"

namespace lagrangian_test {

/// ψ(x) and Dψ(x) (O × I) for a map `psi` callable on an Eigen vector of
/// Jets (a generic lambda or function template over the number type).
template <int O, int I, class F>
std::pair<Eigen::Matrix<double, O, 1>, Eigen::Matrix<double, O, I>> value_and_jacobian(
    F psi, const Eigen::Matrix<double, I, 1>& x) {
  using J = lagrangian::ad::Jet<double, I, 1>;
  Eigen::Matrix<J, I, 1> seeded;
  for (int k = 0; k < I; ++k) {
    seeded[k] = J(x[k]);
    seeded[k].g[k] = 1.0;
  }
  const Eigen::Matrix<J, O, 1> y = psi(seeded);
  std::pair<Eigen::Matrix<double, O, 1>, Eigen::Matrix<double, O, I>> out;
  for (int i = 0; i < O; ++i) {
    out.first[i] = y[i].v;
    for (int k = 0; k < I; ++k) out.second(i, k) = y[i].g[k];
  }
  return out;
}

}  // namespace lagrangian_test
