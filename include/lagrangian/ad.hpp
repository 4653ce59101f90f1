#pragma once
/// \file ad.hpp
/// Forward-mode automatic differentiation used to derive the equations of
/// motion. This header is the only place the AD backend is named: the rest of
/// the library speaks of `ad::Jet` and of the helpers below, so the backend can
/// be swapped without touching the dynamics.
///
/// `Jet<T, N, Order>` is a truncated Taylor polynomial in N directions:
///   x = v + Σ_i g_i ε_i + ½ Σ_ij h_ij ε_i ε_j      (Order = 2)
/// with the symmetric second-order part stored packed (N(N+1)/2 entries).
/// Order 1 is the ordinary dual number (value and gradient). It is a value
/// type without expression templates, so user model code may use `auto`
/// locals, `S x = 0`, `pow`, `abs`, `using std::cos` and branches freely.
/// `T` may itself be a Jet (nesting), which is how higher derivatives are
/// taken where needed.
///
/// `EomJet<N>` is the number type of the single pass that derives the
/// Euler–Lagrange equations (see dynamics.hpp); it tracks which parts of a
/// number are structurally zero so the O(N²) work happens only where needed.
///
/// Why not Eigen's AutoDiffScalar: nested AutoDiffScalar rejects `S x = 0.0`,
/// `pow` and `abs`, returns expression types that dangle when bound to `auto`,
/// and needs n(n+1) directions for a mass matrix where the symmetric
/// second-order Jet needs (n+1)(n+2)/2. The numbers are in docs/architecture.md.

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <ostream>
#include <type_traits>

#include <Eigen/Core>

namespace lagrangian::ad {

template <class T, int N, int Order = 1>
class Jet;

namespace detail {
template <class X>
struct is_jet : std::false_type {};
template <class T, int N, int O>
struct is_jet<Jet<T, N, O>> : std::true_type {};

/// Index of h_ij (i <= j) in packed upper-triangular storage of an N×N matrix.
constexpr int packed(int i, int j, int n) { return i * n - (i * (i - 1)) / 2 + (j - i); }
}  // namespace detail

/// True for Jet types (at any nesting depth).
template <class X>
inline constexpr bool is_jet_v = detail::is_jet<std::remove_cvref_t<X>>::value;

template <int N>
class EomJet;
namespace detail {
template <class X>
struct is_eom_jet : std::false_type {};
template <int N>
struct is_eom_jet<EomJet<N>> : std::true_type {};
}  // namespace detail

/// The AD number types of this header: Jet and EomJet. The <cmath>
/// functions below are written once for both.
template <class X>
concept ADNumber = is_jet_v<X> || detail::is_eom_jet<std::remove_cvref_t<X>>::value;

/// Underlying floating-point type of a (possibly nested) Jet, or X itself.
template <class X>
struct scalar_of {
  using type = X;
};
template <class T, int N, int O>
struct scalar_of<Jet<T, N, O>> {
  using type = typename scalar_of<T>::type;
};

/// Plain value of a number: the value part of an AD number, recursively.
template <class X>
constexpr auto value_of(const X& x) {
  if constexpr (ADNumber<X>) {
    return value_of(x.v);
  } else {
    return x;
  }
}

/// Truncated Taylor polynomial in N directions, first or second order.
template <class T, int N, int Order>
class Jet {
  static_assert(N >= 1, "ad::Jet needs at least one direction");
  static_assert(Order == 1 || Order == 2, "ad::Jet supports Order 1 (gradient) or 2 (gradient and Hessian)");

 public:
  static constexpr int directions = N;
  static constexpr int order = Order;
  static constexpr int hessian_size = Order == 2 ? N * (N + 1) / 2 : 0;
  using value_type = T;

  T v{};                          ///< value
  std::array<T, N> g{};           ///< ∂x/∂ε_i
  std::array<T, hessian_size> h{};  ///< ∂²x/∂ε_i∂ε_j, packed, i <= j

  constexpr Jet() = default;
  /// A constant (all derivatives zero). Implicit, so `S x = 0` and `x * 2` work.
  template <class A>
    requires(std::is_arithmetic_v<A> || std::is_same_v<A, T>)
  constexpr Jet(const A& value) : v(static_cast<T>(value)) {}

  /// The independent variable number `i` at `value` (seed ∂x/∂ε_i = 1).
  static constexpr Jet variable(const T& value, int i) {
    Jet r(value);
    r.g[i] = T(1);
    return r;
  }

  /// h_ij accessor (symmetric).
  constexpr const T& hess(int i, int j) const {
    return i <= j ? h[detail::packed(i, j, N)] : h[detail::packed(j, i, N)];
  }
  constexpr T& hess(int i, int j) { return i <= j ? h[detail::packed(i, j, N)] : h[detail::packed(j, i, N)]; }

  // -- compound assignment -------------------------------------------------
  constexpr Jet& operator+=(const Jet& b) {
    v += b.v;
    for (int i = 0; i < N; ++i) g[i] += b.g[i];
    for (int k = 0; k < hessian_size; ++k) h[k] += b.h[k];
    return *this;
  }
  constexpr Jet& operator-=(const Jet& b) {
    v -= b.v;
    for (int i = 0; i < N; ++i) g[i] -= b.g[i];
    for (int k = 0; k < hessian_size; ++k) h[k] -= b.h[k];
    return *this;
  }
  constexpr Jet& operator*=(const Jet& b) { return *this = *this * b; }
  constexpr Jet& operator/=(const Jet& b) { return *this = *this / b; }
  constexpr Jet& operator+=(const T& s) {
    v += s;
    return *this;
  }
  constexpr Jet& operator-=(const T& s) {
    v -= s;
    return *this;
  }
  constexpr Jet& operator*=(const T& s) {
    v *= s;
    for (int i = 0; i < N; ++i) g[i] *= s;
    for (int k = 0; k < hessian_size; ++k) h[k] *= s;
    return *this;
  }
  constexpr Jet& operator/=(const T& s) { return *this *= T(1) / s; }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  constexpr Jet& operator+=(A s) { return *this += T(s); }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  constexpr Jet& operator-=(A s) { return *this -= T(s); }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  constexpr Jet& operator*=(A s) { return *this *= T(s); }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  constexpr Jet& operator/=(A s) { return *this /= T(s); }

  // -- arithmetic (hidden friends: found by ADL, allow implicit constants) --
  friend constexpr Jet operator+(const Jet& a) { return a; }
  friend constexpr Jet operator-(const Jet& a) {
    Jet r;
    r.v = -a.v;
    for (int i = 0; i < N; ++i) r.g[i] = -a.g[i];
    for (int k = 0; k < hessian_size; ++k) r.h[k] = -a.h[k];
    return r;
  }
  friend constexpr Jet operator+(Jet a, const Jet& b) { return a += b; }
  friend constexpr Jet operator-(Jet a, const Jet& b) { return a -= b; }
  friend constexpr Jet operator+(Jet a, const T& s) { return a += s; }
  friend constexpr Jet operator+(const T& s, Jet a) { return a += s; }
  friend constexpr Jet operator-(Jet a, const T& s) { return a -= s; }
  friend constexpr Jet operator-(const T& s, const Jet& a) {
    Jet r = -a;
    r.v += s;
    return r;
  }
  friend constexpr Jet operator*(Jet a, const T& s) { return a *= s; }
  friend constexpr Jet operator*(const T& s, Jet a) { return a *= s; }
  friend constexpr Jet operator/(Jet a, const T& s) { return a /= s; }
  friend constexpr Jet operator/(const T& s, const Jet& a) { return s * reciprocal(a); }

  /// Product rule to second order:
  /// (ab)_ij = a b_ij + b a_ij + a_i b_j + a_j b_i.
  friend constexpr Jet operator*(const Jet& a, const Jet& b) {
    Jet r;
    r.v = a.v * b.v;
    for (int i = 0; i < N; ++i) r.g[i] = a.v * b.g[i] + b.v * a.g[i];
    if constexpr (Order == 2) {
      int k = 0;
      for (int i = 0; i < N; ++i)
        for (int j = i; j < N; ++j, ++k)
          r.h[k] = a.v * b.h[k] + b.v * a.h[k] + a.g[i] * b.g[j] + a.g[j] * b.g[i];
    }
    return r;
  }
  friend constexpr Jet operator/(const Jet& a, const Jet& b) { return a * reciprocal(b); }

  // -- comparisons act on values (branches in user code) ---------------------
  friend constexpr bool operator==(const Jet& a, const Jet& b) { return a.v == b.v; }
  friend constexpr auto operator<=>(const Jet& a, const Jet& b) { return a.v <=> b.v; }
  friend constexpr bool operator==(const Jet& a, const T& b) { return a.v == b; }
  friend constexpr auto operator<=>(const Jet& a, const T& b) { return a.v <=> b; }

  friend std::ostream& operator<<(std::ostream& os, const Jet& a) { return os << a.v << "[jet]"; }

  /// f(a) given f(a.v), f'(a.v), f''(a.v): the chain rule to second order,
  /// f(a)_ij = f' a_ij + f'' a_i a_j.
  friend constexpr Jet chain(const Jet& a, const T& f0, const T& f1, const T& f2) {
    Jet r;
    r.v = f0;
    for (int i = 0; i < N; ++i) r.g[i] = f1 * a.g[i];
    if constexpr (Order == 2) {
      int k = 0;
      for (int i = 0; i < N; ++i)
        for (int j = i; j < N; ++j, ++k) r.h[k] = f1 * a.h[k] + f2 * a.g[i] * a.g[j];
    }
    return r;
  }

  /// f(a, b) given the value, the partials f_a, f_b and second partials.
  friend constexpr Jet chain2(const Jet& a, const Jet& b, const T& f0, const T& fa, const T& fb, const T& faa,
                              const T& fab, const T& fbb) {
    Jet r;
    r.v = f0;
    for (int i = 0; i < N; ++i) r.g[i] = fa * a.g[i] + fb * b.g[i];
    if constexpr (Order == 2) {
      int k = 0;
      for (int i = 0; i < N; ++i)
        for (int j = i; j < N; ++j, ++k)
          r.h[k] = fa * a.h[k] + fb * b.h[k] + faa * a.g[i] * a.g[j] + fbb * b.g[i] * b.g[j] +
                   fab * (a.g[i] * b.g[j] + a.g[j] * b.g[i]);
    }
    return r;
  }

  friend constexpr Jet reciprocal(const Jet& a) {
    const T r = T(1) / a.v;
    return chain(a, r, -r * r, T(2) * r * r * r);
  }
};

// Arithmetic with plain numbers when T is not itself that number type (nested jets).
#define LAGRANGIAN_AD_MIXED(op)                                                   \
  template <class T, int N, int O, class A>                                       \
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)                    \
  constexpr Jet<T, N, O> operator op(const Jet<T, N, O>& a, A s) {               \
    return a op T(s);                                                             \
  }                                                                               \
  template <class T, int N, int O, class A>                                       \
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)                    \
  constexpr Jet<T, N, O> operator op(A s, const Jet<T, N, O>& a) {               \
    return T(s) op a;                                                             \
  }
LAGRANGIAN_AD_MIXED(+)
LAGRANGIAN_AD_MIXED(-)
LAGRANGIAN_AD_MIXED(*)
LAGRANGIAN_AD_MIXED(/)
#undef LAGRANGIAN_AD_MIXED

template <class T, int N, int O, class A>
  requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
constexpr bool operator==(const Jet<T, N, O>& a, A b) {
  return a.v == T(b);
}
template <class T, int N, int O, class A>
  requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
constexpr auto operator<=>(const Jet<T, N, O>& a, A b) {
  return a.v <=> T(b);
}

// -- EomJet: the number type of the Euler–Lagrange pass ----------------------------

/// Number type for deriving the equations of motion of an N-coordinate
/// system in one pass. With the path direction s, (δq, δt) = (q̇, 1), it
/// carries
///   v = x,  d = ∂x/∂s,  gq = ∂x/∂q,  gv = ∂x/∂q̇,
///   c = ∂²x/∂q̇∂s = (∂²x/∂q̇∂q) q̇ + ∂²x/∂q̇∂t,  H = ∂²x/∂q̇∂q̇ (packed),
/// which for x = L are L, dL/ds, ∂L/∂q, p, the mixed term and M: everything
/// the Euler–Lagrange equations need, and no more (no ∂²/∂q², no ∂²/∂s²).
///
/// A run-time level records which parts can be non-zero:
///   0 — a function of (q, t) only: gv = c = H = 0 (lengths, angles' sines);
///   1 — affine in q̇: H = 0 (velocities of points);
///   2 — general (kinetic energies).
/// Parts above the level are neither stored nor computed, so the O(N²) work
/// on H is spent only where two velocity-dependent factors meet
/// (measurements in docs/performance.md).
template <int N>
class EomJet {
  static_assert(N >= 1, "ad::EomJet needs at least one coordinate");

 public:
  static constexpr int hessian_size = N * (N + 1) / 2;
  using value_type = double;

  int level = 0;
  double v = 0;
  double d = 0;
  std::array<double, N> gq;            // always valid
  std::array<double, N> gv;            // valid when level >= 1
  std::array<double, N> c;         // valid when level >= 1
  std::array<double, hessian_size> H;  // valid when level == 2

  constexpr EomJet() { zero_all(); }
  /// A constant. Implicit, so `S x = 0` and `x * 2` work. (All parts are
  /// zeroed here, once; results of operations write only their valid parts.)
  template <class A>
    requires std::is_arithmetic_v<A>
  constexpr EomJet(A value) : v(static_cast<double>(value)) {
    zero_all();
  }

 private:
  struct Uninitialized {};
  // For results whose every valid part is written by the operation.
  constexpr explicit EomJet(Uninitialized) {}

 public:
  constexpr EomJet(const EomJet& o) { copy_from(o); }
  constexpr EomJet& operator=(const EomJet& o) {
    copy_from(o);
    return *this;
  }

  /// Coordinate q_k with velocity q̇_k (its derivative along the path).
  static constexpr EomJet position(double q, double qd, int k) {
    EomJet r(q);
    r.d = qd;
    r.gq[k] = 1.0;
    return r;
  }
  /// Velocity q̇_k.
  static constexpr EomJet velocity(double qd, int k) {
    EomJet r(qd);
    r.raise(1);
    r.gv[k] = 1.0;
    return r;
  }
  /// Time t (derivative 1 along the path).
  static constexpr EomJet time(double t) {
    EomJet r(t);
    r.d = 1.0;
    return r;
  }

  /// H_ij accessor (symmetric); zero below level 2.
  constexpr double hess(int i, int j) const {
    if (level < 2) return 0.0;
    return i <= j ? H[detail::packed(i, j, N)] : H[detail::packed(j, i, N)];
  }

  /// Raises the level to L, zero-filling the parts that become valid.
  constexpr void raise(int L) {
    if (level < 1 && L >= 1) {
      gv.fill(0.0);
      c.fill(0.0);
    }
    if (level < 2 && L >= 2) H.fill(0.0);
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
    for (int i = 0; i < N; ++i) gq[i] *= s;
    if (level >= 1)
      for (int i = 0; i < N; ++i) {
        gv[i] *= s;
        c[i] *= s;
      }
    if (level == 2)
      for (int k = 0; k < hessian_size; ++k) H[k] *= s;
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
  ///   gv = a gv_b + b gv_a,  c = a c_b + b c_a + gv_a d_b + gv_b d_a,
  ///   H = a H_b + b H_a + gv_a gv_bᵀ + gv_b gv_aᵀ.
  friend constexpr EomJet operator*(const EomJet& a, const EomJet& b) {
    EomJet r{Uninitialized{}};
    r.level = (a.level == 2 || b.level == 2) ? 2 : a.level + b.level;
    r.v = a.v * b.v;
    r.d = a.v * b.d + b.v * a.d;
    for (int i = 0; i < N; ++i) r.gq[i] = a.v * b.gq[i] + b.v * a.gq[i];
    if (a.level >= 1 && b.level >= 1) {
      for (int i = 0; i < N; ++i) {
        r.gv[i] = a.v * b.gv[i] + b.v * a.gv[i];
        r.c[i] = a.v * b.c[i] + b.v * a.c[i] + a.gv[i] * b.d + b.gv[i] * a.d;
      }
    } else if (a.level >= 1) {
      for (int i = 0; i < N; ++i) {
        r.gv[i] = b.v * a.gv[i];
        r.c[i] = b.v * a.c[i] + a.gv[i] * b.d;
      }
    } else if (b.level >= 1) {
      for (int i = 0; i < N; ++i) {
        r.gv[i] = a.v * b.gv[i];
        r.c[i] = a.v * b.c[i] + b.gv[i] * a.d;
      }
    }
    if (r.level == 2) {
      // H from the parts' own Hessians (level-2 factors) ...
      if (a.level == 2 && b.level == 2) {
        for (int k = 0; k < hessian_size; ++k) r.H[k] = a.v * b.H[k] + b.v * a.H[k];
      } else if (a.level == 2) {
        for (int k = 0; k < hessian_size; ++k) r.H[k] = b.v * a.H[k];
      } else if (b.level == 2) {
        for (int k = 0; k < hessian_size; ++k) r.H[k] = a.v * b.H[k];
      }
      // ... plus the outer products of the velocity gradients.
      if (a.level >= 1 && b.level >= 1) {
        const bool fresh = a.level == 1 && b.level == 1;  // H not yet written
        if (&a == &b) {  // a square: gv gvᵀ twice
          add_outer(r.H, a.gv, a.gv, 2.0, fresh);
        } else {
          add_symmetric_outer(r.H, a.gv, b.gv, fresh);
        }
      }
    }
    return r;
  }

  friend constexpr bool operator==(const EomJet& a, const EomJet& b) { return a.v == b.v; }
  friend constexpr auto operator<=>(const EomJet& a, const EomJet& b) { return a.v <=> b.v; }
  friend constexpr bool operator==(const EomJet& a, double b) { return a.v == b; }
  friend constexpr auto operator<=>(const EomJet& a, double b) { return a.v <=> b; }
  friend std::ostream& operator<<(std::ostream& os, const EomJet& a) { return os << a.v << "[eom]"; }

  /// f(a) from f, f', f'': gq = f' gq_a, gv = f' gv_a,
  /// c = f' c_a + f'' gv_a d_a, H = f' H_a + f'' gv_a gv_aᵀ.
  friend constexpr EomJet chain(const EomJet& a, double f0, double f1, double f2) {
    EomJet r{Uninitialized{}};
    r.level = a.level == 0 ? 0 : 2;
    r.v = f0;
    r.d = f1 * a.d;
    for (int i = 0; i < N; ++i) r.gq[i] = f1 * a.gq[i];
    if (a.level >= 1) {
      for (int i = 0; i < N; ++i) {
        r.gv[i] = f1 * a.gv[i];
        r.c[i] = f1 * a.c[i] + f2 * a.gv[i] * a.d;
      }
      if (a.level == 2)
        for (int k = 0; k < hessian_size; ++k) r.H[k] = f1 * a.H[k];
      add_outer(r.H, a.gv, a.gv, f2, a.level == 1);
    }
    return r;
  }

  /// f(a, b) from the value, first and second partials (rare functions:
  /// computed on full parts).
  friend constexpr EomJet chain2(EomJet a, EomJet b, double f0, double fa, double fb, double faa, double fab,
                                 double fbb) {
    const int L = (a.level == 0 && b.level == 0) ? 0 : 2;
    a.raise(L);
    b.raise(L);
    EomJet r{Uninitialized{}};
    r.level = L;
    r.v = f0;
    r.d = fa * a.d + fb * b.d;
    for (int i = 0; i < N; ++i) r.gq[i] = fa * a.gq[i] + fb * b.gq[i];
    if (L == 2) {
      for (int i = 0; i < N; ++i) {
        r.gv[i] = fa * a.gv[i] + fb * b.gv[i];
        r.c[i] = fa * a.c[i] + fb * b.c[i] + faa * a.gv[i] * a.d + fbb * b.gv[i] * b.d +
                 fab * (a.gv[i] * b.d + b.gv[i] * a.d);
      }
      int k = 0;
      for (int i = 0; i < N; ++i)
        for (int j = i; j < N; ++j, ++k)
          r.H[k] = fa * a.H[k] + fb * b.H[k] + faa * a.gv[i] * a.gv[j] + fbb * b.gv[i] * b.gv[j] +
                   fab * (a.gv[i] * b.gv[j] + a.gv[j] * b.gv[i]);
    }
    return r;
  }

  friend constexpr EomJet reciprocal(const EomJet& a) {
    const double r = 1.0 / a.v;
    return chain(a, r, -r * r, 2.0 * r * r * r);
  }

 private:
  constexpr void zero_all() {
    gq.fill(0.0);
    gv.fill(0.0);
    c.fill(0.0);
    H.fill(0.0);
  }
  /// H (+)= f u uᵀ restricted to the upper triangle (assign when `fresh`).
  static constexpr void add_outer(std::array<double, hessian_size>& H, const std::array<double, N>& u,
                                  const std::array<double, N>& w, double f, bool fresh) {
    int k = 0;
    if (fresh) {
      for (int i = 0; i < N; ++i) {
        const double fu = f * u[i];
        for (int j = i; j < N; ++j, ++k) H[k] = fu * w[j];
      }
    } else {
      for (int i = 0; i < N; ++i) {
        const double fu = f * u[i];
        for (int j = i; j < N; ++j, ++k) H[k] += fu * w[j];
      }
    }
  }
  /// H (+)= u wᵀ + w uᵀ, upper triangle.
  static constexpr void add_symmetric_outer(std::array<double, hessian_size>& H, const std::array<double, N>& u,
                                            const std::array<double, N>& w, bool fresh) {
    int k = 0;
    if (fresh) {
      for (int i = 0; i < N; ++i) {
        const double ui = u[i], wi = w[i];
        for (int j = i; j < N; ++j, ++k) H[k] = ui * w[j] + wi * u[j];
      }
    } else {
      for (int i = 0; i < N; ++i) {
        const double ui = u[i], wi = w[i];
        for (int j = i; j < N; ++j, ++k) H[k] += ui * w[j] + wi * u[j];
      }
    }
  }
  /// r = f a + s.
  static constexpr EomJet scaled(const EomJet& a, double f, double s) {
    EomJet r{Uninitialized{}};
    r.level = a.level;
    r.v = f * a.v + s;
    r.d = f * a.d;
    for (int i = 0; i < N; ++i) r.gq[i] = f * a.gq[i];
    if (a.level >= 1)
      for (int i = 0; i < N; ++i) {
        r.gv[i] = f * a.gv[i];
        r.c[i] = f * a.c[i];
      }
    if (a.level == 2)
      for (int k = 0; k < hessian_size; ++k) r.H[k] = f * a.H[k];
    return r;
  }
  /// r = a + sign b, each part written once.
  static constexpr EomJet combined(const EomJet& a, const EomJet& b, double sign) {
    EomJet r{Uninitialized{}};
    r.level = a.level > b.level ? a.level : b.level;
    r.v = a.v + sign * b.v;
    r.d = a.d + sign * b.d;
    for (int i = 0; i < N; ++i) r.gq[i] = a.gq[i] + sign * b.gq[i];
    if (a.level >= 1 && b.level >= 1) {
      for (int i = 0; i < N; ++i) {
        r.gv[i] = a.gv[i] + sign * b.gv[i];
        r.c[i] = a.c[i] + sign * b.c[i];
      }
    } else if (a.level >= 1) {
      r.gv = a.gv;
      r.c = a.c;
    } else if (b.level >= 1) {
      for (int i = 0; i < N; ++i) {
        r.gv[i] = sign * b.gv[i];
        r.c[i] = sign * b.c[i];
      }
    }
    if (a.level == 2 && b.level == 2) {
      for (int k = 0; k < hessian_size; ++k) r.H[k] = a.H[k] + sign * b.H[k];
    } else if (a.level == 2) {
      r.H = a.H;
    } else if (b.level == 2) {
      for (int k = 0; k < hessian_size; ++k) r.H[k] = sign * b.H[k];
    }
    return r;
  }
  constexpr void copy_from(const EomJet& o) {
    level = o.level;
    v = o.v;
    d = o.d;
    gq = o.gq;
    if (level >= 1) {
      gv = o.gv;
      c = o.c;
    }
    if (level == 2) H = o.H;
  }
  constexpr EomJet& accumulate(const EomJet& b, double sign) {
    raise(b.level);
    v += sign * b.v;
    d += sign * b.d;
    for (int i = 0; i < N; ++i) gq[i] += sign * b.gq[i];
    if (b.level >= 1)
      for (int i = 0; i < N; ++i) {
        gv[i] += sign * b.gv[i];
        c[i] += sign * b.c[i];
      }
    if (b.level == 2)
      for (int k = 0; k < hessian_size; ++k) H[k] += sign * b.H[k];
    return *this;
  }
};

// -- <cmath> for AD numbers -------------------------------------------------------
// Each function gives f, f', f'' at the value and lets the number type apply
// the chain rule (`chain`, `chain2`); `using std::sin;` lets the value type be
// double or another Jet.

#define LAGRANGIAN_AD_UNARY(name, f0, f1, f2)      \
  template <ADNumber J>                            \
  constexpr J name(const J& a) {                   \
    using T = typename J::value_type;              \
    using std::sin;                                \
    using std::cos;                                \
    using std::exp;                                \
    using std::log;                                \
    using std::sqrt;                               \
    using std::cosh;                               \
    using std::sinh;                               \
    using std::tan;                                \
    using std::tanh;                               \
    using std::atan;                               \
    using std::asin;                               \
    using std::acos;                               \
    using std::cbrt;                               \
    using std::log1p;                              \
    using std::expm1;                              \
    using std::asinh;                              \
    using std::acosh;                              \
    using std::atanh;                              \
    const T& x = a.v;                              \
    (void)x;                                       \
    return chain(a, f0, f1, f2);                   \
  }

LAGRANGIAN_AD_UNARY(expm1, expm1(x), exp(x), exp(x))
LAGRANGIAN_AD_UNARY(log, log(x), T(1) / x, T(-1) / (x * x))
LAGRANGIAN_AD_UNARY(log1p, log1p(x), T(1) / (T(1) + x), T(-1) / ((T(1) + x) * (T(1) + x)))
LAGRANGIAN_AD_UNARY(log10, log(x) / T(std::log(10.0)), T(1) / (x * T(std::log(10.0))),
                    T(-1) / (x * x * T(std::log(10.0))))
LAGRANGIAN_AD_UNARY(log2, log(x) / T(std::log(2.0)), T(1) / (x * T(std::log(2.0))),
                    T(-1) / (x * x * T(std::log(2.0))))
LAGRANGIAN_AD_UNARY(cbrt, cbrt(x), T(1) / (T(3) * cbrt(x) * cbrt(x)), T(-2) / (T(9) * x * cbrt(x) * cbrt(x)))
LAGRANGIAN_AD_UNARY(asin, asin(x), T(1) / sqrt(T(1) - x * x), x / ((T(1) - x * x) * sqrt(T(1) - x * x)))
LAGRANGIAN_AD_UNARY(acos, acos(x), T(-1) / sqrt(T(1) - x * x), -x / ((T(1) - x * x) * sqrt(T(1) - x * x)))
LAGRANGIAN_AD_UNARY(atan, atan(x), T(1) / (T(1) + x * x), T(-2) * x / ((T(1) + x * x) * (T(1) + x * x)))
LAGRANGIAN_AD_UNARY(sinh, sinh(x), cosh(x), sinh(x))
LAGRANGIAN_AD_UNARY(cosh, cosh(x), sinh(x), cosh(x))
LAGRANGIAN_AD_UNARY(asinh, asinh(x), T(1) / sqrt(x * x + T(1)), -x / ((x * x + T(1)) * sqrt(x * x + T(1))))
LAGRANGIAN_AD_UNARY(acosh, acosh(x), T(1) / sqrt(x * x - T(1)), -x / ((x * x - T(1)) * sqrt(x * x - T(1))))
LAGRANGIAN_AD_UNARY(atanh, atanh(x), T(1) / (T(1) - x * x), T(2) * x / ((T(1) - x * x) * (T(1) - x * x)))
#undef LAGRANGIAN_AD_UNARY

// These evaluate the underlying function once (g++ fuses sin/cos into sincos).
template <ADNumber J>
constexpr J sin(const J& a) {
  using std::cos;
  using std::sin;
  const typename J::value_type s = sin(a.v), c = cos(a.v);
  return chain(a, s, c, -s);
}
template <ADNumber J>
constexpr J cos(const J& a) {
  using std::cos;
  using std::sin;
  const typename J::value_type s = sin(a.v), c = cos(a.v);
  return chain(a, c, -s, -c);
}
template <ADNumber J>
constexpr J exp(const J& a) {
  using std::exp;
  const typename J::value_type e = exp(a.v);
  return chain(a, e, e, e);
}
template <ADNumber J>
constexpr J sqrt(const J& a) {
  using std::sqrt;
  using T = typename J::value_type;
  const T r = sqrt(a.v);
  return chain(a, r, T(0.5) / r, T(-0.25) / (a.v * r));
}
template <ADNumber J>
constexpr J tan(const J& a) {
  using std::tan;
  using T = typename J::value_type;
  const T r = tan(a.v);
  const T sec2 = T(1) + r * r;
  return chain(a, r, sec2, T(2) * r * sec2);
}
template <ADNumber J>
constexpr J tanh(const J& a) {
  using std::tanh;
  using T = typename J::value_type;
  const T r = tanh(a.v);
  const T sech2 = T(1) - r * r;
  return chain(a, r, sech2, T(-2) * r * sech2);
}

/// |a|; the derivative at a = 0 is taken from the right (sign +1).
template <ADNumber J>
constexpr J abs(const J& a) {
  return a.v < typename J::value_type(0) ? -a : a;
}
template <ADNumber J>
constexpr J fabs(const J& a) {
  return abs(a);
}

/// a^p for a constant exponent p: f' = p a^(p-1), f'' = p(p-1) a^(p-2).
/// Integer exponents are exact at a = 0 (x² has derivative 0 there).
template <ADNumber J, class P>
  requires std::is_arithmetic_v<P>
constexpr J pow(const J& a, P p) {
  using std::pow;
  using T = typename J::value_type;
  const T& x = a.v;
  if constexpr (std::is_integral_v<P>) {
    if (p == 0) return J(T(1));
    if (p == 1) return a;
    if (p == 2) return a * a;
    const double pd = static_cast<double>(p);
    const T xm2 = pow(x, static_cast<int>(p - 2));
    return chain(a, xm2 * x * x, T(pd) * xm2 * x, T(pd * (pd - 1.0)) * xm2);
  } else {
    const double pd = static_cast<double>(p);
    return chain(a, pow(x, T(pd)), T(pd) * pow(x, T(pd - 1.0)), T(pd * (pd - 1.0)) * pow(x, T(pd - 2.0)));
  }
}
/// c^b for a constant base: exp(b ln c).
template <ADNumber J, class C>
  requires std::is_arithmetic_v<C>
constexpr J pow(C c, const J& b) {
  using std::log;
  return exp(b * typename J::value_type(log(static_cast<double>(c))));
}
/// a^b, both varying: exp(b ln a); needs a > 0.
template <ADNumber J>
constexpr J pow(const J& a, const J& b) {
  return exp(b * log(a));
}
template <class T, int N, int O>
  requires is_jet_v<T>
constexpr Jet<T, N, O> pow(const Jet<T, N, O>& a, const T& p) {
  return exp(Jet<T, N, O>(p) * log(a));
}

/// atan2(y, x), the angle of the point (x, y).
template <ADNumber J>
constexpr J atan2(const J& y, const J& x) {
  using std::atan2;
  using T = typename J::value_type;
  const T r2 = x.v * x.v + y.v * y.v;
  const T r4 = r2 * r2;
  return chain2(y, x, atan2(y.v, x.v), x.v / r2, -y.v / r2, T(-2) * x.v * y.v / r4, (y.v * y.v - x.v * x.v) / r4,
                T(2) * x.v * y.v / r4);
}
template <ADNumber J, class A>
  requires std::is_arithmetic_v<A>
constexpr J atan2(const J& y, A x) {
  return atan2(y, J(x));
}
template <ADNumber J, class A>
  requires std::is_arithmetic_v<A>
constexpr J atan2(A y, const J& x) {
  return atan2(J(y), x);
}

/// sqrt(a² + b²) without intermediate overflow in the value.
template <ADNumber J>
constexpr J hypot(const J& a, const J& b) {
  using std::hypot;
  using T = typename J::value_type;
  const T r = hypot(a.v, b.v);
  const T r3 = r * r * r;
  return chain2(a, b, r, a.v / r, b.v / r, b.v * b.v / r3, -a.v * b.v / r3, a.v * a.v / r3);
}

template <ADNumber J>
constexpr J max(const J& a, const J& b) {
  return a.v < b.v ? b : a;
}
template <ADNumber J>
constexpr J min(const J& a, const J& b) {
  return b.v < a.v ? b : a;
}
template <ADNumber J>
constexpr J fmax(const J& a, const J& b) {
  return max(a, b);
}
template <ADNumber J>
constexpr J fmin(const J& a, const J& b) {
  return min(a, b);
}

template <ADNumber J>
bool isfinite(const J& a) {
  using std::isfinite;
  return isfinite(a.v);
}
template <ADNumber J>
bool isnan(const J& a) {
  using std::isnan;
  return isnan(a.v);
}

}  // namespace lagrangian::ad

// -- Eigen integration: matrices and vectors of jets ------------------------------
namespace Eigen {
/// Traits shared by the AD number types: Real is the AD type, T its value
/// type, N its number of directions (a cost hint for Eigen).
template <class Real_, class T, int N>
struct LagrangianAdNumTraits : NumTraits<T> {
  using Real = Real_;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1 + N,
    AddCost = 1 + N,
    MulCost = 1 + 3 * N
  };
  static inline Real epsilon() { return Real(NumTraits<T>::epsilon()); }
  static inline Real dummy_precision() { return Real(NumTraits<T>::dummy_precision()); }
  static inline Real highest() { return Real(NumTraits<T>::highest()); }
  static inline Real lowest() { return Real(NumTraits<T>::lowest()); }
  static inline int digits10() { return NumTraits<T>::digits10(); }
};
template <class T, int N, int O>
struct NumTraits<lagrangian::ad::Jet<T, N, O>> : LagrangianAdNumTraits<lagrangian::ad::Jet<T, N, O>, T, N> {};
template <int N>
struct NumTraits<lagrangian::ad::EomJet<N>> : LagrangianAdNumTraits<lagrangian::ad::EomJet<N>, double, N> {};
template <int N, typename BinaryOp>
struct ScalarBinaryOpTraits<lagrangian::ad::EomJet<N>, double, BinaryOp> {
  using ReturnType = lagrangian::ad::EomJet<N>;
};
template <int N, typename BinaryOp>
struct ScalarBinaryOpTraits<double, lagrangian::ad::EomJet<N>, BinaryOp> {
  using ReturnType = lagrangian::ad::EomJet<N>;
};
template <class T, int N, int O, typename BinaryOp>
struct ScalarBinaryOpTraits<lagrangian::ad::Jet<T, N, O>, T, BinaryOp> {
  using ReturnType = lagrangian::ad::Jet<T, N, O>;
};
template <class T, int N, int O, typename BinaryOp>
struct ScalarBinaryOpTraits<T, lagrangian::ad::Jet<T, N, O>, BinaryOp> {
  using ReturnType = lagrangian::ad::Jet<T, N, O>;
};
}  // namespace Eigen
