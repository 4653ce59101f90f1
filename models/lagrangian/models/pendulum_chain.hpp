#pragma once
/// \file pendulum_chain.hpp
/// The planar N-link pendulum chain in generalized coordinates (angles from
/// the downward vertical). SI units: masses in kg, lengths in m, g in m/s²,
/// angles in rad, energies in J.

#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "lagrangian/model.hpp"
#include "lagrangian/models/detail/parameter_arrays.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::models {

/// Chain of N point masses m_i on massless rods l_i (a planar N-link
/// pendulum), angles θ1 … θN from the downward vertical. With
/// x_k = Σ_{i≤k} l_i sin θ_i, y_k = −Σ_{i≤k} l_i cos θ_i:
///   T = Σ_k ½ m_k (ẋ_k² + ẏ_k²),  V = Σ_k m_k g y_k.
/// P is the parameters' type (parameter sensitivities,
/// analysis/sensitivity.hpp: m1 … mN, l1 … lN, g).
template <int N, class P = double>
struct BasicPendulumChain {
  static constexpr int coordinate_count = N;
  std::array<P, N> m;
  std::array<P, N> l;
  P g;
  /// The model with parameters of type Q, and its parameters: m1 … mN,
  /// l1 … lN, g.
  template <class Q>
  using with_parameter_type = BasicPendulumChain<N, Q>;
  static std::string parameter_name(std::size_t i) {
    return detail::indexed_parameter_name<N>(i, std::array<std::string_view, 2>{"m", "l"},
                                             std::array<std::string_view, 1>{"g"});
  }
  static constexpr auto parameter_members() {
    using Self = BasicPendulumChain;
    return detail::array_then_scalar_accessors<Self, P, N, &Self::m, &Self::l>(
        &detail::member_accessor<Self, P, &Self::g>);
  }
  /// Equal masses m (kg) and rods l (m).
  explicit BasicPendulumChain(double mass = 1.0, double length = 1.0, double gravity = 9.81)
      : g(require_nonnegative("PendulumChain", "g", gravity)) {
    m.fill(require_positive("PendulumChain", "m", mass));
    l.fill(require_positive("PendulumChain", "l", length));
  }
  std::string name() const { return "pendulum_chain_" + std::to_string(N); }
  std::vector<std::string> coordinate_names() const {
    std::vector<std::string> out;
    for (int k = 1; k <= N; ++k) out.push_back("theta" + std::to_string(k));
    return out;
  }
  std::array<std::string_view, N> coordinate_units() const {
    std::array<std::string_view, N> units;
    units.fill("rad");
    return units;
  }
  template <class S>
  S kinetic(const Vec<S, N>& q, const Vec<S, N>& qd, const S&) const {
    using std::cos;
    using std::sin;
    S vx = 0;
    S vy = 0;
    S T = 0;
    for (int k = 0; k < N; ++k) {
      vx += l[k] * cos(q[k]) * qd[k];
      vy += l[k] * sin(q[k]) * qd[k];
      T += 0.5 * m[k] * (vx * vx + vy * vy);
    }
    return T;
  }
  template <class S>
  S potential(const Vec<S, N>& q, const S&) const {
    using std::cos;
    S y = 0;
    S V = 0;
    for (int k = 0; k < N; ++k) {
      y -= l[k] * cos(q[k]);
      V += m[k] * g * y;
    }
    return V;
  }
};
/// The N-link chain with parameters in double precision.
template <int N>
using PendulumChain = BasicPendulumChain<N>;

}  // namespace lagrangian::models
