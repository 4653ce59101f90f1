#pragma once
// ad::Jet<T, N, Order>: the truncated Taylor polynomial in N directions,
// first or second order (see ad.hpp).

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

#include "lagrangian/ad/traits.hpp"

namespace lagrangian::ad {

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

}  // namespace lagrangian::ad
