#pragma once
// Hand-coded equations of motion used as the baseline in the benchmarks.
#include <array>
#include <cmath>

#include <Eigen/Cholesky>

#include "lagrangian/model.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace bench {

using lagrangian::Mat;
using lagrangian::Vec;

/// Double pendulum q̈ by Cramer's rule on the 2×2 system M q̈ = f. With Δ =
/// θ1 − θ2: M = [m11, m12; m12, m22], m12 = m2 l1 l2 cos Δ,
///   f1 = −m2 l1 l2 sin Δ θ̇2² − (m1 + m2) g l1 sin θ1,
///   f2 = m2 l1 l2 sin Δ θ̇1² − m2 g l2 sin θ2.
/// With `jacobian`, also ∂q̈/∂(θ1, θ2, θ̇1, θ̇2) (row-major 2 × 4):
/// M⁻¹ (∂f/∂x_j − (∂M/∂x_j) q̈), ∂M/∂θ1 = −∂M/∂θ2 = [0, −m2 l1 l2 sin Δ;
/// −m2 l1 l2 sin Δ, 0], ∂M/∂θ̇ = 0.
inline void double_pendulum_qdd(const lagrangian::models::DoublePendulum& p, const double* q, const double* qd,
                                double* qdd, double* jacobian = nullptr) {
  const double d = q[0] - q[1];
  const double c = std::cos(d), s = std::sin(d);
  const double b = p.m2 * p.l1 * p.l2;
  const double m11 = (p.m1 + p.m2) * p.l1 * p.l1, m12 = b * c, m22 = p.m2 * p.l2 * p.l2;
  const double k1 = (p.m1 + p.m2) * p.g * p.l1, k2 = p.m2 * p.g * p.l2;
  const double f1 = -b * qd[1] * qd[1] * s - k1 * std::sin(q[0]);
  const double f2 = b * qd[0] * qd[0] * s - k2 * std::sin(q[1]);
  const double det = m11 * m22 - m12 * m12;
  qdd[0] = (f1 * m22 - m12 * f2) / det;
  qdd[1] = (m11 * f2 - m12 * f1) / det;
  if (jacobian == nullptr) return;
  const double df1[4] = {-b * c * qd[1] * qd[1] - k1 * std::cos(q[0]), b * c * qd[1] * qd[1], 0.0, -2 * b * s * qd[1]};
  const double df2[4] = {b * c * qd[0] * qd[0], -b * c * qd[0] * qd[0] - k2 * std::cos(q[1]), 2 * b * s * qd[0], 0.0};
  const double sign[4] = {1.0, -1.0, 0.0, 0.0};  // ∂M/∂θ1 = −∂M/∂θ2, ∂M/∂θ̇ = 0
  for (int j = 0; j < 4; ++j) {
    const double e1 = df1[j] + sign[j] * b * s * qdd[1], e2 = df2[j] + sign[j] * b * s * qdd[0];
    jacobian[j] = (e1 * m22 - m12 * e2) / det;
    jacobian[4 + j] = (m11 * e2 - m12 * e1) / det;
  }
}

/// N-link chain q̈: M_ij = (Σ_{k≥max(i,j)} m_k) l_i l_j cos(θi − θj),
/// f_i = −Σ_j (Σ_{k≥max(i,j)} m_k) l_i l_j sin(θi − θj) θ̇j² − (Σ_{k≥i} m_k) g l_i sin θi,
/// with cos(θi − θj) = ci cj + si sj, and a fixed-size Cholesky solve.
template <int N>
struct ChainHand {
  Eigen::LLT<Mat<double, N>> llt;
  Mat<double, N> M;
  Vec<double, N> f;
  void qdd(const lagrangian::models::PendulumChain<N>& p, const Vec<double, N>& q, const Vec<double, N>& qd,
           Vec<double, N>& out) {
    std::array<double, N> c, s, tail;
    double acc = 0;
    for (int i = N - 1; i >= 0; --i) {
      acc += p.m[i];
      tail[i] = acc;
    }
    for (int i = 0; i < N; ++i) {
      c[i] = std::cos(q[i]);
      s[i] = std::sin(q[i]);
    }
    for (int i = 0; i < N; ++i) {
      f[i] = -tail[i] * p.g * p.l[i] * s[i];
      for (int j = 0; j < N; ++j) {
        const double w = tail[std::max(i, j)] * p.l[i] * p.l[j];
        M(i, j) = w * (c[i] * c[j] + s[i] * s[j]);
        f[i] -= w * (s[i] * c[j] - c[i] * s[j]) * qd[j] * qd[j];
      }
    }
    llt.compute(M);
    out = llt.solve(f);
  }
};

/// Double pendulum model that also carries its hand-coded q̈ (for measuring
/// the simulate() driver against raw Odeint with the same right-hand side).
struct HandDoublePendulum : lagrangian::models::DoublePendulum {
  void accelerations(const Vec<double, 2>& q, const Vec<double, 2>& qd, double, Vec<double, 2>& qdd) const {
    double_pendulum_qdd(*this, q.data(), qd.data(), qdd.data());
  }
};

}  // namespace bench
