#pragma once
// Internal: g(q, t), its Jacobian and the Hessians of each row for the
// holonomic constraints, for fixed and run-time sizes (the analyses,
// linearisation.hpp, and consistent_initial_state, mechanics/detail/consistent.hpp).
// Included at the end of constraints.hpp, whose declarations it uses.

#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/ad/jet.hpp"
#include "lagrangian/mechanics/detail/second_derivatives.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian::detail {

/// g(q, t), G = ∂g/∂q and the Hessians ∇²g_i of the holonomic constraints.
struct HolonomicDerivatives {
  Eigen::VectorXd value;
  Eigen::MatrixXd jacobian;
  std::vector<Eigen::MatrixXd> hessians;
};

template <class M>
HolonomicDerivatives holonomic_derivatives(const M& model, const Vec<double, coordinate_count_v<M>>& q, double t) {
  constexpr int n = coordinate_count_v<M>;
  const int m = holonomic_count(model);
  HolonomicDerivatives d;
  d.value.resize(m);
  d.jacobian.resize(m, q.size());
  if constexpr (holonomic_count_v<M> != 0 && n == Dynamic) {
    // Row by row, from passes over pairs of coordinate blocks.
    const int size = static_cast<int>(q.size());
    for (int i = 0; i < m; ++i) {
      double value = 0;
      Eigen::VectorXd gradient;
      Eigen::MatrixXd hessian;
      detail::second_derivatives_by_blocks(
          size, q,
          [&](const auto& qj) {
            using J = typename std::decay_t<decltype(qj)>::Scalar;
            const auto g = model.holonomic(qj, J(t));
            check_rows(g, m, "holonomic()");
            return J(g[i]);
          },
          value, gradient, hessian);
      d.value[i] = value;
      d.jacobian.row(i) = gradient.transpose();
      d.hessians.push_back(hessian);
    }
  } else if constexpr (holonomic_count_v<M> != 0) {
    using J = ad::Jet<double, n, 2>;
    Vec<J, n> qj;
    for (int k = 0; k < n; ++k) qj[k] = J::variable(q[k], k);
    const auto g = model.holonomic(qj, J(t));
    for (int i = 0; i < m; ++i) {
      d.value[i] = g[i].v;
      Eigen::MatrixXd h(n, n);
      for (int k = 0; k < n; ++k) {
        d.jacobian(i, k) = g[i].g[k];
        for (int j = 0; j < n; ++j) h(k, j) = g[i].hess(k, j);
      }
      d.hessians.push_back(h);
    }
  } else {
    (void)model;
    (void)q;
    (void)t;
  }
  return d;
}

}  // namespace lagrangian::detail
