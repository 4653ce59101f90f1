#pragma once
// Shared by the constraint tests.
#include <cmath>

#include "lagrangian/model.hpp"

namespace test_helpers {

/// The Cartesian state (x, y, ẋ, ẏ) of a pendulum of length l at angle θ
/// from the downward vertical with rate θ̇.
inline lagrangian::State<2> pendulum_cartesian_state(double l, double theta, double theta_dot) {
  lagrangian::State<2> s;
  s.q << l * std::sin(theta), -l * std::cos(theta);
  s.qd << l * std::cos(theta) * theta_dot, l * std::sin(theta) * theta_dot;
  return s;
}

/// A free unit-mass particle in the plane (T = ½|q̇|², V = 0), to which tests
/// add constraints.
struct FreePlanarParticle {
  static constexpr int dof = 2;
  template <class S>
  S kinetic(const lagrangian::Vec<S, 2>&, const lagrangian::Vec<S, 2>& qd, const S&) const {
    return 0.5 * qd.squaredNorm();
  }
  template <class S>
  S potential(const lagrangian::Vec<S, 2>& q, const S&) const {
    return 0 * q[0];
  }
};

}  // namespace test_helpers
