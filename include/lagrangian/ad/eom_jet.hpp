#pragma once
// ad::EomJet<N>: the number type of the single pass that derives the
// Euler–Lagrange equations (see ad.hpp and dynamics.hpp).

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <ostream>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include "lagrangian/ad/second_pool.hpp"
#include "lagrangian/ad/traits.hpp"
#include "lagrangian/ad/width_scope.hpp"

namespace lagrangian::ad {

// -- EomJet: the number type of the Euler–Lagrange pass ----------------------------

/// Number type for deriving the equations of motion of an N-coordinate
/// system in one pass. With the path direction s, (δq, δt) = (q̇, 1), it
/// carries
///   v = x,  d = ∂x/∂s,  gq = ∂x/∂q,  gv = ∂x/∂q̇,
///   c = ∂²x/∂q̇∂s = (∂²x/∂q̇∂q) q̇ + ∂²x/∂q̇∂t,  H = ∂²x/∂q̇∂q̇,
/// which for x = L are L, dL/ds, ∂L/∂q, p, the mixed term and M: everything
/// the Euler–Lagrange equations need, and no more (no ∂²/∂q², no ∂²/∂s²).
///
/// Run-time records keep the work where the numbers are non-zero:
/// - a level says which parts can be non-zero:
///     0 — a function of (q, t) only: gv = c = H = 0 (lengths, angles' sines);
///     1 — affine in q̇: H = 0 (velocities of points);
///     2 — general (kinetic energies);
/// - a storage state says which coordinates the first-order parts (gq, gv,
///   c) can depend on: none (constants, time), a single coordinate k (sin q_k,
///   l_k q̇_k cos q_k: only entry k is stored and computed), or any (all N
///   entries, in fixed-length loops the compiler unrolls);
/// - a velocity support [lo, hi): the q̇ components the number depends on
///   (the velocity of the k-th link of a chain depends on q̇_0 … q̇_k), so H
///   lives on the rows [lo, hi);
/// - H is kept lazily as dense rows plus up to `lazy_terms` pending
///   rank-one terms f u uᵀ or f (u wᵀ + w uᵀ). A product of two
///   velocity-dependent factors only records a term; scaling a number
///   scales the coefficients; sums gather the terms, and a number that would
///   hold more sums its pending terms into its rows, all in one pass. Each
///   term is so summed into a matrix once, instead of once per operation
///   that carries it (T = Σ ½ m_k |v_k|² costs one pass per four squares).
///   Above kInlineHessianMax directions the dense rows and pending terms
///   live in a block from a per-thread pool (SecondPool), which holds only
///   the lower triangle of the rows on the support.
/// With RunTimeWidth, N is a capacity: the numbers carry the width() first
/// directions, set for a pass by a WidthScope (run-time sized models).
/// Read the parts through grad_q(), grad_qd(), mixed(), hess() and
/// hessian_to(). Measurements in docs/performance.md.
template <int N, bool RunTimeWidth>
class EomJet {
  static_assert(N >= 1, "ad::EomJet needs at least one coordinate");
  using Vector = std::array<double, N>;
  static constexpr int kNone = -2;   // no first-order dependence stored
  static constexpr int kDense = -1;  // all width() entries stored
  // Single-index storage and pending terms pay off from a few coordinates
  // on; below that, full storage and immediate updates are cheaper.
  static constexpr bool kSparse = N > 4;

 public:
  /// Largest N whose Hessian parts live in the number itself.
  static constexpr int kInlineHessianMax = 12;
  /// The number of directions: N, or for run-time-width numbers (N their
  /// capacity) the width set by the current WidthScope.
  static constexpr int width() {
    if constexpr (RunTimeWidth) {
      return detail::eom_width;
    } else {
      return N;
    }
  }
  static constexpr int hessian_size = N * (N + 1) / 2;
  /// Pending rank-one terms a number holds before it sums them into its
  /// dense rows.
  static constexpr int lazy_terms = kSparse ? 4 : 0;
  /// sin and cos of a number keep their last few results per thread (see
  /// detail::sin_cos): worth it where many angles are each taken more than
  /// once (T and V of a chain), a small cost on a miss otherwise.
  static constexpr bool memoize_trig = kSparse;
  using value_type = double;
  /// Makes this thread's pool of Hessian blocks exist now. A thread_local
  /// that keeps numbers holding blocks calls it before it is constructed, so
  /// that it is destroyed before the pool when the thread ends.
  static void prepare_thread() {
    if constexpr (kPooled) detail::SecondPool<Second>::give(detail::SecondPool<Second>::take());
  }

  // (No default member initialisers: results of operations set exactly the
  // fields their level needs; the constructors below set the rest.)
  int level;  ///< 0: function of (q, t); 1: affine in q̇; 2: general
  double v;   ///< value
  double d;   ///< derivative along the path (δq, δt) = (q̇, 1)

  /// Zero. (User-provided on purpose: value-initialisation, as Eigen does
  /// for its elements, then runs this constructor instead of zeroing every
  /// part.)
  constexpr EomJet() : level(0), v(0.0), d(0.0), state_(kNone) { init_constant(); }
  /// A constant. Implicit, so `S x = 0` and `x * 2` work.
  template <class A>
    requires std::is_arithmetic_v<A>
  constexpr EomJet(A value) : level(0), v(static_cast<double>(value)), d(0.0), state_(kNone) {
    init_constant();
  }

  /// Coordinate q_k with velocity q̇_k (its derivative along the path).
  static constexpr EomJet position(double q, double qd, int k) {
    EomJet r(q);
    r.d = qd;
    if constexpr (kSparse) {
      r.state_ = k;
    } else {
      r.state_ = kDense;
      set_zero(r.gq_, kDense);
    }
    r.gq_[k] = 1.0;
    return r;
  }
  /// Velocity q̇_k.
  static constexpr EomJet velocity(double qd, int k) {
    EomJet r(qd);
    r.level = 1;
    if constexpr (kSparse) {
      r.state_ = k;
      r.gq_[k] = 0.0;
      r.c_[k] = 0.0;
    } else {
      r.state_ = kDense;
      set_zero(r.gq_, kDense);
      set_zero(r.gv_, kDense);
      set_zero(r.c_, kDense);
    }
    r.gv_[k] = 1.0;
    r.lo_ = k;
    r.hi_ = k + 1;
    return r;
  }
  /// A coordinate that moves along the path with rate qd but is not one of
  /// the N differentiated ones (used when coordinates are seeded in blocks).
  static constexpr EomJet moving(double q, double qd) {
    EomJet r(q);
    r.d = qd;
    return r;
  }
  /// Time t (derivative 1 along the path).
  static constexpr EomJet time(double t) { return moving(t, 1.0); }

  /// ∂x/∂q_i.
  constexpr double grad_q(int i) const { return stored(i) ? gq_[i] : 0.0; }
  /// ∂x/∂q̇_i; zero below level 1.
  constexpr double grad_qd(int i) const { return level >= 1 && stored(i) ? gv_[i] : 0.0; }
  /// ∂²x/∂q̇_i∂s = Σ_j ∂²x/∂q̇_i∂q_j q̇_j + ∂²x/∂q̇_i∂t; zero below level 1.
  constexpr double mixed(int i) const { return level >= 1 && stored(i) ? c_[i] : 0.0; }
  /// H_ij = ∂²x/∂q̇_i∂q̇_j (symmetric); zero below level 2.
  constexpr double hess(int i, int j) const {  // (i, j by value: swapped below)
    if (level < 2) return 0.0;
    if constexpr (kPooled)  // (the block holds the lower triangle)
      if (j > i) std::swap(i, j);
    double h = 0.0;
    if (dense_ && i >= lo_ && i < hi_ && j >= lo_) h = H()[i * N + j];  // (row stride N)
    for (int k = 0; k < nterms_; ++k) h += terms()[k].at(i, j);
    return h;
  }
  /// Writes the full symmetric H into the matrix `m` (any type with
  /// m(i, j), cols() and setZero()) of width() columns, or of fewer when the
  /// directions past m.cols() were never seeded (their H entries are zero).
  template <class Matrix>
  constexpr void hessian_to(Matrix& m) const {
    EomJet sum = *this;
    sum.hessian_to(m);
  }
  /// The same, summing the pending terms in place (no copy).
  template <class Matrix>
  constexpr void hessian_to(Matrix& m) {
    m.setZero();
    if (level < 2 || (!dense_ && nterms_ == 0)) return;
    if constexpr (lazy_terms > 0) flush();  // (small systems hold no pending terms)
    const auto& h = H();
    if constexpr (kPooled) {
      for (int i = lo_; i < hi_; ++i)
        for (int j = lo_; j <= i; ++j) m(i, j) = m(j, i) = h[i * N + j];
    } else {
      const int cols = width() < m.cols() ? width() : static_cast<int>(m.cols());
      for (int i = lo_; i < hi_; ++i)
        for (int j = 0; j < cols; ++j) m(i, j) = h[i * N + j];
    }
  }

  /// Raises the level to L, zero-filling the parts that become valid.
  constexpr void raise(int L) {
    if (level < 1 && L >= 1) {
      set_zero(gv_, state_);
      set_zero(c_, state_);
      lo_ = hi_ = 0;
    }
    if (level < 2 && L >= 2) {
      dense_ = false;
      nterms_ = 0;
    }
    if (L > level) level = L;
  }

  constexpr EomJet& operator+=(const EomJet& b) { return accumulate(b, 1.0); }
  constexpr EomJet& operator-=(const EomJet& b) { return accumulate(b, -1.0); }
  constexpr EomJet& operator*=(const EomJet& b) { return *this = *this * b; }
  constexpr EomJet& operator/=(const EomJet& b) { return *this = *this / b; }
  constexpr EomJet& operator+=(double s) {
    v += s;
    return *this;
  }
  constexpr EomJet& operator-=(double s) {
    v -= s;
    return *this;
  }
  constexpr EomJet& operator*=(double s) {
    v *= s;
    d *= s;
    scale(gq_, state_, s);
    if (level >= 1) {
      scale(gv_, state_, s);
      scale(c_, state_, s);
    }
    if (level == 2) {
      if (dense_) {
        auto& h = H();
        if constexpr (kPooled) {
          for (int i = lo_; i < hi_; ++i)
            for (int j = lo_; j <= i; ++j) h[i * N + j] *= s;
        } else {
          for (int i = lo_ * N; i < hi_ * N; ++i) h[i] *= s;
        }
      }
      for (int k = 0; k < nterms_; ++k) terms()[k].f *= s;
    }
    return *this;
  }
  constexpr EomJet& operator/=(double s) { return *this *= 1.0 / s; }

  friend constexpr EomJet operator+(const EomJet& a) { return a; }
  friend constexpr EomJet operator-(const EomJet& a) { return scaled(a, -1.0, 0.0); }
  friend constexpr EomJet operator+(const EomJet& a, const EomJet& b) { return combined(a, b, 1.0); }
  friend constexpr EomJet operator-(const EomJet& a, const EomJet& b) { return combined(a, b, -1.0); }
  friend constexpr EomJet operator+(const EomJet& a, double s) { return scaled(a, 1.0, s); }
  friend constexpr EomJet operator+(double s, const EomJet& a) { return scaled(a, 1.0, s); }
  friend constexpr EomJet operator-(const EomJet& a, double s) { return scaled(a, 1.0, -s); }
  friend constexpr EomJet operator-(double s, const EomJet& a) { return scaled(a, -1.0, s); }
  friend constexpr EomJet operator*(const EomJet& a, double s) { return scaled(a, s, 0.0); }
  friend constexpr EomJet operator*(double s, const EomJet& a) { return scaled(a, s, 0.0); }
  friend constexpr EomJet operator/(const EomJet& a, double s) { return scaled(a, 1.0 / s, 0.0); }
  friend constexpr EomJet operator/(double s, const EomJet& a) { return reciprocal(a) *= s; }
  friend constexpr EomJet operator/(const EomJet& a, const EomJet& b) { return a * reciprocal(b); }

  /// Product rule, part by part, skipping parts known to be zero:
  ///   gq = a gq_b + b gq_a,  gv = a gv_b + b gv_a,
  ///   c = a c_b + b c_a + gv_a d_b + gv_b d_a,
  ///   H = a H_b + b H_a + gv_a gv_bᵀ + gv_b gv_aᵀ (the last two as one
  ///   pending term).
  friend constexpr EomJet operator*(const EomJet& a, const EomJet& b) { return product(a, b); }

  friend constexpr bool operator==(const EomJet& a, const EomJet& b) { return a.v == b.v; }
  friend constexpr auto operator<=>(const EomJet& a, const EomJet& b) { return a.v <=> b.v; }
  friend constexpr bool operator==(const EomJet& a, double b) { return a.v == b; }
  friend constexpr auto operator<=>(const EomJet& a, double b) { return a.v <=> b; }
  friend std::ostream& operator<<(std::ostream& os, const EomJet& a) { return os << a.v << "[eom]"; }

  /// f(a) from f, f', f'': gq = f' gq_a, gv = f' gv_a,
  /// c = f' c_a + f'' gv_a d_a, H = f' H_a + f'' gv_a gv_aᵀ.
  friend constexpr EomJet chain(const EomJet& a, double f0, double f1, double f2) {
    return chain_rule(a, f0, f1, f2);
  }

  /// f(a, b) from the value, first and second partials (rare functions:
  /// both arguments are first brought to dense storage).
  friend constexpr EomJet chain2(const EomJet& a, const EomJet& b, double f0, double fa, double fb, double faa,
                                 double fab, double fbb) {
    return chain2_rule(a, b, f0, fa, fb, faa, fab, fbb);
  }

  friend constexpr EomJet reciprocal(const EomJet& a) {
    const double r = 1.0 / a.v;
    return chain(a, r, -r * r, 2.0 * r * r * r);
  }

 private:
  struct Uninitialized {};
  // Small numbers (full storage) also set the parts a constant never reads:
  // g++ cannot follow the storage state through its flattened passes and
  // would warn that they are read uninitialised.
  constexpr void init_constant() {
    if constexpr (!kSparse) {
      lo_ = hi_ = 0;
      dense_ = false;
      nterms_ = 0;
      gq_.fill(0.0);
    }
  }

  /// A pending part of H: f u uᵀ (square) or f (u wᵀ + w uᵀ); u and w are
  /// stored in full, zero outside the rows [ulo, uhi) and [wlo, whi).
  struct Term {
    double f;
    int ulo, uhi, wlo, whi;
    bool sq;
    Vector u, w;
    constexpr Term() {}
    constexpr Term(const Term& o) { *this = o; }
    constexpr Term& operator=(const Term& o) {
      f = o.f;
      ulo = o.ulo;
      uhi = o.uhi;
      wlo = o.wlo;
      whi = o.whi;
      sq = o.sq;
      if constexpr (kPooled) {  // (u and w are read only on their supports)
        copy_range(u.data(), o.u.data(), ulo, uhi);
        if (!sq) copy_range(w.data(), o.w.data(), wlo, whi);
      } else {
        u = o.u;
        if (!sq) w = o.w;
      }
      return *this;
    }
    /// The term's (i, j) entry.
    constexpr double at(int i, int j) const {
      const double ui = i >= ulo && i < uhi ? u[i] : 0.0, uj = j >= ulo && j < uhi ? u[j] : 0.0;
      if (sq) return f * ui * uj;
      const double wi = i >= wlo && i < whi ? w[i] : 0.0, wj = j >= wlo && j < whi ? w[j] : 0.0;
      return f * (ui * wj + wi * uj);
    }
  };

  // Storage of gq, gv, c: kNone, kDense, or the single stored index k >= 0.
  int state_;
  // Velocity support [lo_, hi_) (valid at level >= 1; empty when lo_ == hi_).
  int lo_, hi_;
  // H at level 2: the dense rows [lo_, hi_) when dense_, plus terms_.
  bool dense_;
  int nterms_;
  Vector gq_;  // stored entries valid
  Vector gv_;  // stored entries valid at level >= 1
  Vector c_;   // stored entries valid at level >= 1
  /// The Hessian parts: pending terms, then the dense block (row-major;
  /// rows [lo_, hi_) valid when dense_).
  struct Second {
    std::array<Term, lazy_terms> terms;
    std::array<double, N * N> H;
  };
  // Small systems keep the Hessian parts in the number; larger ones in a
  // block taken from a per-thread pool when the number first needs one (a
  // number at level 2), so that a vector of n numbers stays small (an
  // n × n block per number would make it grow as n³).
  static constexpr bool kPooled = N > kInlineHessianMax;
  static_assert(kPooled || !RunTimeWidth, "ad::EomJet: run-time width needs a capacity above kInlineHessianMax");
  static_assert(!RunTimeWidth || N % kWidthStep == 0, "ad::EomJet: a run-time-width capacity is whole chunks");
  /// Owns a pooled block: a copy starts without one (it takes its own when
  /// it needs one), a move takes the block over, the destructor gives it back.
  struct PooledBlock {
    Second* p = nullptr;
    PooledBlock() = default;
    PooledBlock(const PooledBlock&) {}
    PooledBlock& operator=(const PooledBlock&) { return *this; }
    PooledBlock(PooledBlock&& o) noexcept : p(std::exchange(o.p, nullptr)) {}
    PooledBlock& operator=(PooledBlock&& o) noexcept {
      std::swap(p, o.p);
      return *this;
    }
    ~PooledBlock() {
      if (p != nullptr) detail::SecondPool<Second>::give(p);
    }
  };
  using SecondStorage = std::conditional_t<kPooled, PooledBlock, Second>;
  SecondStorage second_;

  /// The block of a number at level 2 that holds a dense block or terms.
  constexpr const Second& sec() const {
    if constexpr (kPooled) {
      return *second_.p;
    } else {
      return second_;
    }
  }
  /// The block, taken from the pool if the number has none yet.
  constexpr Second& sec() {
    if constexpr (kPooled) {
      if (second_.p == nullptr) second_.p = detail::SecondPool<Second>::take();
      return *second_.p;
    } else {
      return second_;
    }
  }
  // (The array itself, not a pointer into it: indexing a member array lets
  // the compiler see that H does not overlap gq_, gv_ and c_.)
  constexpr std::array<double, N * N>& H() { return sec().H; }
  constexpr const std::array<double, N * N>& H() const { return sec().H; }
  constexpr Term* terms() { return sec().terms.data(); }
  constexpr const Term* terms() const { return sec().terms.data(); }

  // For results whose every valid part is written by the operation.
  constexpr explicit EomJet(Uninitialized) {}

  constexpr bool stored(int i) const { return state_ == kDense || state_ == i; }

  /// Calls f(i) for i in [0, width()): a fixed-length loop over N (unrolled
  /// by the compiler), or for run-time widths (multiples of kWidthStep) a
  /// loop over chunks of kWidthStep indices, each chunk unrolled.
  template <class F>
  static constexpr void dense_loop(F&& f) {
    if constexpr (RunTimeWidth) {
      const int w = width();
      for (int i = 0; i < w; i += kWidthStep)
        for (int k = 0; k < kWidthStep; ++k) f(i + k);
    } else {
      for (int i = 0; i < N; ++i) f(i);
    }
  }
  /// Calls f(i) for every stored index of storage s: a fixed-length loop
  /// over N (unrolled by the compiler) when dense, one call when single.
  template <class F>
  static constexpr void each(int s, F&& f) {
    if (s == kDense) {
      dense_loop(f);
    } else if (kSparse && s >= 0) {
      f(s);
    }
  }

  /// The storage that holds both a and b.
  static constexpr int joint(int a, int b) {
    if constexpr (!kSparse) return (a == kNone && b == kNone) ? kNone : kDense;
    if (a == kNone) return b;
    if (b == kNone || a == b) return a;
    return kDense;
  }
  static constexpr void set_zero(Vector& x, int s) {
    if (s == kDense) {
      dense_loop([&](int i) { x[i] = 0.0; });
    } else if (s >= 0) {
      x[s] = 0.0;
    }
  }
  static constexpr void scale(Vector& x, int s, double f) {
    if (s == kDense) {
      dense_loop([&](int i) { x[i] *= f; });
    } else if (s >= 0) {
      x[s] *= f;
    }
  }
  /// r = f a in storage s, for a stored as sa (s holds sa).
  static constexpr void put(Vector& r, int s, double f, const Vector& a, int sa) {
    if (s == kDense && sa == kDense) {
      dense_loop([&](int i) { r[i] = f * a[i]; });
    } else {
      set_zero(r, s);
      if (sa >= 0) r[sa] = f * a[sa];
    }
  }
  /// r = f a + g b in storage s, for a and b stored as sa.
  static constexpr void put2(Vector& r, int s, double f, const Vector& a, double g, const Vector& b, int sa) {
    if (s == kDense && sa == kDense) {
      dense_loop([&](int i) { r[i] = f * a[i] + g * b[i]; });
    } else {
      set_zero(r, s);
      if (sa >= 0) r[sa] = f * a[sa] + g * b[sa];
    }
  }
  /// r += f a, for a stored as sa (r's storage holds sa).
  static constexpr void add(Vector& r, double f, const Vector& a, int sa) {
    if (sa == kDense) {
      dense_loop([&](int i) { r[i] += f * a[i]; });
    } else if (sa >= 0) {
      r[sa] += f * a[sa];
    }
  }
  /// r += f a + g b, for a and b stored as sa.
  static constexpr void add2(Vector& r, double f, const Vector& a, double g, const Vector& b, int sa) {
    if (sa == kDense) {
      dense_loop([&](int i) { r[i] += f * a[i] + g * b[i]; });
    } else if (sa >= 0) {
      r[sa] += f * a[sa] + g * b[sa];
    }
  }
  /// Re-stores the first-order parts in storage s, which holds the current one.
  constexpr void convert(int s);

  /// The velocity support holding both factors' supports.
  constexpr void set_hull(const EomJet& a, const EomJet& b);
  // The dense block: whole rows [lo_, hi_) inline; pooled, the lower
  // triangle of those rows within the support, columns [lo_, i] of row i.
  /// x = y for the first width() entries.
  static constexpr void copy_vector(Vector& x, const Vector& y) {
    if constexpr (RunTimeWidth) {
      dense_loop([&](int i) { x[i] = y[i]; });
    } else {
      x = y;
    }
  }
  /// Zeroes the rows [lo, hi) of the dense block.
  static constexpr void zero_rows(std::array<double, N * N>& H, int lo, int hi);
  /// Grows the velocity support to [lo, hi) ⊇ [lo_, hi_), zero-filling the
  /// new rows of the dense block (its columns outside the support are
  /// zeros already).
  constexpr void widen(int lo, int hi);
  /// Sums the pending terms into the dense rows: as P rank-one pieces
  /// f_p x_p y_pᵀ (a square is one piece, a symmetric term two), each row
  /// i gets Σ_p (f_p x_p,i) y_p in one branch-free pass of fixed length.
  /// (Kept out of line: it runs a few times per pass.)
  LAGRANGIAN_COLD void flush();
  /// to[i] = f from[i] for i in [lo, hi).
  static constexpr void scale_range(double* __restrict to, double f, const double* __restrict from, int lo, int hi) {
    for (int i = lo; i < hi; ++i) to[i] = f * from[i];
  }
  /// to[i] = from[i] for i in [lo, hi).
  static constexpr void copy_range(double* __restrict to, const double* __restrict from, int lo, int hi) {
    for (int i = lo; i < hi; ++i) to[i] = from[i];
  }
  /// row[j] += c y[j] for j in [lo, hi).
  static void axpy(double* __restrict row, double c, const double* __restrict y, int lo, int hi) {
    for (int j = lo; j < hi; ++j) row[j] += c * y[j];
  }
  /// row[j] += c y[j] + e z[j] for j in [lo, hi).
  static void axpy2(double* __restrict row, double c, const double* __restrict y, double e,
                    const double* __restrict z, int lo, int hi) {
    for (int j = lo; j < hi; ++j) row[j] += c * y[j] + e * z[j];
  }
  /// A free slot for a pending term (flushing the pending terms when every
  /// slot is taken). The term's supports must lie inside [lo_, hi_).
  constexpr Term& new_term()
    requires(lazy_terms > 0)
  {
    if (nterms_ == lazy_terms) flush();
    return terms()[nterms_++];
  }
  /// gv of a, in full (zero where a stores nothing).
  static constexpr void full_gv(Vector& out, const EomJet& a);
  /// Makes the dense rows valid (zero) if they are not yet.
  constexpr void ensure_dense();
  /// Pending H += f gv_a gv_aᵀ.
  constexpr void push_square(double f, const EomJet& a);
  /// Pending H += f (gv_a gv_bᵀ + gv_b gv_aᵀ).
  constexpr void push_symmetric(double f, const EomJet& a, const EomJet& b);
  /// H += f H_a, for a at level 2 whose support lies inside [lo_, hi_).
  constexpr void add_hessian_of(const EomJet& a, double f);

  /// r = f a + s.
  static constexpr EomJet scaled(const EomJet& a, double f, double s);
  /// r = a + sign b.
  static constexpr EomJet combined(const EomJet& a, const EomJet& b, double sign);
  /// this += sign b.
  constexpr EomJet& accumulate(const EomJet& b, double sign);
  /// a b (eom_jet_rules.hpp; a square when a and b are one number).
  static constexpr EomJet product(const EomJet& a, const EomJet& b);
  /// f(a) from f, f', f''.
  static constexpr EomJet chain_rule(const EomJet& a, double f0, double f1, double f2);
  /// f(a, b) from the value, first and second partials (out of line: rare).
  LAGRANGIAN_COLD static EomJet chain2_rule(EomJet a, EomJet b, double f0, double fa, double fb, double faa,
                                                      double fab, double fbb);

 public:
  constexpr EomJet(const EomJet& o) : level(o.level), v(o.v), d(o.d) { copy_parts(o); }
  constexpr EomJet& operator=(const EomJet& o) {
    level = o.level;
    v = o.v;
    d = o.d;
    copy_parts(o);
    return *this;
  }
  /// Moves take a pooled block over instead of copying it (inline blocks are
  /// copied, their valid rows only; eom_jet_parts.hpp).
  constexpr EomJet(EomJet&& o) noexcept;
  constexpr EomJet& operator=(EomJet&& o) noexcept;

 private:
  constexpr void copy_parts(const EomJet& o);
  /// The first-order parts and the support and Hessian bookkeeping (not the
  /// Hessian block itself) of o.
  constexpr void copy_first(const EomJet& o);
};

}  // namespace lagrangian::ad

#include "lagrangian/ad/eom_jet_parts.hpp"  // IWYU pragma: export
#include "lagrangian/ad/eom_jet_rules.hpp"  // IWYU pragma: export
