#pragma once
// Internal: the 15th-order Gauss–Radau integrator for second-order systems
// q̈ = f(q, q̇, t) (method "gauss_radau15"), after Everhart (1985, "An
// efficient integrator that uses Gauss-Radau spacings", in Dynamics of
// Comets, IAU Coll. 83, 185) and Rein & Spiegel (2015, MNRAS 446, 1424,
// "IAS15"). Compiled once in src/integrate/gauss_radau.cpp.
//
// Over a step of size Δt from t₀, with s = (t − t₀)/Δt ∈ [0, 1], the
// acceleration is a polynomial of degree 7,
//   q̈(s) = a₀ + b₀ s + b₁ s² + … + b₆ s⁷,
// and integrating it twice gives the state inside the step:
//   q̇(s) = q̇₀ + Δt s (a₀ + b₀ s/2 + b₁ s²/3 + … + b₆ s⁷/8),
//   q(s)  = q₀ + q̇₀ Δt s + Δt² s² (a₀/2 + b₀ s/6 + b₁ s²/12 + … + b₆ s⁷/72).
// The b are fixed by collocation at the 7 Gauss–Radau nodes h₁ … h₇ of
// [0, 1] (with h₀ = 0: the 8-point Radau rule, exact to degree 14, so the
// step's error is O(Δt¹⁶)): in Newton's form
//   q̈(s) = a₀ + g₁ s + g₂ s (s − h₁) + … + g₇ s (s − h₁)…(s − h₆),
// each g_k is a divided difference of the accelerations at the nodes, and
// since the accelerations at the nodes depend on the state there, which
// depends on the b, the b are found by fixed-point iteration from a
// prediction (the previous step's polynomial, re-expanded about the new
// step). The same polynomial gives the dense output. |b₆|/|q̈|, the size of
// the last term, measures the step's error and sets the next step,
//   Δt_new = Δt (ε / (max|b₆| / max|q̈|))^(1/7),  (max|q̈| over the step's nodes)
// with ε the run's rtol (Rein & Spiegel 2015, §3.3). The state is summed
// with Kahan's compensation, so that the round-off of the sums does not
// grow with the number of steps.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include "lagrangian/integrate/detail/roots.hpp"

namespace lagrangian::detail {

/// The smallest tolerance the error measure |b₆|/|q̈| can resolve: below
/// about 1e-12 it is the round-off of a 7th divided difference, and steps
/// chosen against a smaller tolerance shrink without end. A run asking for
/// less runs at this and says so.
inline constexpr double kGaussRadauSmallestTolerance = 1e-11;

/// f(x, ẋ, t) of the first-order system x = [q; q̇] (2n values): the
/// stepper uses the second half of ẋ, q̈.
using FirstOrderRhs = FunctionRef<void(const double* x, double* dxdt, double t)>;

/// The constants of the method (computed once, src/integrate/gauss_radau.cpp).
struct GaussRadauConstants {
  static constexpr int K = 7;  ///< polynomial terms b₀ … b₆, nodes h₁ … h₇
  /// h₀ = 0 and the Gauss–Radau nodes h₁ … h₇ on [0, 1]: the roots of
  /// (P₇(u) + P₈(u))/(1 + u), u = 2h − 1, with Pₖ Legendre's polynomials.
  std::array<double, K + 1> h{};
  /// c[k][m]: the coefficient of s^m in Newton's basis polynomial
  /// N_k(s) = s (s − h₁)…(s − h_{k−1}); with q̈(s) = a₀ + Σ_k g_k N_k(s)
  /// = a₀ + Σ_m b_{m−1} s^m, b_{m−1} = Σ_{k ≥ m} c[k][m] g_k.
  std::array<std::array<double, K + 1>, K + 1> c{};
  /// 1/h_k and 1/(h_k − h_j), j < k, for the divided differences.
  std::array<double, K + 1> inv_h{};
  std::array<std::array<double, K + 1>, K + 1> inv_gap{};
  /// C(k + 1, j + 1), for re-expanding a polynomial about a new step.
  std::array<std::array<double, K>, K> binomial{};
};
const GaussRadauConstants& gauss_radau_constants();

/// The stepper for N coordinates (state of 2N values); N = 0: any number,
/// given at construction. Fixed N keeps every per-coordinate loop a
/// compile-time one (compiled for N ≤ 8 in src/integrate/gauss_radau_loop.cpp).
template <int N = 0>
class GaussRadau15 {
  static constexpr int K = GaussRadauConstants::K;
  template <int M>
  using Store = std::conditional_t<(N > 0), std::array<double, static_cast<std::size_t>(M * (N > 0 ? N : 1))>,
                                   std::vector<double>>;

 public:
  /// h₀ = 0 and the Gauss–Radau nodes h₁ … h₇ (see GaussRadauConstants).
  static const std::array<double, 8>& nodes() { return gauss_radau_constants().h; }

  /// A stepper for n coordinates (n = N when N > 0).
  explicit GaussRadau15(int n = N) : n_(N > 0 ? N : n) {
    if constexpr (N == 0) {
      for (Start* st : {&now_, &start_}) resize(*st);
      for (Polynomial* p : {&last_, &before_, &dense_}) resize(*p);
      for (auto* v : {&b_, &g_, &e_}) v->assign(static_cast<std::size_t>(K * n_), 0.0);
      x_.assign(static_cast<std::size_t>(2 * n_), 0.0);
      dx_ = x_;
    } else {
      for (auto* v : {&b_, &g_, &e_}) v->fill(0.0);
    }
    gauss_radau_constants();
  }

  /// Starts from the state x (2n values): no compensation, no prediction.
  void start(const double* x) { moved(x, true); }
  /// The state was changed between steps to x: by a projection onto the
  /// constraints (`discontinuous` false: the previous step's polynomial
  /// still predicts the next) or by an impact (true: it does not).
  void moved(const double* x, bool discontinuous) {
    for (int i = 0; i < n(); ++i) {
      now_.q[at(i)] = x[i];
      now_.v[at(i)] = x[n() + i];
      now_.cq[at(i)] = now_.cv[at(i)] = 0.0;
    }
    a0_valid_ = false;
    if (discontinuous) last_.valid = false;
  }

  /// What an attempted step found.
  struct Attempt {
    int iterations = 0;           ///< predictor–corrector iterations
    double corrector_change = 0;  ///< max |Δb₆| / max |q̈| of the last iteration
    bool converged = false;       ///< the iteration reached round-off
    double error = 0;             ///< max |b₆| / max |q̈|, the step's error measure
    /// τ = √(2 |q̈|² / (|q⃛|² + |q̈| |q⁗|)) at the step's end (norms over all
    /// coordinates; s), the time scale of the motion (Pham, Rein & Spiegel
    /// 2024); 0 where it is not defined (q̈ = 0).
    double timescale = 0;
  };
  /// Iterates the polynomial of a step of size dt from time t (the state is
  /// left as it was; accept() advances it).
  Attempt attempt(FirstOrderRhs f, double t, double dt);
  /// The next step after a step of size dt whose error measure was `error`,
  /// for the tolerance eps: dt (eps/error)^(1/7), at most 4 dt.
  static double next_step(double dt, double error, double eps) {
    if (!(error > 0)) return dt / kSafety;  // the polynomial is exact: grow by the most allowed
    return std::min(dt * std::pow(eps / error, 1.0 / 7.0), dt / kSafety);
  }
  /// The next step: the larger of (7! eps)^(1/7) τ from the motion's time
  /// scale (Pham, Rein & Spiegel 2024), which takes far fewer steps on
  /// eccentric orbits, and the step from the error measure, which still
  /// holds where q̈ passes through zero and τ with it (a pendulum at the
  /// bottom); at most 4 dt.
  static double next_step(double dt, const Attempt& a, double eps) {
    const double by_error = next_step(dt, a.error, eps);
    if (!(a.timescale > 0) || !std::isfinite(a.timescale)) return by_error;
    return std::min(std::max(std::pow(5040.0 * eps, 1.0 / 7.0) * a.timescale, by_error), dt / kSafety);
  }
  /// Advances the state over the step just attempted (size dt) and predicts
  /// the polynomial of the next.
  void accept(double dt);

  /// Returns to the start of the last accepted step, as before accept():
  /// to take a shorter step to an event inside it. (The polynomial inside
  /// a step is of order 9 or so; only its end has the method's order 15,
  /// so a state continued from inside a step would carry that error.)
  void rewind();

  /// The state (2n values) after the last accepted step.
  void state(double* x) const {
    for (int i = 0; i < n(); ++i) {
      x[i] = now_.q[at(i)] - now_.cq[at(i)];
      x[n() + i] = now_.v[at(i)] - now_.cv[at(i)];
    }
  }
  /// The state (2n values) at the fraction s ∈ [0, 1] of the last accepted
  /// step, from its polynomial.
  void dense(double s, double* x) const;
  /// The size of the last accepted step (the one dense() covers).
  double dense_step() const { return dense_.dt; }

  /// A step whose next step would be under this fraction of it is
  /// rejected; steps grow by at most its inverse (Rein & Spiegel 2015).
  static constexpr double kSafety = 0.25;

 private:
  static constexpr int kMaxIterations = 12;
  /// The iteration has converged when b₆ changes by less than this relative
  /// to |q̈| (the round-off of double precision).
  static constexpr double kConverged = 1e-16;
  /// A stalled iteration is taken as converged (at its round-off floor)
  /// below this: g₇, a 7th divided difference over nodes as close as 0.09,
  /// carries up to about 1e4 ε of q̈'s round-off.
  static constexpr double kStalled = 1e-12;
  /// Past this growth of the step the previous polynomial predicts nothing.
  static constexpr double kMaxPredictedRatio = 20;
  // Coefficients of b_k in q (÷(k+2)(k+3)) and q̇ (÷(k+2)).
  static constexpr std::array<double, K> kPosition{1.0 / 6, 1.0 / 12, 1.0 / 20, 1.0 / 30, 1.0 / 42, 1.0 / 56, 1.0 / 72};
  static constexpr std::array<double, K> kVelocity{1.0 / 2, 1.0 / 3, 1.0 / 4, 1.0 / 5, 1.0 / 6, 1.0 / 7, 1.0 / 8};

  static std::size_t at(int i) { return static_cast<std::size_t>(i); }
  /// n: a compile-time constant when N > 0.
  int n() const {
    if constexpr (N > 0) {
      return N;
    } else {
      return n_;
    }
  }
  std::size_t at(int k, int i) const { return static_cast<std::size_t>(k * n() + i); }
  /// Kahan's compensated sum: adds `in` to p, carrying the lost low bits
  /// in c (the sum is p − c).
  static void add_compensated(double& p, double& c, double in) {
    const double y = in - c;
    const double t = p + y;
    c = (t - p) - y;
    p = t;
  }
  void predict(double dt);
  /// The changes of q and q̇ (coordinate i) from a step's start to the
  /// fraction s of it, for coefficients b, start velocity v0 and q̈ a0:
  /// Δq = Δt s (v0 + Δt s (a0/2 + Σ_k b_k s^{k+1}/((k+2)(k+3)))),
  /// Δq̇ = Δt s (a0 + Σ_k b_k s^{k+1}/(k+2)).
  void increments(const Store<K>& b, int i, double v0, double a0, double s, double dt, double& dq, double& dv) const;

  /// The state at a step's start, with its compensation (q − cq is the
  /// sum), and q̈ there.
  struct Start {
    Store<1> q{}, v{}, cq{}, cv{}, a0{};
  };
  /// An accepted step's polynomial: its converged b, the prediction they
  /// were iterated from, the step's size; `valid` false when there is none.
  struct Polynomial {
    Store<K> b{}, e{};
    double dt = 0;
    bool valid = false;
  };
  void resize(Start& s) const {
    for (auto* v : {&s.q, &s.v, &s.cq, &s.cv, &s.a0}) v->assign(static_cast<std::size_t>(n_), 0.0);
  }
  void resize(Polynomial& p) const {
    for (auto* v : {&p.b, &p.e}) v->assign(static_cast<std::size_t>(K * n_), 0.0);
  }

  int n_;
  Start now_;                         // the current state: the next step's start
  bool a0_valid_ = false;             // now_.a0 is q̈ at now_
  Store<K> b_{}, g_{}, e_{};          // 7 × n each: b_k of the attempt, Newton g_k, its prediction
  Polynomial last_;                   // the last accepted step's, predicting the next
  Polynomial before_;                 // the one before it, for rewind()
  Start start_;                       // the last accepted step's start, for dense() and rewind()
  Polynomial dense_;                  // the last accepted step's, for dense()
  Store<2> x_{}, dx_{};               // 2n: a node's state and its derivative
};

template <int N>
void GaussRadau15<N>::predict(double dt) {
  // The last step's polynomial about its end, in the new step's s:
  // s_old = 1 + r s with r = dt/dt_last, so Σ_k b_k s_old^{k+1} gives
  // e_j = r^{j+1} Σ_{k ≥ j} C(k+1, j+1) b_k for the power s^{j+1}. The
  // difference between the last step's converged b and its own prediction
  // is added to the new prediction (Everhart 1985).
  const double r = last_.valid ? dt / last_.dt : 0.0;
  if (!last_.valid || !(r <= kMaxPredictedRatio)) {
    std::fill(e_.begin(), e_.end(), 0.0);
    std::fill(b_.begin(), b_.end(), 0.0);
    return;
  }
  const auto& binomial = gauss_radau_constants().binomial;
  double rp = r;
  for (int j = 0; j < K; ++j, rp *= r)
    for (int i = 0; i < n(); ++i) {
      double s = 0;
      for (int k = j; k < K; ++k) s += binomial[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)] * last_.b[at(k, i)];
      e_[at(j, i)] = rp * s;
      b_[at(j, i)] = e_[at(j, i)] + (last_.b[at(j, i)] - last_.e[at(j, i)]);
    }
}

template <int N>
typename GaussRadau15<N>::Attempt GaussRadau15<N>::attempt(FirstOrderRhs f, double t, double dt) {
  const GaussRadauConstants& gr = gauss_radau_constants();
  const auto& h = gr.h;
  const auto& c = gr.c;
  if (!a0_valid_) {
    for (int i = 0; i < n(); ++i) {
      x_[at(i)] = now_.q[at(i)];
      x_[at(n() + i)] = now_.v[at(i)];
    }
    f(x_.data(), dx_.data(), t);
    for (int i = 0; i < n(); ++i) now_.a0[at(i)] = dx_[at(n() + i)];
    a0_valid_ = true;
  }
  predict(dt);
  // g from b: b_{m−1} = Σ_{k ≥ m} c[k][m] g_k, c[m][m] = 1, solved from m = 7 down.
  for (int m = K; m >= 1; --m)
    for (int i = 0; i < n(); ++i) {
      double s = b_[at(m - 1, i)];
      for (int k = m + 1; k <= K; ++k) s -= c[static_cast<std::size_t>(k)][static_cast<std::size_t>(m)] * g_[at(k - 1, i)];
      g_[at(m - 1, i)] = s;
    }
  Attempt out;
  double last_change = std::numeric_limits<double>::infinity();
  // The scale of q̈ over the step: the largest |q̈| at its start and nodes
  // (one node's alone may pass near zero).
  double a0_scale = 0;
  for (int i = 0; i < n(); ++i) a0_scale = std::max(a0_scale, std::abs(now_.a0[at(i)]));
  double max_acc = a0_scale;
  for (int it = 1; it <= kMaxIterations; ++it) {
    out.iterations = it;
    double max_change = 0;
    max_acc = a0_scale;
    for (int node = 1; node <= K; ++node) {
      const std::size_t nd = static_cast<std::size_t>(node);
      const double s = h[nd];
      for (int i = 0; i < n(); ++i) {
        double dq, dv;
        increments(b_, i, now_.v[at(i)], now_.a0[at(i)], s, dt, dq, dv);
        x_[at(i)] = now_.q[at(i)] + (dq - now_.cq[at(i)]);
        x_[at(n() + i)] = now_.v[at(i)] + (dv - now_.cv[at(i)]);
      }
      f(x_.data(), dx_.data(), t + s * dt);
      const double* acc = dx_.data() + n();
      const auto& inv_gap = gr.inv_gap[nd];
      const double inv_h = gr.inv_h[nd];
      const auto& cn = c[nd];
      for (int i = 0; i < n(); ++i) {
        // The divided difference a[0, h₁, …, h_node], by the recursion on
        // differences (exactly 0 for a constant q̈; a sum with explicit
        // weights loses two digits to cancellation).
        double d = (acc[i] - now_.a0[at(i)]) * inv_h;
        for (int j = 1; j < node; ++j) d = (d - g_[at(j - 1, i)]) * inv_gap[static_cast<std::size_t>(j)];
        const double change = d - g_[at(node - 1, i)];
        g_[at(node - 1, i)] = d;
        for (int m = 1; m <= node; ++m) b_[at(m - 1, i)] += cn[static_cast<std::size_t>(m)] * change;
        max_acc = std::max(max_acc, std::abs(acc[i]));
        if (node == K) max_change = std::max(max_change, std::abs(change));
      }
    }
    out.corrector_change = max_acc > 0 ? max_change / max_acc : max_change;
    if (!std::isfinite(out.corrector_change) || out.corrector_change < kConverged) break;
    // Stalled: at the round-off floor when small; an early bump of a
    // converging iteration may still go on, a later one is divergence.
    if (it > 2 && out.corrector_change >= last_change && (out.corrector_change < kStalled || it > 4)) break;
    last_change = out.corrector_change;
  }
  // Converged, or at the round-off floor of the divided differences.
  out.converged = out.corrector_change < kStalled;
  double max_b6 = 0;
  for (int i = 0; i < n(); ++i) max_b6 = std::max(max_b6, std::abs(b_[at(6, i)]));
  out.error = max_acc > 0 ? max_b6 / max_acc : (max_b6 > 0 ? std::numeric_limits<double>::infinity() : 0.0);
  // q̈, its first and second derivative in time at the end, s = 1:
  // q̈ = a₀ + Σ b_k, q⃛ = Σ (k+1) b_k / Δt, q⁗ = Σ (k+1) k b_k / Δt².
  double a2 = 0, j2 = 0, s2 = 0;
  for (int i = 0; i < n(); ++i) {
    double a = now_.a0[at(i)], jerk = 0, snap = 0;
    for (int k = 0; k < K; ++k) {
      const double bk = b_[at(k, i)];
      a += bk;
      jerk += (k + 1) * bk;
      snap += (k + 1) * k * bk;
    }
    jerk /= dt;
    snap /= dt * dt;
    a2 += a * a;
    j2 += jerk * jerk;
    s2 += snap * snap;
  }
  const double denominator = j2 + std::sqrt(a2 * s2);
  out.timescale = a2 > 0 && denominator > 0 ? std::sqrt(2 * a2 / denominator) : 0.0;
  return out;
}

template <int N>
void GaussRadau15<N>::accept(double dt) {
  start_ = now_;
  const double dt2 = dt * dt;
  for (int i = 0; i < n(); ++i) {
    // Smallest terms first. The largest, q̇₀ Δt and q̈₀ Δt, are added with
    // their products' rounding (exact by fma) and with the velocity's own
    // compensation: the state's round-off then does not grow with the steps.
    double& q = now_.q[at(i)];
    double& cq = now_.cq[at(i)];
    double& v = now_.v[at(i)];
    double& cv = now_.cv[at(i)];
    for (int k = K - 1; k >= 0; --k) {
      const double bk = b_[at(k, i)];
      add_compensated(q, cq, dt2 * kPosition[static_cast<std::size_t>(k)] * bk);
      add_compensated(v, cv, dt * kVelocity[static_cast<std::size_t>(k)] * bk);
    }
    add_compensated(q, cq, 0.5 * dt2 * now_.a0[at(i)]);
    const double qv = dt * start_.v[at(i)];
    add_compensated(q, cq, std::fma(dt, start_.v[at(i)], -qv) - dt * start_.cv[at(i)]);
    add_compensated(q, cq, qv);
    const double va = dt * now_.a0[at(i)];
    add_compensated(v, cv, std::fma(dt, now_.a0[at(i)], -va));
    add_compensated(v, cv, va);
  }
  before_ = last_;
  last_.b = b_;
  last_.e = e_;
  last_.dt = dt;
  last_.valid = true;
  dense_ = last_;
  a0_valid_ = false;
}

template <int N>
void GaussRadau15<N>::rewind() {
  now_ = start_;
  a0_valid_ = true;
  last_ = before_;
}

template <int N>
void GaussRadau15<N>::increments(const Store<K>& b, int i, double v0, double a0, double s, double dt, double& dq,
                                 double& dv) const {
  double pq = b[at(6, i)] * kPosition[6];
  double pv = b[at(6, i)] * kVelocity[6];
  for (int k = K - 2; k >= 0; --k) {
    pq = b[at(k, i)] * kPosition[static_cast<std::size_t>(k)] + s * pq;
    pv = b[at(k, i)] * kVelocity[static_cast<std::size_t>(k)] + s * pv;
  }
  dq = dt * s * (v0 + dt * s * (0.5 * a0 + s * pq));
  dv = dt * s * (a0 + s * pv);
}

template <int N>
void GaussRadau15<N>::dense(double s, double* x) const {
  for (int i = 0; i < n(); ++i) {
    double dq, dv;
    increments(dense_.b, i, start_.v[at(i)], start_.a0[at(i)], s, dense_.dt, dq, dv);
    x[i] = start_.q[at(i)] + (dq - start_.cq[at(i)]);
    x[n() + i] = start_.v[at(i)] + (dv - start_.cv[at(i)]);
  }
}

}  // namespace lagrangian::detail
