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

/// Underlying floating-point type of a (possibly nested) Jet, or X itself.
template <class X>
struct scalar_of {
  using type = X;
};
template <class T, int N, int O>
struct scalar_of<Jet<T, N, O>> {
  using type = typename scalar_of<T>::type;
};

/// Plain value of a number: the value part of a Jet, recursively.
template <class X>
constexpr auto value_of(const X& x) {
  if constexpr (is_jet_v<X>) {
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

// -- <cmath> for jets -----------------------------------------------------------
// Each function gives f, f', f'' at the value; `using std::sin;` inside the
// bodies lets T be double or another Jet.

#define LAGRANGIAN_AD_UNARY(name, f0, f1, f2)      \
  template <class T, int N, int O>                 \
  constexpr Jet<T, N, O> name(const Jet<T, N, O>& a) { \
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

LAGRANGIAN_AD_UNARY(sin, sin(x), cos(x), -sin(x))
LAGRANGIAN_AD_UNARY(cos, cos(x), -sin(x), -cos(x))
LAGRANGIAN_AD_UNARY(exp, exp(x), exp(x), exp(x))
LAGRANGIAN_AD_UNARY(expm1, expm1(x), exp(x), exp(x))
LAGRANGIAN_AD_UNARY(log, log(x), T(1) / x, T(-1) / (x * x))
LAGRANGIAN_AD_UNARY(log1p, log1p(x), T(1) / (T(1) + x), T(-1) / ((T(1) + x) * (T(1) + x)))
LAGRANGIAN_AD_UNARY(log10, log(x) / T(std::log(10.0)), T(1) / (x * T(std::log(10.0))),
                    T(-1) / (x * x * T(std::log(10.0))))
LAGRANGIAN_AD_UNARY(log2, log(x) / T(std::log(2.0)), T(1) / (x * T(std::log(2.0))),
                    T(-1) / (x * x * T(std::log(2.0))))
LAGRANGIAN_AD_UNARY(sqrt, sqrt(x), T(0.5) / sqrt(x), T(-0.25) / (x * sqrt(x)))
LAGRANGIAN_AD_UNARY(cbrt, cbrt(x), T(1) / (T(3) * cbrt(x) * cbrt(x)), T(-2) / (T(9) * x * cbrt(x) * cbrt(x)))
LAGRANGIAN_AD_UNARY(tan, tan(x), T(1) + tan(x) * tan(x), T(2) * tan(x) * (T(1) + tan(x) * tan(x)))
LAGRANGIAN_AD_UNARY(asin, asin(x), T(1) / sqrt(T(1) - x * x), x / ((T(1) - x * x) * sqrt(T(1) - x * x)))
LAGRANGIAN_AD_UNARY(acos, acos(x), T(-1) / sqrt(T(1) - x * x), -x / ((T(1) - x * x) * sqrt(T(1) - x * x)))
LAGRANGIAN_AD_UNARY(atan, atan(x), T(1) / (T(1) + x * x), T(-2) * x / ((T(1) + x * x) * (T(1) + x * x)))
LAGRANGIAN_AD_UNARY(sinh, sinh(x), cosh(x), sinh(x))
LAGRANGIAN_AD_UNARY(cosh, cosh(x), sinh(x), cosh(x))
LAGRANGIAN_AD_UNARY(tanh, tanh(x), T(1) - tanh(x) * tanh(x), T(-2) * tanh(x) * (T(1) - tanh(x) * tanh(x)))
LAGRANGIAN_AD_UNARY(asinh, asinh(x), T(1) / sqrt(x * x + T(1)), -x / ((x * x + T(1)) * sqrt(x * x + T(1))))
LAGRANGIAN_AD_UNARY(acosh, acosh(x), T(1) / sqrt(x * x - T(1)), -x / ((x * x - T(1)) * sqrt(x * x - T(1))))
LAGRANGIAN_AD_UNARY(atanh, atanh(x), T(1) / (T(1) - x * x), T(2) * x / ((T(1) - x * x) * (T(1) - x * x)))
#undef LAGRANGIAN_AD_UNARY

/// |a|; the derivative at a = 0 is taken from the right (sign +1).
template <class T, int N, int O>
constexpr Jet<T, N, O> abs(const Jet<T, N, O>& a) {
  return a.v < T(0) ? -a : a;
}
template <class T, int N, int O>
constexpr Jet<T, N, O> fabs(const Jet<T, N, O>& a) {
  return abs(a);
}

/// a^p for a constant exponent p: f' = p a^(p-1), f'' = p(p-1) a^(p-2).
/// Integer exponents are exact at a = 0 (x² has derivative 0 there).
template <class T, int N, int O, class P>
  requires std::is_arithmetic_v<P>
constexpr Jet<T, N, O> pow(const Jet<T, N, O>& a, P p) {
  using std::pow;
  const T& x = a.v;
  if constexpr (std::is_integral_v<P>) {
    if (p == 0) return Jet<T, N, O>(T(1));
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
template <class T, int N, int O, class C>
  requires std::is_arithmetic_v<C>
constexpr Jet<T, N, O> pow(C c, const Jet<T, N, O>& b) {
  using std::log;
  return exp(b * T(log(static_cast<double>(c))));
}
/// a^b, both varying: exp(b ln a); needs a > 0.
template <class T, int N, int O>
constexpr Jet<T, N, O> pow(const Jet<T, N, O>& a, const Jet<T, N, O>& b) {
  return exp(b * log(a));
}
template <class T, int N, int O>
  requires is_jet_v<T>
constexpr Jet<T, N, O> pow(const Jet<T, N, O>& a, const T& p) {
  return exp(Jet<T, N, O>(p) * log(a));
}

/// atan2(y, x), the angle of the point (x, y).
template <class T, int N, int O>
constexpr Jet<T, N, O> atan2(const Jet<T, N, O>& y, const Jet<T, N, O>& x) {
  using std::atan2;
  const T r2 = x.v * x.v + y.v * y.v;
  const T r4 = r2 * r2;
  return chain2(y, x, atan2(y.v, x.v), x.v / r2, -y.v / r2, T(-2) * x.v * y.v / r4,
                (y.v * y.v - x.v * x.v) / r4, T(2) * x.v * y.v / r4);
}
template <class T, int N, int O, class A>
  requires std::is_arithmetic_v<A>
constexpr Jet<T, N, O> atan2(const Jet<T, N, O>& y, A x) {
  return atan2(y, Jet<T, N, O>(x));
}
template <class T, int N, int O, class A>
  requires std::is_arithmetic_v<A>
constexpr Jet<T, N, O> atan2(A y, const Jet<T, N, O>& x) {
  return atan2(Jet<T, N, O>(y), x);
}

/// sqrt(a² + b²) without intermediate overflow in the value.
template <class T, int N, int O>
constexpr Jet<T, N, O> hypot(const Jet<T, N, O>& a, const Jet<T, N, O>& b) {
  using std::hypot;
  const T r = hypot(a.v, b.v);
  const T r3 = r * r * r;
  return chain2(a, b, r, a.v / r, b.v / r, b.v * b.v / r3, -a.v * b.v / r3, a.v * a.v / r3);
}

template <class T, int N, int O>
constexpr Jet<T, N, O> max(const Jet<T, N, O>& a, const Jet<T, N, O>& b) {
  return a.v < b.v ? b : a;
}
template <class T, int N, int O>
constexpr Jet<T, N, O> min(const Jet<T, N, O>& a, const Jet<T, N, O>& b) {
  return b.v < a.v ? b : a;
}
template <class T, int N, int O>
constexpr Jet<T, N, O> fmax(const Jet<T, N, O>& a, const Jet<T, N, O>& b) {
  return max(a, b);
}
template <class T, int N, int O>
constexpr Jet<T, N, O> fmin(const Jet<T, N, O>& a, const Jet<T, N, O>& b) {
  return min(a, b);
}

template <class T, int N, int O>
bool isfinite(const Jet<T, N, O>& a) {
  using std::isfinite;
  return isfinite(a.v);
}
template <class T, int N, int O>
bool isnan(const Jet<T, N, O>& a) {
  using std::isnan;
  return isnan(a.v);
}

}  // namespace lagrangian::ad

// -- Eigen integration: matrices and vectors of jets ------------------------------
namespace Eigen {
template <class T, int N, int O>
struct NumTraits<lagrangian::ad::Jet<T, N, O>> : NumTraits<T> {
  using Real = lagrangian::ad::Jet<T, N, O>;
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
template <class T, int N, int O, typename BinaryOp>
struct ScalarBinaryOpTraits<lagrangian::ad::Jet<T, N, O>, T, BinaryOp> {
  using ReturnType = lagrangian::ad::Jet<T, N, O>;
};
template <class T, int N, int O, typename BinaryOp>
struct ScalarBinaryOpTraits<T, lagrangian::ad::Jet<T, N, O>, BinaryOp> {
  using ReturnType = lagrangian::ad::Jet<T, N, O>;
};
}  // namespace Eigen
