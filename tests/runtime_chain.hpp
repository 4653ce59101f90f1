#pragma once
// The N-link pendulum chain of models::PendulumChain with N chosen at run
// time (dof = Dynamic): a second formulation of the same system for tests.
#include <cmath>
#include <random>

#include "lagrangian/model.hpp"

namespace lagrangian::test_models {

/// The N-link chain of models::PendulumChain with N chosen at run time.
struct RuntimeChain {
  static constexpr int dof = Dynamic;
  int n;
  double m = 1.0, l = 1.0, g = 9.81;
  int size() const { return n; }
  template <class S>
  S kinetic(const Vec<S, Dynamic>& q, const Vec<S, Dynamic>& qd, const S&) const {
    using std::cos;
    using std::sin;
    S vx = 0, vy = 0, T = 0;
    for (int k = 0; k < n; ++k) {
      vx += l * cos(q[k]) * qd[k];
      vy += l * sin(q[k]) * qd[k];
      T += 0.5 * m * (vx * vx + vy * vy);
    }
    return T;
  }
  template <class S>
  S potential(const Vec<S, Dynamic>& q, const S&) const {
    using std::cos;
    S y = 0, V = 0;
    for (int k = 0; k < n; ++k) {
      y -= l * cos(q[k]);
      V += m * g * y;
    }
    return V;
  }
};

/// The same chain with a linear damping D = ½ c Σ θ̇ᵢ².
struct DampedRuntimeChain : RuntimeChain {
  double c = 0.0;
  template <class S>
  S dissipation(const Vec<S, Dynamic>&, const Vec<S, Dynamic>& qd) const {
    S d = 0;
    for (int k = 0; k < n; ++k) d += 0.5 * c * qd[k] * qd[k];
    return d;
  }
};

/// A state of an N-coordinate chain with every angle and rate drawn
/// uniformly from [−1.5, 1.5] (rad, rad/s).
template <int N>
State<N> random_chain_state(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  State<N> s;
  for (int i = 0; i < N; ++i) {
    s.q[i] = u(rng);
    s.qd[i] = u(rng);
  }
  return s;
}

}  // namespace lagrangian::test_models
