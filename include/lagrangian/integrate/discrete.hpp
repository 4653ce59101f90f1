#pragma once
/// \file discrete.hpp
/// The discrete Lagrangian of a model and its derivatives, by automatic
/// differentiation.
///
/// A discrete Lagrangian L_d(q0, q1) approximates the action of the true
/// motion from q0 at time t to q1 at time t + h (J·s):
///
///   midpoint:     L_d = h · L((q0 + q1)/2, (q1 − q0)/h, t + h/2)
///   trapezoidal:  L_d = (h/2) · [L(q0, (q1 − q0)/h, t) + L(q1, (q1 − q0)/h, t + h)]
///
/// Both are second-order accurate. Their slot derivatives
///
///   D1 L_d = ∂L_d/∂q0,   D2 L_d = ∂L_d/∂q1         (units of momentum: kg·m/s, or kg·m²/s)
///
/// give the discrete Legendre transforms p0 = −D1 L_d(q0, q1) and
/// p1 = D2 L_d(q0, q1); stationarity of the discrete action
/// Σ_k L_d(q_k, q_{k+1}) over interior points gives the discrete
/// Euler–Lagrange equations D2 L_d(q_{k−1}, q_k) + D1 L_d(q_k, q_{k+1}) = 0.
/// The second derivatives D11, D12 = ∂²L_d/∂q0∂q1 and D22 (kg/s, or kg·m²/s)
/// are the Jacobians Newton's method needs for those equations.
///
/// Everything comes from one forward pass over L with second-order
/// ad::Jet numbers in the 2n directions (q0, q1); for a run-time sized model,
/// passes over pairs of blocks of them (mechanics/detail/second_derivatives.hpp).

#include <stdexcept>
#include <string>

#include "lagrangian/ad.hpp"
#include "lagrangian/mechanics/detail/second_derivatives.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// Quadrature rule of the discrete Lagrangian (see the file comment).
enum class DiscreteRule {
  midpoint,     ///< h L((q0 + q1)/2, (q1 − q0)/h, t + h/2)
  trapezoidal,  ///< (h/2) [L(q0, v, t) + L(q1, v, t + h)], v = (q1 − q0)/h
};

/// Name of a rule ("midpoint", "trapezoidal").
inline const char* to_string(DiscreteRule r) { return r == DiscreteRule::midpoint ? "midpoint" : "trapezoidal"; }

/// The rule named `name`; throws std::invalid_argument naming it otherwise.
inline DiscreteRule discrete_rule_from_string(const std::string& name) {
  if (name == "midpoint") return DiscreteRule::midpoint;
  if (name == "trapezoidal") return DiscreteRule::trapezoidal;
  throw std::invalid_argument("discrete rule '" + name + "' is not one of: midpoint, trapezoidal");
}

/// L_d and its first and second slot derivatives at (q0, q1).
template <int N>
struct DiscreteLagrangian {
  double value = 0;   ///< L_d (J·s)
  Vec<double, N> d1;  ///< D1 L_d = ∂L_d/∂q0
  Vec<double, N> d2;  ///< D2 L_d = ∂L_d/∂q1
  Mat<double, N> d11; ///< ∂²L_d/∂q0²
  Mat<double, N> d12; ///< ∂²L_d/∂q0∂q1 (row i: ∂/∂q0_i, column j: ∂/∂q1_j)
  Mat<double, N> d22; ///< ∂²L_d/∂q1²
};

namespace detail {

/// L_d on any scalar type (double or AD numbers).
template <class M, class S>
S discrete_lagrangian_of(const M& model, const Vec<S, coordinate_count_v<M>>& q0,
                         const Vec<S, coordinate_count_v<M>>& q1, double t, double h,
                         DiscreteRule rule) {
  Vec<S, coordinate_count_v<M>> v = q0, qm = q0;
  for (int k = 0; k < q0.size(); ++k) {
    v[k] = (q1[k] - q0[k]) * (1.0 / h);
    qm[k] = (q0[k] + q1[k]) * 0.5;
  }
  if (rule == DiscreteRule::midpoint) return h * lagrangian_of(model, qm, v, S(t + 0.5 * h));
  return 0.5 * h * (lagrangian_of(model, q0, v, S(t)) + lagrangian_of(model, q1, v, S(t + h)));
}

template <class M>
DiscreteLagrangian<coordinate_count_v<M>> discrete_lagrangian_derivatives_fixed(
    const M& model, const Vec<double, coordinate_count_v<M>>& q0, const Vec<double, coordinate_count_v<M>>& q1,
    double t, double h, DiscreteRule rule);

}  // namespace detail

/// The discrete Lagrangian L_d(q0, q1) of `model` over [t, t + h] (J·s).
template <class M>
double discrete_lagrangian(const M& model, const Vec<double, coordinate_count_v<M>>& q0,
                           const Vec<double, coordinate_count_v<M>>& q1, double t,
                           double h, DiscreteRule rule = DiscreteRule::midpoint) {
  check_model<M>();
  return detail::discrete_lagrangian_of<M, double>(model, q0, q1, t, h, rule);
}

/// L_d, D1 L_d, D2 L_d and the second derivatives at (q0, q1) over
/// [t, t + h], from one pass with ad::Jet<double, 2n, 2>.
template <class M>
DiscreteLagrangian<coordinate_count_v<M>> discrete_lagrangian_derivatives(
    const M& model, const Vec<double, coordinate_count_v<M>>& q0, const Vec<double, coordinate_count_v<M>>& q1,
    double t, double h, DiscreteRule rule = DiscreteRule::midpoint) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
  if constexpr (n == Dynamic) {
    // Passes over pairs of blocks of the 2n variables (q0, q1).
    const int size = static_cast<int>(q0.size());
    Eigen::VectorXd x(2 * size);
    x << q0, q1;
    Eigen::VectorXd g;
    Eigen::MatrixXd hs;
    DiscreteLagrangian<n> out;
    detail::second_derivatives_by_blocks(
        2 * size, x,
        [&](const auto& xj) {
          using J = typename std::decay_t<decltype(xj)>::Scalar;
          const Vec<J, Dynamic> a = xj.head(size), b = xj.tail(size);
          return detail::discrete_lagrangian_of<M, J>(model, a, b, t, h, rule);
        },
        out.value, g, hs);
    out.d1 = g.head(size);
    out.d2 = g.tail(size);
    out.d11 = hs.topLeftCorner(size, size);
    out.d12 = hs.topRightCorner(size, size);
    out.d22 = hs.bottomRightCorner(size, size);
    return out;
  } else {
    return detail::discrete_lagrangian_derivatives_fixed(model, q0, q1, t, h, rule);
  }
}

namespace detail {
template <class M>
DiscreteLagrangian<coordinate_count_v<M>> discrete_lagrangian_derivatives_fixed(
    const M& model, const Vec<double, coordinate_count_v<M>>& q0, const Vec<double, coordinate_count_v<M>>& q1,
    double t, double h, DiscreteRule rule) {
  constexpr int n = coordinate_count_v<M>;
  using J = ad::Jet<double, 2 * n, 2>;
  Vec<J, n> a, b;
  for (int k = 0; k < n; ++k) {
    a[k] = J::variable(q0[k], k);
    b[k] = J::variable(q1[k], n + k);
  }
  const J ld = detail::discrete_lagrangian_of<M, J>(model, a, b, t, h, rule);
  DiscreteLagrangian<n> out;
  out.value = ld.v;
  for (int i = 0; i < n; ++i) {
    out.d1[i] = ld.g[i];
    out.d2[i] = ld.g[n + i];
    for (int j = 0; j < n; ++j) {
      out.d11(i, j) = ld.hess(i, j);
      out.d12(i, j) = ld.hess(i, n + j);
      out.d22(i, j) = ld.hess(n + i, n + j);
    }
  }
  return out;
}
}  // namespace detail

}  // namespace lagrangian
