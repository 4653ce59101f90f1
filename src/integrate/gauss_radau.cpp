// The 15th-order Gauss–Radau stepper (detail/gauss_radau.hpp).

#include "lagrangian/detail/gauss_radau.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lagrangian::detail {
namespace {

constexpr int K = 7;  // polynomial terms b₀ … b₆, nodes h₁ … h₇

/// P₇(u) + P₈(u) by Legendre's recurrence (k + 1) P_{k+1} = (2k + 1) u P_k − k P_{k−1}.
long double radau_polynomial(long double u) {
  long double p0 = 1, p1 = u;
  for (int k = 1; k < 8; ++k) {
    const long double p2 = ((2 * k + 1) * u * p1 - k * p0) / (k + 1);
    p0 = p1;
    p1 = p2;
  }
  return p0 + p1;  // P₇ + P₈
}

/// The roots of P₇ + P₈ in (−1, 1], bracketed on a grid and bisected to
/// long double precision, mapped to h = (u + 1)/2; h₀ = 0 (u = −1).
std::array<double, 8> compute_nodes() {
  std::array<double, 8> h{};
  int found = 0;
  constexpr int kGrid = 4096;
  const long double du = 2.0L / kGrid;
  long double a = -1 + du / 8, fa = radau_polynomial(a);  // past the root at u = −1
  for (int i = 1; i <= kGrid && found < K; ++i) {
    long double b = -1 + du * i, fb = radau_polynomial(b);
    if ((fa < 0) != (fb < 0)) {
      long double lo = a, hi = b, flo = fa;
      for (int it = 0; it < 200 && hi - lo > 0; ++it) {
        const long double mid = (lo + hi) / 2;
        if (mid == lo || mid == hi) break;
        const long double fm = radau_polynomial(mid);
        if ((fm < 0) == (flo < 0)) {
          lo = mid;
          flo = fm;
        } else {
          hi = mid;
        }
      }
      h[static_cast<std::size_t>(++found)] = static_cast<double>(((lo + hi) / 2 + 1) / 2);
    }
    a = b;
    fa = fb;
  }
  return h;
}

/// The expansion of Newton's basis in powers of s: C[k][m] is the
/// coefficient of s^m in N_k(s) = s (s − h₁)…(s − h_{k−1}), k, m = 1 … 7.
/// With q̈(s) = a₀ + Σ_k g_k N_k(s) = a₀ + Σ_m b_{m−1} s^m,
/// b_{m−1} = Σ_{k ≥ m} C[k][m] g_k.
struct Basis {
  std::array<std::array<double, K + 1>, K + 1> c{};
  /// 1/h_k and 1/(h_k − h_j), j < k, for the divided differences.
  std::array<double, K + 1> inv_h{};
  std::array<std::array<double, K + 1>, K + 1> inv_gap{};
  /// C(k + 1, j + 1), for re-expanding a polynomial about a new step.
  std::array<std::array<double, K>, K> binomial{};
  Basis() {
    const auto& h = GaussRadau15::nodes();
    std::array<std::array<long double, K + 2>, K + 1> poly{};  // poly[k][m]
    poly[1][1] = 1;
    for (int k = 2; k <= K; ++k)
      for (int m = 1; m <= k; ++m)  // N_k = N_{k−1} · (s − h_{k−1})
        poly[k][m] = poly[k - 1][m - 1] - static_cast<long double>(h[k - 1]) * poly[k - 1][m];
    for (int k = 1; k <= K; ++k)
      for (int m = 1; m <= k; ++m) c[k][m] = static_cast<double>(poly[k][m]);
    for (int k = 1; k <= K; ++k) {
      inv_h[k] = 1.0 / h[static_cast<std::size_t>(k)];
      for (int j = 1; j < k; ++j) inv_gap[k][j] = 1.0 / (h[static_cast<std::size_t>(k)] - h[static_cast<std::size_t>(j)]);
    }
    for (int k = 0; k < K; ++k)
      for (int j = 0; j <= k; ++j) {
        double r = 1;  // C(k + 1, j + 1)
        for (int i = 1; i <= j + 1; ++i) r = r * (k + 1 - (j + 1) + i) / i;
        binomial[k][j] = r;
      }
  }
};

const Basis& basis() {
  static const Basis b;
  return b;
}

/// Kahan's compensated sum: adds `in` to *p, carrying the lost low bits in
/// *c (the sum is *p − *c).
inline void add_compensated(double& p, double& c, double in) {
  const double y = in - c;
  const double t = p + y;
  c = (t - p) - y;
  p = t;
}

// Coefficients of b_k in q (÷(k+2)(k+3)) and q̇ (÷(k+2)).
constexpr std::array<double, K> kPosition{1.0 / 6, 1.0 / 12, 1.0 / 20, 1.0 / 30, 1.0 / 42, 1.0 / 56, 1.0 / 72};
constexpr std::array<double, K> kVelocity{1.0 / 2, 1.0 / 3, 1.0 / 4, 1.0 / 5, 1.0 / 6, 1.0 / 7, 1.0 / 8};

constexpr int kMaxIterations = 12;

/// The iteration has converged when b₆ changes by less than this relative
/// to |q̈| (the round-off of double precision).
constexpr double kConverged = 1e-16;
/// A stalled iteration is taken as converged (at its round-off floor) below
/// this: g₇, a 7th divided difference over nodes as close as 0.09, carries
/// about 1e4 ε of q̈'s round-off.
constexpr double kStalled = 1e-12;
/// A step whose next step would be under this fraction of it is rejected;
/// steps grow by at most its inverse (Rein & Spiegel 2015).
constexpr double kSafety = 0.25;
/// Past this growth of the step the previous polynomial predicts nothing.
constexpr double kMaxPredictedRatio = 20;

}  // namespace

const std::array<double, 8>& GaussRadau15::nodes() {
  static const std::array<double, 8> h = compute_nodes();
  return h;
}

GaussRadau15::GaussRadau15(int n)
    : n_(n),
      q_(static_cast<std::size_t>(n)),
      v_(q_),
      cq_(q_),
      cv_(q_),
      a0_(q_),
      b_(static_cast<std::size_t>(K * n)),
      g_(b_),
      e_(b_),
      b_last_(b_),
      e_last_(b_),
      q0_(q_),
      v0_(q_),
      cq0_(q_),
      cv0_(q_),
      a00_(q_),
      x_(static_cast<std::size_t>(2 * n)),
      dx_(x_) {
  basis();
}

void GaussRadau15::start(const double* x) {
  moved(x, true);
}

void GaussRadau15::moved(const double* x, bool discontinuous) {
  std::copy(x, x + n_, q_.begin());
  std::copy(x + n_, x + 2 * n_, v_.begin());
  std::fill(cq_.begin(), cq_.end(), 0.0);
  std::fill(cv_.begin(), cv_.end(), 0.0);
  a0_valid_ = false;
  if (discontinuous) have_last_ = false;
}

void GaussRadau15::predict(double dt) {
  // The last step's polynomial about its end, in the new step's s:
  // s_old = 1 + r s with r = dt/dt_last, so Σ_k b_k s_old^{k+1} gives
  // e_j = r^{j+1} Σ_{k ≥ j} C(k+1, j+1) b_k for the power s^{j+1}. The
  // difference between the last step's converged b and its own prediction
  // is added to the new prediction (Everhart 1985).
  const double r = have_last_ ? dt / dt_last_ : 0.0;
  if (!have_last_ || !(r <= kMaxPredictedRatio)) {
    std::fill(e_.begin(), e_.end(), 0.0);
    std::fill(b_.begin(), b_.end(), 0.0);
    return;
  }
  const auto& binomial = basis().binomial;
  double rp = r;
  for (int j = 0; j < K; ++j, rp *= r) {
    double* ej = &e_[static_cast<std::size_t>(j * n_)];
    for (int i = 0; i < n_; ++i) ej[i] = 0;
    for (int k = j; k < K; ++k) {
      const double w = rp * binomial[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)];
      const double* bk = &b_last_[static_cast<std::size_t>(k * n_)];
      for (int i = 0; i < n_; ++i) ej[i] += w * bk[i];
    }
    for (int i = 0; i < n_; ++i) {
      const std::size_t at = static_cast<std::size_t>(j * n_ + i);
      b_[at] = e_[at] + (b_last_[at] - e_last_[at]);
    }
  }
}

GaussRadau15::Attempt GaussRadau15::attempt(FirstOrderRhs f, double t, double dt) {
  const auto& h = nodes();
  const Basis& basis_ = basis();
  const auto& c = basis_.c;
  const std::size_t n = static_cast<std::size_t>(n_);
  if (!a0_valid_) {
    std::copy(q_.begin(), q_.end(), x_.begin());
    std::copy(v_.begin(), v_.end(), x_.begin() + n_);
    f(x_.data(), dx_.data(), t);
    std::copy(dx_.begin() + n_, dx_.end(), a0_.begin());
    a0_valid_ = true;
  }
  predict(dt);
  // g from b: b_{m−1} = Σ_{k ≥ m} C[k][m] g_k, C[m][m] = 1, solved from m = 7 down.
  for (int m = K; m >= 1; --m)
    for (std::size_t i = 0; i < n; ++i) {
      double s = b_[(m - 1) * n + i];
      for (int k = m + 1; k <= K; ++k) s -= c[k][m] * g_[(k - 1) * n + i];
      g_[(m - 1) * n + i] = s;
    }
  Attempt out;
  double last_change = std::numeric_limits<double>::infinity();
  // The scale of q̈ over the step: the largest |q̈| at its start and nodes
  // (one node's alone may pass near zero).
  double a0_scale = 0;
  for (std::size_t i = 0; i < n; ++i) a0_scale = std::max(a0_scale, std::abs(a0_[i]));
  double max_acc = a0_scale;
  for (int it = 1; it <= kMaxIterations; ++it) {
    out.iterations = it;
    double max_change = 0;
    max_acc = a0_scale;
    for (int node = 1; node <= K; ++node) {
      const double s = h[static_cast<std::size_t>(node)];
      for (std::size_t i = 0; i < n; ++i) {
        double pq = b_[6 * n + i] * kPosition[6];
        double pv = b_[6 * n + i] * kVelocity[6];
        for (int k = K - 2; k >= 0; --k) {
          pq = b_[static_cast<std::size_t>(k) * n + i] * kPosition[static_cast<std::size_t>(k)] + s * pq;
          pv = b_[static_cast<std::size_t>(k) * n + i] * kVelocity[static_cast<std::size_t>(k)] + s * pv;
        }
        const double dq = dt * s * (v_[i] + dt * s * (0.5 * a0_[i] + s * pq));
        const double dv = dt * s * (a0_[i] + s * pv);
        x_[i] = q_[i] + (dq - cq_[i]);
        x_[n + i] = v_[i] + (dv - cv_[i]);
      }
      f(x_.data(), dx_.data(), t + s * dt);
      const double* acc = dx_.data() + n_;
      const auto& inv_gap = basis_.inv_gap[static_cast<std::size_t>(node)];
      for (std::size_t i = 0; i < n; ++i) {
        // The divided difference a[0, h₁, …, h_node].
        double d = (acc[i] - a0_[i]) * basis_.inv_h[static_cast<std::size_t>(node)];
        for (int j = 1; j < node; ++j) d = (d - g_[(j - 1) * n + i]) * inv_gap[static_cast<std::size_t>(j)];
        const double change = d - g_[(node - 1) * n + i];
        g_[(node - 1) * n + i] = d;
        for (int m = 1; m <= node; ++m) b_[(m - 1) * n + i] += c[node][m] * change;
        max_acc = std::max(max_acc, std::abs(acc[i]));
        if (node == K) max_change = std::max(max_change, std::abs(change));
      }
    }
    out.corrector_change = max_acc > 0 ? max_change / max_acc : (max_change > 0 ? max_change : 0.0);
    if (!std::isfinite(out.corrector_change) || out.corrector_change < kConverged) break;
    // Stalled: at the round-off floor when small; an early bump of a
    // converging iteration may still go on, a later one is divergence.
    if (it > 2 && out.corrector_change >= last_change && (out.corrector_change < kStalled || it > 4)) break;
    last_change = out.corrector_change;
  }
  // Converged, or at the round-off floor of the divided differences.
  out.converged = out.corrector_change < kStalled;
  double max_b6 = 0;
  for (std::size_t i = 0; i < n; ++i) max_b6 = std::max(max_b6, std::abs(b_[6 * n + i]));
  out.error = max_acc > 0 ? max_b6 / max_acc : (max_b6 > 0 ? std::numeric_limits<double>::infinity() : 0.0);
  return out;
}

double GaussRadau15::next_step(double dt, double error, double eps) {
  if (!(error > 0)) return dt / kSafety;  // the polynomial is exact: grow by the most allowed
  const double next = dt * std::pow(eps / error, 1.0 / 7.0);
  return std::min(next, dt / kSafety);
}

void GaussRadau15::accept(double dt) {
  const std::size_t n = static_cast<std::size_t>(n_);
  q0_ = q_;
  v0_ = v_;
  cq0_ = cq_;
  cv0_ = cv_;
  a00_ = a0_;
  const double dt2 = dt * dt;
  for (std::size_t i = 0; i < n; ++i) {
    // Smallest terms first. The largest, q̇₀ Δt and q̈₀ Δt, are added with
    // their products' rounding (exact by fma) and with the velocity's own
    // compensation: the state's round-off then does not grow with the steps.
    for (int k = K - 1; k >= 0; --k) {
      const double bk = b_[static_cast<std::size_t>(k) * n + i];
      add_compensated(q_[i], cq_[i], dt2 * kPosition[static_cast<std::size_t>(k)] * bk);
      add_compensated(v_[i], cv_[i], dt * kVelocity[static_cast<std::size_t>(k)] * bk);
    }
    add_compensated(q_[i], cq_[i], 0.5 * dt2 * a0_[i]);
    const double qv = dt * v0_[i];
    add_compensated(q_[i], cq_[i], std::fma(dt, v0_[i], -qv) - dt * cv0_[i]);
    add_compensated(q_[i], cq_[i], qv);
    const double va = dt * a0_[i];
    add_compensated(v_[i], cv_[i], std::fma(dt, a0_[i], -va));
    add_compensated(v_[i], cv_[i], va);
  }
  b_last_ = b_;
  e_last_ = e_;
  dt_last_ = dt;
  have_last_ = true;
  a0_valid_ = false;
}

void GaussRadau15::state(double* x) const {
  for (int i = 0; i < n_; ++i) {
    x[i] = q_[static_cast<std::size_t>(i)] - cq_[static_cast<std::size_t>(i)];
    x[n_ + i] = v_[static_cast<std::size_t>(i)] - cv_[static_cast<std::size_t>(i)];
  }
}

void GaussRadau15::dense(double s, double* x) const {
  const std::size_t n = static_cast<std::size_t>(n_);
  const double dt = dt_last_;
  for (std::size_t i = 0; i < n; ++i) {
    double pq = b_last_[6 * n + i] * kPosition[6];
    double pv = b_last_[6 * n + i] * kVelocity[6];
    for (int k = K - 2; k >= 0; --k) {
      pq = b_last_[static_cast<std::size_t>(k) * n + i] * kPosition[static_cast<std::size_t>(k)] + s * pq;
      pv = b_last_[static_cast<std::size_t>(k) * n + i] * kVelocity[static_cast<std::size_t>(k)] + s * pv;
    }
    x[i] = q0_[i] + (dt * s * (v0_[i] + dt * s * (0.5 * a00_[i] + s * pq)) - cq0_[i]);
    x[n + i] = v0_[i] + (dt * s * (a00_[i] + s * pv) - cv0_[i]);
  }
}

}  // namespace lagrangian::detail
