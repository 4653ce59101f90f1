#pragma once
// A body that has come to rest on a fixed frictionless plane and slides on
// it under gravity g along −z (shared by the tangent-flow tests of the C++
// model, the text model and the particle scene). Its impulses and the
// plane's force are along the unit normal n̂, so along the plane it falls
// freely whatever its bounces were, and at rest its centre lies on the
// plane n·r = c:
//   r(t) = P (r0 + v0 t − ½ g t² ẑ) + (c / |n|) n̂,   v(t) = P (v0 − g t ẑ),
// P = I − n̂n̂ᵀ (r in m, v in m/s, t in s). Every neighbouring start comes to
// rest on the same plane, so the Jacobian of (r, v) at t with respect to
// (r, v) at 0 is
//   Φ = [[P, t P], [0, P]].

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include <Eigen/Core>

namespace lagrangian_test {

inline Eigen::MatrixXd flow_sliding_on_a_plane(const Eigen::Vector3d& unit_normal, double t) {
  const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - unit_normal * unit_normal.transpose();
  Eigen::MatrixXd flow = Eigen::MatrixXd::Zero(6, 6);
  flow.topLeftCorner(3, 3) = p;
  flow.topRightCorner(3, 3) = t * p;
  flow.bottomRightCorner(3, 3) = p;
  return flow;
}

/// (r, v) at t (above) of the body from (r0, v0) at 0, at rest by then on
/// the plane n·r = c (n of any length).
inline Eigen::VectorXd state_sliding_on_a_plane(const Eigen::Vector3d& r0, const Eigen::Vector3d& v0,
                                                const Eigen::Vector3d& normal, double c, double g, double t) {
  const Eigen::Vector3d n = normal.normalized(), down(0.0, 0.0, -g);
  const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - n * n.transpose();
  Eigen::VectorXd x(6);
  x << p * (r0 + v0 * t + 0.5 * t * t * down) + (c / normal.norm()) * n, p * (v0 + t * down);
  return x;
}

/// ∂f/∂p_j at p = `at` (column j) for a smooth f of K parameters, by
/// central differences with steps `step` max(floor, |p_j|): by default
/// 1e-6 max(1, |p_j|) for a closed form (truncation error about 1e-12 of
/// f's third derivative); a relative step (floor 0) for plain runs, whose
/// own errors a larger step divides less.
template <std::size_t K, class F>
Eigen::MatrixXd central_differences(const F& f, const std::array<double, K>& at, double step = 1e-6,
                                    double floor = 1.0) {
  Eigen::MatrixXd columns(f(at).size(), static_cast<Eigen::Index>(K));
  for (std::size_t j = 0; j < K; ++j) {
    std::array<double, K> up = at, down = at;
    const double h = step * std::max(floor, std::abs(at[j]));
    up[j] += h;
    down[j] -= h;
    columns.col(static_cast<Eigen::Index>(j)) = (f(up) - f(down)) / (2 * h);
  }
  return columns;
}

}  // namespace lagrangian_test
