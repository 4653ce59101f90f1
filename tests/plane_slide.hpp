#pragma once
// The flow of a body that has come to rest on a fixed frictionless plane
// with unit normal n̂ and slides on it under gravity (shared by the
// tangent-flow tests of the C++ model, the text model and the particle
// scene). Along the plane it falls freely whatever its bounces were, and
// every neighbouring start comes to rest on the same plane, so at time t
// (s) the Jacobian of (r, v) at t with respect to (r, v) at 0 is
//   Φ = [[P, t P], [0, P]],   P = I − n̂n̂ᵀ.

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

}  // namespace lagrangian_test
