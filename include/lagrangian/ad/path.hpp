#pragma once
// ad::along_path: a function of (q, t) differentiated along the motion.

namespace lagrangian::ad {

/// q + s q̇ and t + s as numbers of type J (an ad::Jet whose direction 0 is
/// the path parameter s): a function f(q, t) evaluated on them carries
/// df/ds = (∂f/∂q) q̇ + ∂f/∂t in g[0] and, for a second-order J,
/// d²f/ds² = q̇ᵀ (∂²f/∂q²) q̇ + 2 (∂²f/∂q∂t) q̇ + ∂²f/∂t² in hess(0, 0).
/// q and q̇ may hold numbers that carry derivatives themselves (nesting).
template <class J, class Q, class Qd, class Out, class T>
void along_path(const Q& q, const Qd& qd, const T& t, Out& q_path, J& t_path) {
  for (int k = 0; k < static_cast<int>(q.size()); ++k) {
    q_path[k] = J(q[k]);
    q_path[k].g[0] = qd[k];
  }
  t_path = J(t);
  t_path.g[0] = 1.0;
}

}  // namespace lagrangian::ad
