#include "lagrangian/detail/impact_cycle.hpp"

#include <algorithm>
#include <cmath>

#include <complex>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

namespace lagrangian::detail {

std::vector<ImpactCycle::Impact> ImpactCycle::round(int max_period, int window) const {
  const auto size = static_cast<int>(impacts_.size());
  for (int p = 1; p <= max_period && 3 * p <= size; ++p) {
    bool repeats = true;
    for (int k = size - 2 * p; k < size && repeats; ++k) {
      const Impact& a = impacts_[static_cast<std::size_t>(k)];
      const Impact& b = impacts_[static_cast<std::size_t>(k - p)];
      repeats = a.contact == b.contact && a.e == b.e;
    }
    if (repeats) return {impacts_.end() - p, impacts_.end()};
  }
  if (size >= 2 * window) return {impacts_.end() - window, impacts_.end()};
  return {};
}

std::vector<ImpactCycle::Impact> ImpactCycle::due_round(int contacts) {
  if (impacts_.size() < next_try_) return {};
  std::vector<Impact> out = settles_ == 0 ? round(2 * contacts, 6 * contacts) : impacts_;
  if (!out.empty()) next_try_ = 2 * impacts_.size();  // until settled() says it worked
  return out;
}

void ImpactCycle::settled() {
  impacts_.clear();
  next_try_ = 12;
  ++settles_;
}

bool round_limit(int n, const double* v, RoundMap round, double* out) {
  using Eigen::MatrixXd;
  using Eigen::VectorXd;
  const Eigen::Map<const VectorXd> v0(v, n);
  const double size = v0.lpNorm<Eigen::Infinity>();
  if (!(size > 0) || !std::isfinite(size)) return false;
  // F(u) = C u + b: b = F(0), and column i of C from F(h e_i) with h the
  // size of v (F is affine everywhere, so h only sets the rounding's scale).
  VectorXd zero = VectorXd::Zero(n), b(n), u(n), fu(n);
  round(zero.data(), b.data());
  // A round of impacts whose gaps move on their own (∂φ/∂t ≠ 0) drives the
  // velocities towards no fixed subspace: not extrapolated.
  if (!(b.lpNorm<Eigen::Infinity>() <= 1e-14 * size)) return false;
  MatrixXd C(n, n);
  for (int i = 0; i < n; ++i) {
    u.setZero();
    u[i] = size;
    round(u.data(), fu.data());
    C.col(i) = (fu - b) / size;
  }
  // v = Σ c_i w_i over C's eigenvectors; C^k v → the part along eigenvalue
  // 1 (what the round leaves unchanged) when every other |λ| < 1. A decay
  // per round of 1 − 2m/M (m/M down to 1e-12) is told from rounding (1e-12).
  const Eigen::EigenSolver<MatrixXd> es(C);
  if (es.info() != Eigen::Success) return false;
  const Eigen::VectorXcd lambda = es.eigenvalues();
  const Eigen::MatrixXcd W = es.eigenvectors();
  Eigen::PartialPivLU<Eigen::MatrixXcd> lu(W);
  const double cond = W.norm() * lu.inverse().norm();
  if (!std::isfinite(cond) || cond > 1e8) return false;  // no basis of eigenvectors (a Jordan block)
  const Eigen::VectorXcd c = lu.solve(v0.cast<std::complex<double>>().eval());
  Eigen::VectorXcd kept = Eigen::VectorXcd::Zero(n);
  constexpr double one = 1e-12;
  for (int i = 0; i < n; ++i) {
    const std::complex<double> l = lambda[i];
    if (std::abs(l - 1.0) <= one) {
      kept[i] = c[i];
    } else if (!(std::abs(l) < 1.0 - one)) {
      return false;  // a part that keeps its size (a reflection) or grows: nothing settles
    }
  }
  const VectorXd limit = (W * kept).real();
  if (!limit.allFinite()) return false;
  for (int i = 0; i < n; ++i) out[i] = limit[i];
  return true;
}

}  // namespace lagrangian::detail
