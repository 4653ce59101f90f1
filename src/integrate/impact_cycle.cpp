#include "lagrangian/integrate/detail/impact_cycle.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>
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

namespace {

/// Entry (i, j) of an n × n column-major matrix.
double& at(std::vector<double>& a, int n, int i, int j) {
  return a[static_cast<std::size_t>(j) * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)];
}

double max_abs(const std::vector<double>& a) {
  double m = 0;
  for (double x : a) m = std::max(m, std::abs(x));
  return m;
}

/// a ← a a (n × n), through `scratch`.
void square(std::vector<double>& a, std::vector<double>& scratch, int n) {
  std::fill(scratch.begin(), scratch.end(), 0.0);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < n; ++k) {
      const double akj = at(a, n, k, j);
      if (akj == 0) continue;
      for (int i = 0; i < n; ++i) at(scratch, n, i, j) += at(a, n, i, k) * akj;
    }
  a.swap(scratch);
}

}  // namespace

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
  if (!C.allFinite()) return false;
  // Velocities no impact of the round touches (row and column of C those
  // of I: a body far from the contacts) keep their values; the rest, m of
  // them, are solved for.
  std::vector<int> active;
  for (int i = 0; i < n; ++i) {
    bool touched = false;
    for (int j = 0; j < n && !touched; ++j) touched = C(i, j) != (i == j ? 1.0 : 0.0) || C(j, i) != (i == j ? 1.0 : 0.0);
    if (touched) active.push_back(i);
  }
  const int na = static_cast<int>(active.size());
  if (na == 0) {
    for (int i = 0; i < n; ++i) out[i] = v[i];
    return true;
  }
  MatrixXd Cs(na, na);
  VectorXd vs(na);
  for (int j = 0; j < na; ++j) {
    vs[j] = v[active[static_cast<std::size_t>(j)]];
    for (int i = 0; i < na; ++i) Cs(i, j) = C(active[static_cast<std::size_t>(i)], active[static_cast<std::size_t>(j)]);
  }
  // Every impact of the round, 0 ≤ e ≤ 1, is a contraction in the kinetic
  // energy's norm, so C is one: |λ| ≤ 1, and λ = 1 has a full set of
  // eigenvectors. C^k v then tends to P v, P the projection onto
  // ker(C − I) (what the round leaves unchanged) along range(C − I) (what
  // it changes), if no other |λ| = 1 (a reflection that keeps its size).
  // With K and L bases of ker(C − I) and ker((C − I)ᵀ) = range(C − I)^⊥:
  // P = K (Lᵀ K)⁻¹ Lᵀ. A decay per round of 1 − 2m/M (m/M down to about 1e-11)
  // is told from rounding (1e-12 of the largest pivot).
  constexpr double one = 1e-12;
  const MatrixXd A = Cs - MatrixXd::Identity(na, na);
  Eigen::FullPivLU<MatrixXd> right(A), left(A.transpose());
  right.setThreshold(one);
  left.setThreshold(one);
  const int kept = na - right.rank();
  if (na - left.rank() != kept) return false;
  std::vector<double> P(static_cast<std::size_t>(na) * static_cast<std::size_t>(na), 0.0);
  VectorXd limit = VectorXd::Zero(na);
  if (kept > 0) {
    const MatrixXd K = right.kernel(), L = left.kernel();
    MatrixXd G(kept, kept);
    for (int i = 0; i < kept; ++i)
      for (int j = 0; j < kept; ++j) G(i, j) = L.col(i).dot(K.col(j));
    Eigen::FullPivLU<MatrixXd> g(G);
    if (!g.isInvertible()) return false;  // λ = 1 without a full set of eigenvectors (C is no contraction)
    VectorXd lv(kept), y(kept), li(kept), z(kept);
    for (int i = 0; i < kept; ++i) lv[i] = L.col(i).dot(vs);
    y = g.solve(lv);
    for (int i = 0; i < kept; ++i) limit += y[i] * K.col(i);
    // Column j of P: K (Lᵀ K)⁻¹ (row j of L)ᵀ.
    for (int j = 0; j < na; ++j) {
      for (int i = 0; i < kept; ++i) li[i] = L(j, i);
      z = g.solve(li);
      for (int i = 0; i < na; ++i) at(P, na, i, j) = K.row(i).dot(z);
    }
  }
  if (!limit.allFinite()) return false;
  // The rest, D = C − P, must decay: D^(2^45) (2^45 rounds, 3.5e13) is
  // e^-35 of its size at a decay of 1e-12 per round, and a part with
  // |λ| = 1 keeps its size however often it is squared.
  std::vector<double> D(P.size()), scratch(P.size());
  for (int j = 0; j < na; ++j)
    for (int i = 0; i < na; ++i) at(D, na, i, j) = Cs(i, j) - at(P, na, i, j);
  const double scale = std::max(1.0, max_abs(D));
  for (int k = 0; k < 45; ++k) {
    square(D, scratch, na);
    const double d = max_abs(D);
    if (!std::isfinite(d) || d > 1e8 * scale) return false;  // grows
    if (d <= 1e-10 * scale) break;
  }
  if (!(max_abs(D) <= 1e-6 * scale)) return false;  // a part that keeps its size
  for (int i = 0; i < n; ++i) out[i] = v[i];
  for (int j = 0; j < na; ++j) out[active[static_cast<std::size_t>(j)]] = limit[j];
  return true;
}

bool close_together(int n, double* v, int count, double speed, FunctionRef<double(int, const double*)> rate,
                    FunctionRef<void(int, double*)> plastic) {
  std::vector<int> closing;
  std::vector<double> open(static_cast<std::size_t>(n));
  for (;;) {
    double worst = 0;
    bool more = false;
    for (int k = 0; k < count; ++k) {
      const double r = rate(k, v);
      if (!(r < -1e-13 * speed)) continue;
      worst = std::min(worst, r);
      if (std::find(closing.begin(), closing.end(), k) == closing.end()) closing.push_back(k), more = true;
    }
    if (worst == 0) return true;
    if (worst < -1e-6 * speed || !more) return false;
    auto close = [&](const double* in, double* out) {
      std::copy(in, in + n, out);
      for (int k : closing) plastic(k, out);
    };
    std::copy(v, v + n, open.begin());
    if (!round_limit(n, open.data(), round_map(close), v)) return false;
  }
}

}  // namespace lagrangian::detail
